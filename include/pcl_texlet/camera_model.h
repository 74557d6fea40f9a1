/*
 * pcl_texlet: camera models, how depth pixels relate to rays.
 *
 * TexletEstimation and the apps use a camera model through this interface: to place a pixel
 * relative to the principal point (the noise model's r) and to turn a depth pixel into a
 * 3D point. Depth z is measured along the optical axis, so a point is ray(u, v) * z.
 */
#pragma once

#include <memory>
#include <string>

namespace pcl
{
namespace texlet
{

class CameraModel
{
public:
  using Ptr = std::shared_ptr<CameraModel>;
  using ConstPtr = std::shared_ptr<const CameraModel>;

  virtual ~CameraModel () = default;

  virtual std::string
  name () const = 0;

  /** \brief Ray through pixel (u, v) with z = 1: the point at depth z is (x z, y z, z). */
  virtual void
  pixelToRay (double u, double v, double &x, double &y) const = 0;

  /** \brief Distance of pixel (u, v) from the principal point, pixels. */
  virtual double
  principalPointDistance (double u, double v) const = 0;
};

/** \brief Ideal pinhole: focal lengths and principal point in pixels, no distortion. */
class PinholeCamera : public CameraModel
{
public:
  /** \throws pcl::BadArgumentException unless fx, fy > 0 and all values finite. */
  PinholeCamera (double fx, double fy, double cx, double cy);

  std::string
  name () const override { return "pinhole"; }

  void
  pixelToRay (double u, double v, double &x, double &y) const override
  {
    x = (u - cx_) / fx_;
    y = (v - cy_) / fy_;
  }

  double
  principalPointDistance (double u, double v) const override;

  double fx () const { return fx_; }
  double fy () const { return fy_; }
  double cx () const { return cx_; }
  double cy () const { return cy_; }

private:
  double fx_, fy_, cx_, cy_;
};

} // namespace texlet
} // namespace pcl
