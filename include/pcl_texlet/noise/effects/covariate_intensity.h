/*
 * pcl_texlet term `covariate:intensity`: depth noise that changes with the surface's grey level,
 * a term whose form comes from the data rather than from a law (docs/model_lab.md, "Terms built
 * from the data").
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `covariate:intensity`: a variance factor that is a smooth function of the surface's
  * grey level in the colour image (PixelContext::intensity).
  *
  * Physics: the dots a structured-light sensor matches are its projector's light reflected by
  * the surface; a dark print returns a dim pattern, found less precisely (and not at all on the
  * darkest print). No law is assumed: the log of the factor is piecewise linear in the grey
  * level I, with knots at I = 0, 1/4, 1/2 and 3/4 whose values the lab fits, and 0 at white
  * (I = 1), so the paper's polynomial stays the noise of a white surface. Where the grey level is
  * unknown (no colour frames) the factor is 1. The simulator's scenes have one albedo: it has no
  * generative form.
  */
struct CovariateIntensity
{
  static constexpr const char *kName = "covariate:intensity";
  static constexpr EffectText kText = {"intensity",
                                       "depth variance that changes with the surface's grey level (a term built from the data)",
                                       "a dark print returns a dim dot pattern that the sensor matches less precisely; the variance factor's shape over the grey level is fitted, not assumed"};

  static constexpr unsigned kLabNeeds = kNeedsIntensity | kNeedsRepeatedFrames;

  /** \brief The knots' log variance factors, at grey levels 0, 1/4, 1/2, 3/4 (0 at white). */
  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"log_factor_black", 0.0, 0.1, 0.5},
            {"log_factor_quarter", 0.0, 0.1, 0.5},
            {"log_factor_half", 0.0, 0.1, 0.5},
            {"log_factor_three_quarters", 0.0, 0.1, 0.5}};
  }

  static PCL_TEXLET_HD double
  varianceFactor (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    const double grey = ctx.intensity;
    if (!std::isfinite (grey)) // unknown
      return 1.0;
    const double x = 4.0 * (grey < 0.0 ? 0.0 : (grey > 1.0 ? 1.0 : grey));
    const int k = x >= 3.0 ? 3 : static_cast<int> (x);
    const double f = x - k;
    const double right = k == 3 ? 0.0 : p[k + 1];
    return std::exp (p[k] * (1.0 - f) + right * f);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
