/*
 * Explicit instantiations of TexletEstimation and computeTexlet for PCL's depth-camera point
 * types. Other point types: define PCL_NO_PRECOMPILE before including texlet_estimation.h.
 */
#include <pcl_texlet/impl/texlet_estimation.hpp>
#include <pcl_texlet/texlet_estimation.h>

#include <pcl/impl/instantiate.hpp>
#include <pcl/point_types.h>

#define PCL_INSTANTIATE_TexletEstimation(T, OutT) template class PCL_EXPORTS pcl::TexletEstimation<T, OutT>;
#define PCL_INSTANTIATE_computeTexlet(T, OutT)                                                                         \
  template PCL_EXPORTS bool pcl::computeTexlet<T, OutT> (const pcl::PointCloud<T> &, pcl::index_t,                   \
                                                         const pcl::texlet::TexletParameters &,                        \
                                                         const pcl::texlet::CameraModel &,                             \
                                                         const pcl::texlet::NoiseModel &, OutT &);

// clang-format off
PCL_INSTANTIATE_PRODUCT (TexletEstimation, ((pcl::PointXYZ)(pcl::PointXYZRGB)(pcl::PointXYZRGBA)(pcl::PointXYZRGBNormal))((pcl::Texlet)))
PCL_INSTANTIATE_PRODUCT (computeTexlet, ((pcl::PointXYZ)(pcl::PointXYZRGB)(pcl::PointXYZRGBA)(pcl::PointXYZRGBNormal))((pcl::Texlet)))
// clang-format on
