/*
 * pcl_texlet kernels: structured-light triangulation (Kinect v1 class sensors).
 *
 * The sensor matches the projected dot pattern in its IR image; the shift of a dot against the
 * reference is the disparity d (pixels) and depth follows by triangulation, z = f b / d, with f
 * the IR camera's focal length (pixels) and b the projector-camera baseline (metres). Noise and
 * quantisation happen in disparity, which is why depth noise grows with z^2 and depth steps
 * with z^2 / (f b).
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <cmath>
#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief The product f b that triangulation divides by: focal length \a fx_px (pixels) times
  * baseline \a baseline_m (metres). Every f b of the project comes from here.
  */
PCL_TEXLET_HD constexpr double
focalBaseline (double fx_px, double baseline_m)
{
  return fx_px * baseline_m;
}

/** \brief Disparity in pixels of depth \a z_m (metres): f b / z. \a fb = f (px) * b (m). */
PCL_TEXLET_HD double
disparityFromDepth (double z_m, double fb)
{
  return fb / z_m;
}

/** \brief Depth in metres of disparity \a d_px: f b / d. */
PCL_TEXLET_HD double
depthFromDisparity (double d_px, double fb)
{
  return fb / d_px;
}

/** \brief Disparity SD (px) equivalent to a depth SD \a sigma_z_m at depth \a z_m: first-order
  * propagation through d = f b / z, |dd/dz| = f b / z^2.
  */
PCL_TEXLET_HD double
disparitySigmaFromDepthSigma (double sigma_z_m, double z_m, double fb)
{
  return sigma_z_m * fb / (z_m * z_m);
}

/** \brief Depth SD (m) of a disparity SD \a sigma_d_px at depth \a z_m: sigma_d z^2 / (f b). */
PCL_TEXLET_HD double
depthSigmaFromDisparitySigma (double sigma_d_px, double z_m, double fb)
{
  return sigma_d_px * z_m * z_m / fb;
}

/** \brief Disparity rounded to the nearest multiple of \a step_px (the sensor reports integer
  * multiples of a sub-pixel step: 1/8 px on the Kinect v1).
  */
PCL_TEXLET_HD double
quantiseDisparity (double d_px, double step_px)
{
  return step_px * std::floor (d_px / step_px + 0.5);
}

/** \brief Depth change per pixel of disparity at depth \a z_mm, mm/px: z^2 / (f b). Through it a
  * disparity offset delta (px) moves the depth by -J delta and a disparity SD s becomes J s.
  */
PCL_TEXLET_HD double
depthPerDisparityMm (double z_mm, double fb_px_m)
{
  return z_mm * z_mm / (1000.0 * fb_px_m);
}

/** \brief Irradiance of a projector at a surface point relative to the sensor's own projector,
  * capped at \a cap: (cos_j / r_j^2) / (cos_own / r_own^2). Cosines are of the angle between
  * the surface normal and the direction to the projector; zero when cos_j <= 0. Summed over the
  * other active projectors it is the foreign load that interference grows with.
  */
PCL_TEXLET_HD double
relativeIrradiance (double cos_j, double r_j, double cos_own, double r_own, double cap = 4.0)
{
  if (!(cos_j > 0))
    return 0.0;
  if (!(cos_own > 0))
    return cap;
  const double w = (cos_j / (r_j * r_j)) / (cos_own / (r_own * r_own));
  return w < cap ? w : cap;
}

/** \brief Depth step (m) between neighbouring quantised disparities at depth \a z_m:
  * z^2 step / (f b) to first order.
  */
PCL_TEXLET_HD double
depthStep (double z_m, double step_px, double fb)
{
  return z_m * z_m * step_px / fb;
}

/** \brief The depth the sensor reports for disparity \a d_px: f b / d rounded to whole
  * millimetres, 0 (no reading) for a non-positive disparity or a depth outside
  * [min_depth_m, max_depth_m]. max_depth_m must not exceed 65.535 m (16-bit millimetres).
  */
PCL_TEXLET_HD std::uint16_t
reportedDepthMm (double d_px, double fb, double min_depth_m, double max_depth_m)
{
  if (!(d_px > 0))
    return 0;
  const double z = fb / d_px;
  if (z < min_depth_m || z > max_depth_m)
    return 0;
  return static_cast<std::uint16_t> (std::floor (z * 1000.0 + 0.5));
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
