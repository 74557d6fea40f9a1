/*
 * pcl_texlet: which points of an organised cloud carry a depth reading.
 */
#pragma once

#include <cmath>

namespace pcl
{
namespace texlet
{

/** \brief A point with a depth reading: finite and in front of the camera (z > 0). */
template <typename PointT> inline bool
isValidDepthPoint (const PointT &p)
{
  return std::isfinite (p.x) && std::isfinite (p.y) && std::isfinite (p.z) && p.z > 0.0f;
}

} // namespace texlet
} // namespace pcl
