/*
 * pcl_texlet camera: the intrinsics of a depth image, as a ROS camera_info file holds them (camera.yaml).
 */
#pragma once

#include <pcl_texlet/kernels/structured_light.h>

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief The largest image side the readers accept, pixels: beyond any depth sensor's, so a
  * larger size in a header or camera.yaml is corruption, refused before memory is allocated.
  */
constexpr int kMaxImageSide = 16384;

/** \brief Intrinsics of a depth image, as in a ROS camera_info YAML file (camera.yaml). */
struct CameraInfo
{
  int width = 0;                     ///< image_width, pixels
  int height = 0;                    ///< image_height, pixels
  double K[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};  ///< camera_matrix.data, row-major: fx 0 cx 0 fy cy 0 0 1
  std::string distortion_model = "plumb_bob"; ///< distortion_model
  std::vector<double> D = std::vector<double> (5, 0.0); ///< distortion_coefficients.data (k1 k2 p1 p2 k3)
  double baseline_m = 0.075;         ///< projector-camera baseline in metres (optional key)
  double disparity_subpixel = 0.125; ///< disparity quantisation step in pixels (optional key)

  double fx () const { return K[0]; }
  double fy () const { return K[4]; }
  double cx () const { return K[2]; }
  double cy () const { return K[5]; }
  /** \brief Focal length fx (px) times the baseline (m), the f b of triangulation. */
  double fb () const { return kernels::focalBaseline (fx (), baseline_m); }
};

} // namespace texlet
} // namespace pcl
