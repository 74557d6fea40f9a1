/*
 * pcl_texlet kernels: the physical effects of DESIGN.md section 5 as terms of the depth noise
 * model (mean and variance of a depth sample), the closed forms the model lab fits.
 *
 * The simulator (sensor_effects.h) draws the effects in disparity; these are their moments in
 * depth. Through z = f b / d a disparity offset delta (px) moves the depth by -J delta and a
 * disparity SD s (px) becomes a depth SD J s, with J = z^2 / (f b) the depth per pixel of
 * disparity (mm/px for z in mm: J = z_mm^2 / (1000 f b)).
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

/** \brief Depth change per pixel of disparity at depth \a z_mm, mm/px: z^2 / (f b). */
PCL_TEXLET_HD double
depthPerDisparityMm (double z_mm, double fb_px_m)
{
  return z_mm * z_mm / (1000.0 * fb_px_m);
}

/** \brief Factor on the depth variance of the `radial` effect: (1 + gain (r / r_ref)^2)^2. */
PCL_TEXLET_HD double
radialVarianceFactor (double gain, double r_px, double reference_radius_px)
{
  const double x = r_px / reference_radius_px;
  const double f = 1.0 + gain * x * x;
  return f > 0.0 ? f * f : 0.0;
}

/** \brief Factor on the depth variance of the `incidence_angle` effect:
  * (1 + gain (1 / cos(theta) - 1))^2; cos(theta) is clamped to 0.05 (87 degrees).
  */
PCL_TEXLET_HD double
incidenceVarianceFactor (double gain, double cos_theta)
{
  const double c = cos_theta > 0.05 ? cos_theta : 0.05;
  const double f = 1.0 + gain * (1.0 / c - 1.0);
  return f > 0.0 ? f * f : 0.0;
}

/** \brief Factor on the depth variance of the `interference` effect, 1 + gain (P - 1) for P
  * active projectors: each other projector adds a foreign load of about one (a wall lit by
  * sensors standing side by side), and the simulator multiplies the variance by 1 + gain load.
  */
PCL_TEXLET_HD double
interferenceVarianceFactor (double gain, double active_projectors)
{
  const double others = active_projectors > 1.0 ? active_projectors - 1.0 : 0.0;
  const double f = 1.0 + gain * others;
  return f > 0.0 ? f : 0.0;
}

/** \brief Disparity offset of warm-up drift at frame \a frame, px: A exp(-frame / tau). */
PCL_TEXLET_HD double
driftDisparityOffset (double amplitude_px, double time_constant_frames, double frame)
{
  const double tau = time_constant_frames > 1e-3 ? time_constant_frames : 1e-3;
  return amplitude_px * std::exp (-frame / tau);
}

/** \brief Variance of depth near an edge (`lateral_noise`), mm^2: the jittered correlation
  * window reads the other side of the edge, most often at the edge itself:
  * sigma_edge^2 exp(-dist^2 / (2 width^2)).
  */
PCL_TEXLET_HD double
lateralVariance (double sigma_edge_mm, double width_px, double edge_distance_px)
{
  const double w = width_px > 1e-3 ? width_px : 1e-3;
  const double x = edge_distance_px / w;
  return sigma_edge_mm * sigma_edge_mm * std::exp (-0.5 * x * x);
}

/** \brief Weights of the four nodes of a nodes_x x nodes_y grid (row-major) spanning the image
  * [0, width - 1] x [0, height - 1] that bilinear interpolation at pixel (u, v) uses: their
  * indices and weights; outside the image, those of the border.
  */
PCL_TEXLET_HD void
bilinearGridWeights (int nodes_x, int nodes_y, double width, double height, double u, double v, int index[4],
                     double weight[4])
{
  double gx = (nodes_x - 1) * u / (width - 1.0), gy = (nodes_y - 1) * v / (height - 1.0);
  gx = gx < 0 ? 0 : (gx > nodes_x - 1 ? nodes_x - 1 : gx);
  gy = gy < 0 ? 0 : (gy > nodes_y - 1 ? nodes_y - 1 : gy);
  int ix = static_cast<int> (gx), iy = static_cast<int> (gy);
  ix = ix > nodes_x - 2 ? nodes_x - 2 : ix;
  iy = iy > nodes_y - 2 ? nodes_y - 2 : iy;
  const double fx = gx - ix, fy = gy - iy;
  index[0] = iy * nodes_x + ix;
  index[1] = index[0] + 1;
  index[2] = index[0] + nodes_x;
  index[3] = index[2] + 1;
  weight[0] = (1 - fy) * (1 - fx);
  weight[1] = (1 - fy) * fx;
  weight[2] = fy * (1 - fx);
  weight[3] = fy * fx;
}

/** \brief Bilinear interpolation of a nodes_x x nodes_y grid (row-major) spanning the image
  * [0, width - 1] x [0, height - 1] at pixel (u, v); outside, the border value.
  */
PCL_TEXLET_HD double
bilinearGrid (const double *nodes, int nodes_x, int nodes_y, double width, double height, double u, double v)
{
  int index[4];
  double weight[4];
  bilinearGridWeights (nodes_x, nodes_y, width, height, u, v, index, weight);
  return weight[0] * nodes[index[0]] + weight[1] * nodes[index[1]] + weight[2] * nodes[index[2]] +
         weight[3] * nodes[index[3]];
}

/** \brief quantizedMoments by summing the levels within 7 SDs of \a d0 (the 2.6e-12 of the
  * probability beyond is up to 1e-10 of the variance; the cost grows with sigma / step: one erf
  * per level). For sigma below step / 2.
  */
PCL_TEXLET_HD void
quantizedMomentsByLevels (double d0, double sigma, double step, double &mean_offset, double &variance)
{
  const double lo = std::floor ((d0 - 7.0 * sigma) / step + 0.5), hi = std::floor ((d0 + 7.0 * sigma) / step + 0.5);
  const double inv = 1.0 / (sigma * 1.4142135623730951);
  double s0 = 0, s1 = 0, s2 = 0;
  // Neighbouring levels share a boundary: one erf per boundary.
  double erf_below = std::erf (((lo - 0.5) * step - d0) * inv);
  for (double k = lo; k <= hi; k += 1.0)
  {
    // P(level k) = P(d in [(k - 1/2) step, (k + 1/2) step)).
    const double erf_above = std::erf (((k + 0.5) * step - d0) * inv);
    const double p = 0.5 * (erf_above - erf_below);
    erf_below = erf_above;
    const double x = k * step - d0;
    s0 += p;
    s1 += p * x;
    s2 += p * x * x;
  }
  mean_offset = s1 / s0;
  variance = s2 / s0 - mean_offset * mean_offset;
  if (variance < 0)
    variance = 0;
}

/** \brief quantizedMoments through the Fourier series of the rounding error (for sigma of step / 2
  * and more, where three harmonics reach double precision).
  *
  * The rounding error e(x) = step round(x / step) - x is a sawtooth of period step:
  * e = sum_k (-1)^k step / (pi k) sin(k theta(x)), e^2 = step^2 / 12 + sum_k (-1)^k step^2 / (pi k)^2
  * cos(k theta(x)), theta = 2 pi x / step. Over x ~ N(d0, sigma^2) each harmonic is damped by
  * g_k = exp(-2 pi^2 k^2 sigma^2 / step^2), and Cov(x, e) = sum_k (-1)^k 2 sigma^2 g_k cos(k theta(d0)).
  * So the mean offset is E e, and Var(x + e) = sigma^2 + 2 Cov(x, e) + E e^2 - (E e)^2: Sheppard's
  * sigma^2 + step^2 / 12 plus harmonics that die off as g_1 <= exp(-pi^2 / 2) = 0.0072, with
  * g_3 <= 5e-20. One exp, one sin and one cos instead of an erf per level (the levels' sum was most of the
  * model lab's fitting time when the model quantises).
  */
PCL_TEXLET_HD void
quantizedMomentsByHarmonics (double d0, double sigma, double step, double &mean_offset, double &variance)
{
  const double kPi = 3.14159265358979323846;
  // The phase of d0 within its step, in [-1/2, 1/2]: the harmonics' arguments stay small.
  const double u = d0 / step;
  const double theta = 2.0 * kPi * (u - std::floor (u + 0.5));
  const double r = 2.0 * kPi * kPi * sigma * sigma / (step * step);
  const double s1 = std::sin (theta), c1 = std::cos (theta);
  double mean = 0, square = step * step / 12.0, cov = 0;
  double sk = 0, ck = 1; // sin(k theta), cos(k theta) by the angle-addition recurrence
  double sign = -1;      // (-1)^k
  // g_k = g_1^(k^2) by products (g_k = g_(k-1) g_1^(2k-1)): one exp, and none in its slow
  // underflow path (for r beyond 700 every harmonic is below the smallest double anyway).
  const double g1 = r < 700.0 ? std::exp (-r) : 0.0;
  double g = 1, odd_power = g1;
  for (int k = 1; k <= 3; ++k, sign = -sign)
  {
    g *= odd_power;
    odd_power *= g1 * g1;
    if (!(g > 0))
      break; // this harmonic and all after it are gone (also for an infinite sigma)
    const double next_s = sk * c1 + ck * s1, next_c = ck * c1 - sk * s1;
    sk = next_s;
    ck = next_c;
    mean += sign * step / (kPi * k) * g * sk;
    square += sign * step * step / (kPi * kPi * k * k) * g * ck;
    cov += sign * 2.0 * sigma * sigma * g * ck;
  }
  mean_offset = mean;
  variance = sigma * sigma + 2.0 * cov + square - mean * mean;
  if (variance < 0)
    variance = 0;
}

/** \brief Mean offset and variance (px) of a disparity N(d0, sigma^2) rounded to multiples of
  * \a step (the sensor's sub-pixel steps).
  *
  * Why: when the noise is smaller than a step the reported disparity sticks to the nearest
  * level, so the SD swings with the sub-step phase of d0 (small on a level, up to step / 2
  * between two) and the mean follows a staircase; with more noise both tend to Sheppard's
  * sigma^2 + step^2 / 12 and no bias. Below step / 2 the levels are summed
  * (quantizedMomentsByLevels), from there on the series converges in three harmonics
  * (quantizedMomentsByHarmonics); the two agree to about 1e-10 where both apply.
  */
PCL_TEXLET_HD void
quantizedMoments (double d0, double sigma, double step, double &mean_offset, double &variance)
{
  if (!(step > 0))
  {
    mean_offset = 0.0;
    variance = sigma * sigma;
    return;
  }
  if (!(std::fabs (d0 / step) < 4.5e15))
  {
    // No level can be told apart (or d0 is not finite): nothing to say.
    mean_offset = variance = NAN;
    return;
  }
  if (!(sigma > 1e-6 * step))
  {
    const double level = step * std::floor (d0 / step + 0.5);
    mean_offset = level - d0;
    variance = 0.0;
    return;
  }
  if (sigma < 0.5 * step)
    quantizedMomentsByLevels (d0, sigma, step, mean_offset, variance);
  else
    quantizedMomentsByHarmonics (d0, sigma, step, mean_offset, variance);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
