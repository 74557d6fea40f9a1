/*
 * pcl_texlet simulator: a structured-light depth sensor (Kinect v1 class) placed in a scene.
 *
 * The sensor is an IR camera (ideal pinhole) and a dot projector a baseline away along the
 * camera's +x axis, both looking along the camera's +z axis. Camera frame: x right, y down,
 * z forward (OpenCV/ROS). The pose maps camera coordinates into the scene frame.
 */
#pragma once

#include <pcl_texlet/kernels/structured_light.h>

#include <Eigen/Geometry>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief Geometry and intrinsics of one sensor. */
struct DepthSensor
{
  int width = 640;          ///< image width, pixels
  int height = 480;         ///< image height, pixels
  double fx = 580.0;        ///< focal length along x, pixels (Kinect v1 IR camera at VGA)
  double fy = 580.0;        ///< focal length along y, pixels
  double cx = 319.5;        ///< principal point x, pixels
  double cy = 239.5;        ///< principal point y, pixels
  double baseline_m = 0.075; ///< projector-camera distance along the camera's x axis, metres
  double min_depth_m = 0.5;  ///< readings closer than this are dropped (Kinect v1: about 0.5 m)
  double max_depth_m = 8.0;  ///< readings farther than this are dropped (at most 65.535 m)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity (); ///< scene from camera
  bool projector_active = true; ///< whether its projector lights the scene (interference)

  /** \brief A Kinect v1 at \a width x \a height: f = 580 px at 640 columns, scaled with the
    * width (290 px at QVGA), principal point at the image centre ((w - 1) / 2, (h - 1) / 2).
    */
  static DepthSensor
  kinect (int width = 640, int height = 480);

  /** \brief Product of the focal length fx (px) and the baseline (m) that triangulation uses. */
  double
  fb () const { return kernels::focalBaseline (fx, baseline_m); }

  /** \brief Position of the camera's centre in the scene. */
  Eigen::Vector3d
  cameraPosition () const { return pose.translation (); }

  /** \brief Position of the projector in the scene: baseline_m along the camera's x axis. */
  Eigen::Vector3d
  projectorPosition () const { return pose * Eigen::Vector3d (baseline_m, 0.0, 0.0); }

  /** \brief Checks sizes, intrinsics, depth range and pose.
    * \throws pcl::BadArgumentException naming the offending value.
    */
  void
  validate () const;
};

} // namespace sim
} // namespace texlet
} // namespace pcl
