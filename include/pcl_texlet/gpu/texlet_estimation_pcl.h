/*
 * pcl_texlet GPU: the PCL side of pcl::texlet::gpu::TexletEstimation (needs PCL and libpcl_texlet).
 *
 * Host pcl::PointCloud in, pcl::PointCloud<pcl::Texlet> out; the library's CameraModel and
 * NoiseModel turned into the device's PODs. DeviceTexlet has pcl::Texlet's layout (checked
 * below), so downloads go straight into the cloud's memory.
 */
#pragma once

#include <pcl_texlet/camera/camera_estimation.h>
#include <pcl_texlet/camera/camera_model.h>
#include <pcl_texlet/gpu/texlet_estimation.h>
#include <pcl_texlet/noise/noise_model.h>
#include <pcl_texlet/features/point_types.h>
#include <pcl_texlet/camera/valid_point.h>

#include <pcl/exceptions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h> // pcl::traits::has_color_v

#include <cstddef>
#include <cstring>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace gpu
{

#define PCL_TEXLET_SAME_OFFSET(a, b) \
  static_assert (offsetof (pcl::Texlet, a) == offsetof (DeviceTexlet, b), "DeviceTexlet::" #b " is not at pcl::Texlet::" #a)
PCL_TEXLET_SAME_OFFSET (x, x);
PCL_TEXLET_SAME_OFFSET (y, y);
PCL_TEXLET_SAME_OFFSET (z, z);
PCL_TEXLET_SAME_OFFSET (normal_x, normal_x);
PCL_TEXLET_SAME_OFFSET (normal_y, normal_y);
PCL_TEXLET_SAME_OFFSET (normal_z, normal_z);
PCL_TEXLET_SAME_OFFSET (rgba, rgba);
PCL_TEXLET_SAME_OFFSET (curvature, curvature);
PCL_TEXLET_SAME_OFFSET (radius, radius);
PCL_TEXLET_SAME_OFFSET (support, support);
PCL_TEXLET_SAME_OFFSET (cov_p_xx, cov_p_xx);
PCL_TEXLET_SAME_OFFSET (cov_p_xy, cov_p_xy);
PCL_TEXLET_SAME_OFFSET (cov_p_xz, cov_p_xz);
PCL_TEXLET_SAME_OFFSET (cov_p_yy, cov_p_yy);
PCL_TEXLET_SAME_OFFSET (cov_p_yz, cov_p_yz);
PCL_TEXLET_SAME_OFFSET (cov_p_zz, cov_p_zz);
PCL_TEXLET_SAME_OFFSET (cov_n_11, cov_n_11);
PCL_TEXLET_SAME_OFFSET (cov_n_12, cov_n_12);
PCL_TEXLET_SAME_OFFSET (cov_n_22, cov_n_22);
PCL_TEXLET_SAME_OFFSET (pixel_index, pixel_index);
#undef PCL_TEXLET_SAME_OFFSET
static_assert (sizeof (pcl::Texlet) == sizeof (DeviceTexlet), "DeviceTexlet and pcl::Texlet differ in size");
static_assert (alignof (pcl::Texlet) == alignof (DeviceTexlet), "DeviceTexlet and pcl::Texlet differ in alignment");

/** \brief The device form of a PinholeModel or OpenNIFovModel.
  * \throws pcl::BadArgumentException for another kind of camera model
  */
DeviceCamera
toDeviceCamera (const texlet::CameraModel &camera);

/** \brief The device form of a noise model made of PolynomialSigmaTerms (at most
  * DeviceNoise::kMaxTerms). \throws pcl::BadArgumentException naming a term the device lacks
  */
DeviceNoise
toDeviceNoise (const texlet::NoiseModel &noise);

/** \brief An organised cloud as device points on the host: x, y, z and, when the type has
  * colour, PCL's rgba. \throws pcl::UnorganizedPointCloudException for an unorganised cloud
  */
template <typename PointT> void
toDevicePoints (const pcl::PointCloud<PointT> &cloud, std::vector<DevicePoint> &points)
{
  if (cloud.height <= 1 || static_cast<std::size_t> (cloud.width) * cloud.height != cloud.size ())
    throw pcl::UnorganizedPointCloudException ("pcl::texlet::gpu::TexletEstimation: the input cloud is not organised; "
                                               "texlets need the pixel grid of a depth image");
  points.resize (cloud.size ());
  for (std::size_t i = 0; i < cloud.size (); ++i)
  {
    const PointT &p = cloud[i];
    points[i].x = p.x;
    points[i].y = p.y;
    points[i].z = p.z;
    if constexpr (pcl::traits::has_color_v<PointT>)
      points[i].rgba = p.rgba;
    else
      points[i].rgba = 0;
  }
}

/** \brief Uploads an organised cloud (see toDevicePoints). */
template <typename PointT> void
uploadCloud (const pcl::PointCloud<PointT> &cloud, DeviceArray2D<DevicePoint> &device)
{
  std::vector<DevicePoint> host;
  toDevicePoints (cloud, host);
  device.upload (host, static_cast<int> (cloud.width));
}

/** \brief Downloads device texlets into a cloud (one row; is_dense when all were made). */
inline void
downloadTexlets (const DeviceArray<DeviceTexlet> &device, pcl::PointCloud<pcl::Texlet> &cloud)
{
  cloud.resize (device.size ());
  cloud.width = static_cast<std::uint32_t> (device.size ());
  cloud.height = 1;
  device.download (reinterpret_cast<DeviceTexlet *> (cloud.data ()));
  bool dense = true;
  for (const pcl::Texlet &t : cloud)
    dense = dense && t.support > 0;
  cloud.is_dense = dense;
}

template <typename PointT> void
TexletEstimation::compute (const pcl::PointCloud<PointT> &cloud, pcl::PointCloud<pcl::Texlet> &output)
{
  DeviceArray2D<DevicePoint> device;
  uploadCloud (cloud, device);
  if (!has_camera_)
    setCamera (toDeviceCamera (texlet::estimatePinholeModel (cloud)));
  const bool colour = colour_;
  colour_ = pcl::traits::has_color_v<PointT>;
  DeviceArray<DeviceTexlet> texlets;
  try
  {
    compute (device, texlets);
  }
  catch (...)
  {
    colour_ = colour;
    throw;
  }
  colour_ = colour;
  downloadTexlets (texlets, output);
}

} // namespace gpu
} // namespace texlet
} // namespace pcl
