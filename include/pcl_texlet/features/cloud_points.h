/*
 * pcl_texlet: an organised pcl::PointCloud as the points of a frame of the texlet stages
 * (kernels/texlet_stages.h, kernels/pixel_disc.h): size, points by pixel and by index, which
 * have a depth reading, and colour (and its grey level) where the point type has one.
 */
#pragma once

#include <pcl_texlet/camera/valid_point.h>
#include <pcl_texlet/noise/pixel_context.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h> // pcl::traits::has_color_v

#include <cstddef>
#include <limits>

namespace pcl
{
namespace texlet
{
namespace detail
{

template <typename PointT>
class CloudPoints
{
public:
  explicit CloudPoints (const pcl::PointCloud<PointT> &cloud)
    : points_ (cloud.points.data ()), width_ (static_cast<int> (cloud.width)), height_ (static_cast<int> (cloud.height))
  {
  }

  int
  width () const { return width_; }
  int
  height () const { return height_; }

  const PointT &
  point (int u, int v) const { return points_[static_cast<std::size_t> (v) * width_ + u]; }
  const PointT &
  point (std::ptrdiff_t index) const { return points_[index]; }

  static bool
  valid (const PointT &p) { return isValidDepthPoint (p); }

  static constexpr bool
  hasColour () { return pcl::traits::has_color_v<PointT>; }

  /** \brief Adds the colour of pixel \a index to the sums (points with colour only). */
  void
  addColour ([[maybe_unused]] int index, [[maybe_unused]] unsigned &r, [[maybe_unused]] unsigned &g,
             [[maybe_unused]] unsigned &b) const
  {
    if constexpr (pcl::traits::has_color_v<PointT>)
    {
      const PointT &p = points_[index];
      r += p.r;
      g += p.g;
      b += p.b;
    }
  }

  /** \brief Grey level of point \a p (greyLevel), NaN for a point type without colour. */
  static double
  intensity ([[maybe_unused]] const PointT &p)
  {
    if constexpr (pcl::traits::has_color_v<PointT>)
      return greyLevel (p.r, p.g, p.b);
    else
      return std::numeric_limits<double>::quiet_NaN ();
  }

private:
  const PointT *points_;
  int width_, height_;
};

} // namespace detail
} // namespace texlet
} // namespace pcl
