/*
 * pcl_texlet multi-sensor: texlets of several sensors in one reference frame.
 */
#pragma once

#include <pcl_texlet/features/point_types.h>

#include <pcl/point_cloud.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Moves a texlet by the rigid transform \a pose: P' = R P + t, N' = R N,
  * Sigma_P' = R Sigma_P R^T, and Sigma_N re-expressed in the tangent frame of N' (which is a
  * fixed function of N', not the rotated old frame): Sigma_N' = M Sigma_N M^T with
  * M = T(N')^T R T(N). Texlets that failed (support 0 or NaN) are copied unchanged.
  */
void
transformTexlet (const pcl::Texlet &in, const Eigen::Isometry3d &pose, pcl::Texlet &out);

/** \brief transformTexlet on every texlet of \a in; \a out keeps the organisation. */
void
transformTexlets (const pcl::PointCloud<pcl::Texlet> &in, const Eigen::Isometry3d &pose,
                  pcl::PointCloud<pcl::Texlet> &out);

/** \brief Texlets of several sensors in one frame, each with the sensor it came from. */
struct MergedTexlets
{
  pcl::PointCloud<pcl::Texlet> texlets; ///< valid texlets only, unorganised (height 1), dense
  std::vector<std::uint16_t> sensor;    ///< index of the source sensor, one per texlet
  std::size_t dropped = 0;              ///< failed texlets (support 0 or non-finite) left out

  /** \brief Appends the valid texlets of \a cloud (in sensor \a sensor_index's camera frame),
    * moved into the reference frame by \a pose (reference from camera).
    */
  void
  add (const pcl::PointCloud<pcl::Texlet> &cloud, const Eigen::Isometry3d &pose, std::uint16_t sensor_index);

  /** \brief Number of texlets from sensor \a sensor_index. */
  std::size_t
  countFrom (std::uint16_t sensor_index) const;
};

/** \brief Whether \a t is a texlet that was computed (support > 0, finite centre and normal). */
bool
isValidTexlet (const pcl::Texlet &t);

} // namespace texlet
} // namespace pcl
