/*
 * pcl_texlet: depth frames to organised clouds through a camera model (the paper's step 1).
 */
#pragma once

#include <pcl_texlet/camera/camera_model.h>
#include <pcl_texlet/camera/depth_frame.h>

#include <pcl/exceptions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h> // pcl::traits::has_color_v

#include <limits>

namespace pcl
{
namespace texlet
{

/** \brief Back-projects a depth frame (mm, 0 = no reading) into an organised cloud in metres:
  * p = ray(u, v) * z. Pixels without a reading become NaN. Colour is copied when the point
  * type has it and the frame carries RGB.
  * \throws pcl::BadArgumentException if the frame's buffers do not match its size.
  */
template <typename PointT> void
depthToCloud (const DepthFrame &frame, const CameraModel &camera, pcl::PointCloud<PointT> &cloud)
{
  const std::size_t n = static_cast<std::size_t> (frame.width) * frame.height;
  if (frame.width <= 0 || frame.height <= 0 || frame.depth_mm.size () != n ||
      (!frame.rgb.empty () && frame.rgb.size () != 3 * n))
    throw pcl::BadArgumentException ("depthToCloud: frame '" + frame.name + "' has buffers that do not match its size");
  cloud.width = frame.width;
  cloud.height = frame.height;
  cloud.resize (n);
  cloud.is_dense = false;
  const float nan = std::numeric_limits<float>::quiet_NaN ();
  for (int v = 0; v < frame.height; ++v)
    for (int u = 0; u < frame.width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * frame.width + u;
      PointT &p = cloud[i];
      if (frame.depth_mm[i] == 0)
        p.x = p.y = p.z = nan;
      else
      {
        double rx, ry;
        camera.pixelToRay (u, v, rx, ry);
        const double z = frame.depth_mm[i] * 1e-3;
        p.x = static_cast<float> (rx * z);
        p.y = static_cast<float> (ry * z);
        p.z = static_cast<float> (z);
      }
      if constexpr (pcl::traits::has_color_v<PointT>)
      {
        if (!frame.rgb.empty ())
        {
          p.r = frame.rgb[3 * i];
          p.g = frame.rgb[3 * i + 1];
          p.b = frame.rgb[3 * i + 2];
          p.a = 255;
        }
      }
    }
}

} // namespace texlet
} // namespace pcl
