/*
 * Internal: conversions between Eigen vectors (host API) and the kernels' Vec3 (device-ready).
 */
#pragma once

#include <pcl_texlet/kernels/vec3.h>

#include <Eigen/Core>

namespace pcl
{
namespace texlet
{
namespace sim
{

inline kernels::Vec3<double>
toVec3 (const Eigen::Vector3d &v)
{
  return {v.x (), v.y (), v.z ()};
}

inline Eigen::Vector3d
toEigen (const kernels::Vec3<double> &v)
{
  return {v.x, v.y, v.z};
}

} // namespace sim
} // namespace texlet
} // namespace pcl
