/*
 * pcl_texlet: calibrated pinhole camera with OpenCV / ROS plumb_bob distortion.
 *
 * The fix the paper proposes for OpenNI's back-projection: calibrated intrinsics, the ray
 * through the undistorted pixel, intersected at the measured depth.
 */
#pragma once

#include <pcl_texlet/camera/camera_model.h>
#include <pcl_texlet/kernels/plumb_bob.h>
#include <pcl_texlet/camera/camera_info.h>

namespace pcl
{
namespace texlet
{

/** \brief Calibrated pinhole camera with plumb_bob distortion (camera.yaml's K and D). */
class PinholeModel : public CameraModel
{
public:
  /** \param fx, fy focal lengths, pixels (> 0)
    * \param cx, cy principal point, pixels
    * \param distortion plumb_bob coefficients (k1 k2 p1 p2 k3); zero for an ideal pinhole
    * \throws pcl::BadArgumentException unless fx, fy > 0 and every value finite
    */
  PinholeModel (double fx, double fy, double cx, double cy, const kernels::PlumbBob &distortion = {});

  /** \brief From camera.yaml's K and D. plumb_bob is applied; another distortion model is
    * accepted only with all-zero coefficients.
    * \throws pcl::BadArgumentException for a distortion model this class cannot apply
    */
  static PinholeModel
  fromCameraInfo (const CameraInfo &info);

  /** \brief "pinhole". */
  std::string
  name () const override { return "pinhole"; }

  /** \brief Undistorts the pixel (Newton's method) and returns its ray; NaN where the
    * distortion cannot be inverted (far outside the calibrated field).
    */
  void
  pixelToRay (double u, double v, double &x, double &y) const override;

  /** \brief Distorts the normalised point (X / Z, Y / Z) (plumb_bob) and applies fx, fy, cx, cy. */
  void
  project (double X, double Y, double Z, double &u, double &v) const override;

  /** \brief Distance from the calibrated principal point (cx, cy). */
  double
  principalPointDistance (double u, double v) const override;

  double fx () const { return fx_; }
  double fy () const { return fy_; }
  double cx () const { return cx_; }
  double cy () const { return cy_; }
  const kernels::PlumbBob &distortion () const { return d_; }
  bool hasDistortion () const;

private:
  double fx_, fy_, cx_, cy_;
  kernels::PlumbBob d_;
};

} // namespace texlet
} // namespace pcl
