/*
 * pcl_texlet: OpenNI's simplified back-projection (the paper's Eq. 1 to 3), kept so that users
 * can reproduce its flaws on purpose and measure them.
 *
 *   x = x_norm tan(hFOV/2) z,   x_norm = 2 (u / r_x - 0.5)
 *   y = y_norm tan(vFOV/2) z,   y_norm = 2 (v / r_y - 0.5)
 *
 * y_norm has the paper's magnitude with its sign turned to PCL's camera frame (y down; Eq. 3
 * as printed has y up, OpenNI's world convention). The flaws: the principal point is taken at
 * (r_x/2, r_y/2) whatever the calibration says, there is no distortion, and after registration
 * to the RGB camera the IR camera's field of view is still used (kinectIr() on registered depth).
 */
#pragma once

#include <pcl_texlet/camera/camera_model.h>

namespace pcl
{
namespace texlet
{

/** \brief OpenNI's field-of-view back-projection (above): the camera model of an OpenNI grabber's
  * point clouds, with its flaws.
  */
class OpenNIFovModel : public CameraModel
{
public:
  /** \param width, height resolution r_x, r_y, pixels (> 0)
    * \param hfov, vfov horizontal and vertical field of view, radians, in (0, pi)
    * \throws pcl::BadArgumentException otherwise
    */
  OpenNIFovModel (int width, int height, double hfov, double vfov);

  /** \brief Kinect v1 IR camera as OpenNI's PS1080 driver reports it: focal length
    * ZPD / (2 ZPPS) = 120 mm / (2 x 0.1052 mm) = 570.3 px at VGA, i.e. 58.6 x 45.6 degrees.
    * Applied to depth registered to the RGB camera, this is the registered-depth flaw.
    */
  static OpenNIFovModel
  kinectIr (int width = 640, int height = 480);

  /** \brief Kinect v1 RGB camera's field of view (525 px at VGA: 62.7 x 49.1 degrees): the
    * paper's first fix for registered depth, still without principal point or distortion.
    */
  static OpenNIFovModel
  kinectRgb (int width = 640, int height = 480);

  /** \brief "openni_fov". */
  std::string
  name () const override { return "openni_fov"; }

  /** \brief The paper's Eq. 1 to 3: x = 2 (u / r_x - 0.5) tan (hFOV / 2), likewise y (y down). */
  void
  pixelToRay (double u, double v, double &x, double &y) const override;

  /** \brief The inverse of pixelToRay: u = r_x (0.5 + X / (2 Z tan (hFOV / 2))), likewise v. */
  void
  project (double X, double Y, double Z, double &u, double &v) const override;

  /** \brief Distance from the image centre (r_x / 2, r_y / 2), where this model puts the
    * principal point.
    */
  double
  principalPointDistance (double u, double v) const override;

  int width () const { return width_; }
  int height () const { return height_; }
  double hfov () const { return hfov_; }
  double vfov () const { return vfov_; }

  /** \brief The pinhole focal lengths this model amounts to: r_x / (2 tan(hFOV/2)), likewise y. */
  double equivalentFx () const;
  double equivalentFy () const;

private:
  int width_, height_;
  double hfov_, vfov_;
  double tan_h_, tan_v_;
};

} // namespace texlet
} // namespace pcl
