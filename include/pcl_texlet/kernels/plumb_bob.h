/*
 * pcl_texlet kernels: the OpenCV / ROS "plumb_bob" lens distortion (k1 k2 p1 p2 k3).
 *
 * Normalised image coordinates (x, y) = (X/Z, Y/Z) are distorted to
 *   xd = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
 *   yd = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y,   r^2 = x^2 + y^2,
 * and the pixel is (fx xd + cx, fy yd + cy). Back-projection inverts the distortion by
 * Newton's method on this 2D map, which converges in a few steps for real lenses and, unlike
 * OpenCV's fixed-point iteration, to full precision.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace kernels
{

struct PlumbBob
{
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
};

/** \brief Distorts normalised coordinates; optionally returns the Jacobian d(xd, yd)/d(x, y). */
PCL_TEXLET_HD void
distortPlumbBob (const PlumbBob &d, double x, double y, double &xd, double &yd, double *jacobian = nullptr)
{
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  xd = x * radial + 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x);
  yd = y * radial + d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y;
  if (jacobian)
  {
    const double dradial = d.k1 + r2 * (2 * d.k2 + 3 * d.k3 * r2); // d radial / d r2
    jacobian[0] = radial + 2 * x * x * dradial + 2 * d.p1 * y + 6 * d.p2 * x; // dxd/dx
    jacobian[1] = 2 * x * y * dradial + 2 * d.p1 * x + 2 * d.p2 * y;          // dxd/dy
    jacobian[2] = 2 * x * y * dradial + 2 * d.p1 * x + 2 * d.p2 * y;          // dyd/dx
    jacobian[3] = radial + 2 * y * y * dradial + 6 * d.p1 * y + 2 * d.p2 * x; // dyd/dy
  }
}

/** \brief Inverts distortPlumbBob: the normalised (x, y) whose distortion is (xd, yd).
  * \return false if Newton's method did not converge (a distortion that folds over).
  */
PCL_TEXLET_HD bool
undistortPlumbBob (const PlumbBob &d, double xd, double yd, double &x, double &y)
{
  x = xd;
  y = yd;
  for (int it = 0; it < 30; ++it)
  {
    double fx, fy, J[4];
    distortPlumbBob (d, x, y, fx, fy, J);
    const double ex = fx - xd, ey = fy - yd;
    if (ex * ex + ey * ey < 1e-28)
      return true;
    const double det = J[0] * J[3] - J[1] * J[2];
    if (!(std::fabs (det) > 1e-12))
      return false;
    x -= (J[3] * ex - J[1] * ey) / det;
    y -= (-J[2] * ex + J[0] * ey) / det;
  }
  double fx, fy;
  distortPlumbBob (d, x, y, fx, fy);
  return (fx - xd) * (fx - xd) + (fy - yd) * (fy - yd) < 1e-20;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
