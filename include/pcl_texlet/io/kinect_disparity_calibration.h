/*
 * pcl_texlet io: the depth calibration of a Kinect's raw 11-bit disparity, z = 1 / (c0 + c1 d),
 * with the depth camera's intrinsics, from an OpenCV FileStorage YAML file such as the one
 * Herrera's Kinect calibration toolbox writes (docs/inputs.md, "Raw Kinect disparity folder").
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief The raw disparity value a Kinect gives where it has no reading (0x7FF). */
constexpr std::uint16_t kKinectNoDisparity = 2047;

/** \brief How raw Kinect disparity d becomes depth: z = 1 / (c0 + c1 d') metres (Herrera,
  * Kannala and Heikkilä, "Joint depth and color camera calibration with distortion correction",
  * TPAMI 2012), where d' = d + beta(u, v) exp(alpha0 - alpha1 d) is d corrected for the
  * spatially varying distortion when beta is given, else d itself.
  */
struct KinectDisparityCalibration
{
  CameraInfo info;  ///< the depth camera; width and height 0 when the file does not give them
  double c0 = 0.0;  ///< 1/m
  double c1 = 0.0;  ///< 1/m per disparity unit (negative for a Kinect: about -0.003)
  double alpha[2] = {0.0, 0.0};     ///< dc_alpha: the decay of the distortion with disparity
  std::vector<double> beta;          ///< dc_beta, row-major height x width; empty: no correction
  int beta_width = 0;                ///< dc_beta's cols
  int beta_height = 0;               ///< dc_beta's rows

  /** \brief The depth in millimetres, rounded, of raw disparity \a d at pixel (\a u, \a v); 0
    * (no reading) for d >= kKinectNoDisparity, and where the depth is not positive and finite
    * or does not fit 16 bits (65535 mm).
    */
  std::uint16_t
  depthMm (std::uint16_t d, int u, int v) const;
};

/** \brief Load a Kinect depth calibration from an OpenCV FileStorage YAML file (a first line
  * "%YAML:1.0" and "!!opencv-matrix" maps of rows, cols, dt and data are accepted, as are plain
  * YAML lists). The keys, each under one of the names given (two names of one quantity are an
  * error):
  * - camera matrix, 3x3, required: dK (Herrera's toolbox), depth_intrinsics, camera_matrix or K;
  * - distortion, 4 or 5 numbers (k1 k2 p1 p2 [k3]; more only when those are 0), optional: dkc,
  *   depth_distortion, distortion_coefficients or D; none is no distortion;
  * - c0 and c1, required: dc = [c0 c1] (1x2, Herrera's order: z = 1 / (dc(2) d + dc(1))),
  *   depth_calibration = [c0 c1], or scalars c0 and c1;
  * - dc_alpha (1x2) and dc_beta (height x width), optional, Herrera's disparity distortion;
  * - image_width and image_height, optional: the size every frame must have;
  * - baseline_m, optional: the projector-camera baseline (default CameraInfo's 0.075 m).
  *
  * info.disparity_subpixel is set to fx baseline |c1|, the step in pixels one unit of raw
  * disparity is, so that the disparity lattice of the depths is the one the calibration implies.
  * Other keys (the toolbox's colour camera and extrinsics) are ignored.
  * \throws pcl::IOException naming the file and the problem: missing file, not YAML, a missing
  *         or malformed key, two names of one quantity, c1 zero or c0, c1 not finite, focal
  *         lengths not positive.
  */
KinectDisparityCalibration
loadKinectDisparityCalibration (const std::string &path);

} // namespace texlet
} // namespace pcl
