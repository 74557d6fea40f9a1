/*
 * pcl_texlet GPU tests: comparing relation statistics of the CUDA backend with the CPU path.
 *
 * A relation whose angle lies within rounding of a bin edge may land one bin over on the GPU
 * (acosf against acos). The tests count those borderline relations on the host and allow each
 * of them to move one count between two bins.
 */
#pragma once

#include <pcl_texlet/kernels/relation_histogram.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_texlet_test
{

/** Directed relations whose angle lies within \a tol_deg of an angle bin edge or a box's
  * angle edge (both directions of a pair share the angle, so pairs count twice).
  */
inline std::uint64_t
borderlineRelations (const pcl::texlet::kernels::RelationInput<float> &in,
                     const pcl::texlet::kernels::RelationConfig &config, double tol_deg = 1e-4)
{
  namespace kn = pcl::texlet::kernels;
  // (0 and 180 degrees are no edges: relationBin puts them in the first and the last bin.)
  std::vector<double> edges;
  for (int b = 1; b < config.axes.angle_bins; ++b)
    edges.push_back (b * (180.0 / config.axes.angle_bins));
  for (int b = 0; b < config.box_count; ++b)
  {
    edges.push_back (config.boxes[b].angle_deg - config.boxes[b].angle_tol_deg);
    edges.push_back (config.boxes[b].angle_deg + config.boxes[b].angle_tol_deg);
  }
  std::uint64_t n = 0;
  for (int i = 0; i < in.count; ++i)
    for (int j = i + 1; j < in.count; ++j)
    {
      const double a = kn::texletRelation (in.centre[i], in.normal[i], in.centre[j], in.normal[j]).angle_deg;
      for (const double e : edges)
        if (std::fabs (a - e) <= tol_deg)
        {
          n += 2;
          break;
        }
    }
  return n;
}

/** Sum over bins of |a - b|. */
inline std::uint64_t
absoluteDifference (const std::vector<std::uint64_t> &a, const std::vector<std::uint64_t> &b)
{
  std::uint64_t d = 0;
  for (std::size_t k = 0; k < a.size (); ++k)
    d += a[k] > b[k] ? a[k] - b[k] : b[k] - a[k];
  return d;
}

} // namespace pcl_texlet_test
