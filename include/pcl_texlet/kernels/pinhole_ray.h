/*
 * pcl_texlet kernels: the viewing ray through a pixel of a pinhole camera with plumb_bob
 * distortion, for the host's camera models and the GPU's back-projection alike.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/plumb_bob.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Whether \a d distorts at all (any coefficient non-zero). */
PCL_TEXLET_HD bool
hasDistortion (const PlumbBob &d)
{
  return d.k1 != 0 || d.k2 != 0 || d.p1 != 0 || d.p2 != 0 || d.k3 != 0;
}

/** \brief Ray (x, y, 1) through pixel (u, v) of the pinhole (fx, fy, cx, cy) with distortion
  * \a d; NaN where the distortion cannot be inverted.
  */
PCL_TEXLET_HD void
pinholeRay (double fx, double fy, double cx, double cy, const PlumbBob &d, double u, double v, double &x, double &y)
{
  const double xd = (u - cx) / fx, yd = (v - cy) / fy;
  if (!hasDistortion (d))
  {
    x = xd;
    y = yd;
    return;
  }
  if (!undistortPlumbBob (d, xd, yd, x, y))
    x = y = NAN;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
