/*
 * pcl_texlet: camera models, how depth pixels relate to rays.
 *
 * TexletEstimation, the simulator and the apps use a camera model through this interface: to
 * turn a depth pixel into a 3D point, to project a point into the image, and to place a pixel
 * relative to the principal point (the noise model's r). Depth z is measured along the optical
 * axis, so the point of pixel (u, v) at depth z is (x z, y z, z) with (x, y) = pixelToRay(u, v).
 * The camera frame is PCL's: x right, y down, z forward.
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

  /** \brief Pixel (u, v) of the point (X, Y, Z), Z > 0. */
  virtual void
  project (double X, double Y, double Z, double &u, double &v) const = 0;

  /** \brief Distance of pixel (u, v) from the principal point, pixels. */
  virtual double
  principalPointDistance (double u, double v) const = 0;
};

} // namespace texlet
} // namespace pcl
