/*
 * pcl_texlet effect `disparity_quantization`: the sensor reports disparity in sub-pixel steps.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `disparity_quantization`: the sensor reports disparity in sub-pixel steps.
  *
  * Physics: the Kinect v1 reports disparity as an integer count of 1/8 pixel, so depth comes in
  * steps of z^2 step_px / (f b) (about 2.9 mm at 1 m, 11.5 mm at 2 m for f = 580 px,
  * b = 7.5 cm). The paper (Fig. 7) notes that much of the measured noise is of this size.
  * The simulator rounds the noisy disparity; the step is also written to the recording's
  * camera.yaml as disparity_subpixel. The term gives the moments of the rounded disparity at
  * the true depth's sub-step phase (step^2 / 12 where the phase is unknown).
  */
struct DisparityQuantization
{
  static constexpr const char *kName = "disparity_quantization";
  static constexpr EffectText kText = {"phase",
                                       "disparity in sub-pixel steps: depth steps of z^2 step / (f b)",
                                       "the sensor reports disparity in sub-pixel steps (1/8 px on the Kinect v1): depth comes in steps of z^2 step / (f b), so SD and mean swing with the true disparity's sub-step phase"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    double step_px = 0.125; ///< disparity step, pixels
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"step_px", "px", "disparity step (camera.yaml disparity_subpixel)", ParameterRange::Positive,
             &SimParameters::step_px}};
  }

  static PCL_TEXLET_HD void
  frameSettings (const SimParameters &p, kernels::SensorFrameSettings &fs)
  {
    fs.quantisation_step_px = p.step_px;
  }

  /** \brief The step is the sensor's: camera.yaml carries it whether or not the frames are rounded. */
  static void
  labelCamera (const SimParameters &p, bool /*enabled*/, CameraLabel &label)
  {
    label.disparity_step_px = p.step_px;
  }

  // --- the noise model's term ----------------------------------------------------------------

  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"step_px", 0.0, SimParameters ().step_px, 0.05}};
  }

  struct TermSettings
  {
    double lattice_phase = 0.0;  ///< the levels sit at (k + lattice_phase) step_px
    /** 0: the noisy disparity is rounded; 1: the true one, the noise comes after; 2: both, the
      * true one on the first lattice (first_step_px), the noisy one on the term's. */
    int rounds_before_noise = 0;
    double first_step_px = 0.0; ///< form 2's first lattice's step (levels at k first_step_px); 0: the term's step_px
  };

  static std::vector<Field<TermSettings>>
  termSettings ()
  {
    return {{"lattice_phase", "steps", "the levels sit at (k + lattice_phase) step_px: the phase of the depth lattice",
             ParameterRange::Any, &TermSettings::lattice_phase},
            {"rounds_before_noise", "1",
             "0: the noisy disparity is rounded (SD and mean swing with the phase); 1: the true disparity is "
             "rounded and the noise added after (the mean is a staircase, the SD is the noise's); 2: both, the true "
             "disparity on a first lattice (first_step_px) and the noisy one on the term's",
             ParameterRange::NonNegative, &TermSettings::rounds_before_noise},
            {"first_step_px", "px",
             "rounds_before_noise 2's first lattice: the true disparity's levels sit at k first_step_px (camera.yaml's "
             "step), the noisy one's on the term's own lattice; 0: the term's step",
             ParameterRange::NonNegative, &TermSettings::first_step_px}};
  }

  /** \brief What is wrong with \a s, or "" when nothing. */
  static std::string
  settingsProblem (const TermSettings &s)
  {
    return s.rounds_before_noise >= 0 && s.rounds_before_noise <= 2
               ? ""
               : "rounds_before_noise must be 0 (the noisy disparity is rounded), 1 (the true one) or 2 (both, on "
                 "two lattices), got " +
                     std::to_string (s.rounds_before_noise);
  }

  /** \brief Where the rounding happens is for the data to say: a sensor rounds what it
    * measured, but a pipeline (or a simulator) may round the true disparity and add noise after,
    * or do both on two lattices (a published Kinect simulator: camera.yaml's before its noise,
    * the sensor's own depth table after it).
    */
  static std::vector<std::pair<std::string, std::vector<double>>>
  formSearch ()
  {
    return {{"rounds_before_noise", {0, 1, 2}}};
  }

  /** \brief The lab starts from the lattice the recordings' depths sit on where it found one
    * that camera.yaml does not imply (a real Kinect's, section "The disparity lattice" of
    * docs/model_lab.md), else from the recording's own step (camera.yaml).
    */
  static void
  labStart (const LabStart &facts, double *p, TermSettings &s)
  {
    // Form 2's first lattice: camera.yaml's where the depths sit on one of their own; else the
    // term's (one lattice, rounded before and after the noise).
    s.first_step_px = 0.0;
    if (facts.lattice_step_px > 0)
    {
      p[0] = facts.lattice_step_px;
      s.lattice_phase = facts.lattice_phase;
      s.first_step_px = facts.disparity_step_px > 0 ? facts.disparity_step_px : SimParameters ().step_px;
      return;
    }
    p[0] = facts.disparity_step_px > 0 ? facts.disparity_step_px : SimParameters ().step_px;
    s.lattice_phase = 0.0;
  }

  /** \brief Rounding is applied last, to the bias and independent variance of the other terms. */
  static PCL_TEXLET_HD void
  transformMoments (const double *p, const TermSettings &s, const PixelContext &ctx, double &bias_mm,
                    double &variance_mm2)
  {
    const double step = std::fabs (p[0]);
    if (!(step > 0))
      return;
    const double J = depthPerDisparity (ctx);
    if (!(J > 0))
      return;
    if (!(std::isfinite (ctx.true_depth_mm) && ctx.true_depth_mm > 0))
    {
      // The phase of a measured (already quantised) depth says nothing: the variance from frame
      // to frame averaged over the phases. Rounded before the noise, a pixel's level is the same
      // in every frame: a bias, no noise.
      if (s.rounds_before_noise != 1)
        variance_mm2 = J * J * varianceOverPhases (std::sqrt (variance_mm2) / J, step);
      return;
    }
    // The disparity before rounding: the true one moved by the other terms' bias.
    const double d0 = ctx.fb_px_m * 1000.0 / ctx.true_depth_mm - bias_mm / J;
    double mean_offset = 0, var_px = 0;
    roundingMoments (p, s, d0, std::sqrt (variance_mm2) / J, mean_offset, var_px);
    bias_mm -= J * mean_offset;
    variance_mm2 = J * J * var_px;
  }

  /** \brief Mean offset and variance (px) of a disparity N(\a d0, \a sigma^2) after the term's
    * rounding: the model lab evaluates it per pixel, at each pixel's own sub-step phase.
    */
  static PCL_TEXLET_HD void
  roundingMoments (const double *p, const TermSettings &s, double d0, double sigma, double &mean_offset,
                   double &variance)
  {
    const double step = std::fabs (p[0]);
    if (s.rounds_before_noise == 1)
    {
      // The true disparity's level: a fixed offset; the noise after it keeps its own variance.
      moments (d0 - s.lattice_phase * step, 0.0, step, mean_offset, variance);
      variance = sigma * sigma;
      return;
    }
    if (s.rounds_before_noise == 2)
    {
      // The true disparity's level on the first lattice, then the noisy one rounded on the term's.
      const double first = s.first_step_px > 0 ? s.first_step_px : step;
      double level_offset = 0, unused = 0;
      moments (d0, 0.0, first, level_offset, unused);
      moments (d0 + level_offset - s.lattice_phase * step, sigma, step, mean_offset, variance);
      mean_offset += level_offset;
      return;
    }
    moments (d0 - s.lattice_phase * step, sigma, step, mean_offset, variance);
  }

  // --- the moments of a rounded Gaussian -----------------------------------------------------

  /** \brief The variance of N(d0, \a sigma^2) rounded to multiples of \a step, averaged over a
    * uniform phase of d0 within a step: sigma^2 + step^2 / 12 less the phase average of the
    * squared mean offset, step^2 / (2 pi^2) sum_k exp (-a k^2) / k^2 with a = 4 pi^2 sigma^2 / step^2.
    *
    * Why: it is what a pixel's readings scatter by from frame to frame where its phase is unknown
    * (a measured depth's, a texlet's points'): Sheppard's sigma^2 + step^2 / 12 where the noise
    * spans a step, but sqrt(1 / pi) step sigma where it is far below one (only pixels near a
    * level's edge flicker). The sum for a of 0.05 and more (29 terms at most); below, its
    * Poisson-summed form pi^2 / 6 - sqrt (pi a) + a / 2 (what it leaves out is below 1e-80).
    */
  static PCL_TEXLET_HD double
  varianceOverPhases (double sigma, double step)
  {
    if (!(step > 0))
      return sigma * sigma;
    const double kPi = 3.14159265358979323846;
    const double r = 2.0 * kPi * kPi * sigma * sigma / (step * step), a = 2.0 * r;
    double lost = 0;
    if (a < 0.05)
      lost = kPi * kPi / 6.0 - std::sqrt (kPi * a) + 0.5 * a;
    else
      for (int k = 1; k <= 64; ++k)
      {
        const double g2 = std::exp (-2.0 * r * k * k);
        if (g2 < 1e-18)
          break;
        lost += g2 / (double (k) * k);
      }
    const double v = sigma * sigma + step * step / 12.0 - step * step * lost / (2.0 * kPi * kPi);
    return v > 0 ? v : 0.0;
  }

  /** \brief moments () by summing the levels within 7 SDs of \a d0 (the 2.6e-12 of the
    * probability beyond is up to 1e-10 of the variance; the cost grows with sigma / step: one
    * erf per level). For sigma below step / 2.
    */
  static PCL_TEXLET_HD void
  momentsByLevels (double d0, double sigma, double step, double &mean_offset, double &variance)
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

  /** \brief moments () through the Fourier series of the rounding error (for sigma of step / 2
    * and more, where three harmonics reach double precision).
    *
    * The rounding error e(x) = step round(x / step) - x is a sawtooth of period step:
    * e = sum_k (-1)^k step / (pi k) sin(k theta(x)), e^2 = step^2 / 12 + sum_k (-1)^k step^2 / (pi k)^2
    * cos(k theta(x)), theta = 2 pi x / step. Over x ~ N(d0, sigma^2) each harmonic is damped by
    * g_k = exp(-2 pi^2 k^2 sigma^2 / step^2), and Cov(x, e) = sum_k (-1)^k 2 sigma^2 g_k cos(k theta(d0)).
    * So the mean offset is E e, and Var(x + e) = sigma^2 + 2 Cov(x, e) + E e^2 - (E e)^2: Sheppard's
    * sigma^2 + step^2 / 12 plus harmonics that die off as g_1 <= exp(-pi^2 / 2) = 0.0072, with
    * g_3 <= 5e-20. One exp, one sin and one cos instead of an erf per level.
    */
  static PCL_TEXLET_HD void
  momentsByHarmonics (double d0, double sigma, double step, double &mean_offset, double &variance)
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
    * sigma^2 + step^2 / 12 and no bias. Below step / 2 the levels are summed (momentsByLevels),
    * from there on the series converges in three harmonics (momentsByHarmonics); the two agree
    * to about 1e-10 where both apply.
    */
  static PCL_TEXLET_HD void
  moments (double d0, double sigma, double step, double &mean_offset, double &variance)
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
      momentsByLevels (d0, sigma, step, mean_offset, variance);
    else
      momentsByHarmonics (d0, sigma, step, mean_offset, variance);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
