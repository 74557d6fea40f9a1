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

/** \brief `covariate:intensity`: a variance factor and a disparity offset, each a smooth function
  * of the surface's grey level in the colour image (PixelContext::intensity).
  *
  * Physics: the dots a structured-light sensor matches are its projector's light reflected by
  * the surface; a dark print returns a dim pattern, found less precisely (and not at all on the
  * darkest print), and a dim dot's centre may be found off its place. No law is assumed: the log
  * of the factor and the offset are each piecewise linear in the grey level I, with knots at
  * I = 0, 1/4, 1/2 and 3/4 whose values the lab fits, and 0 at white (I = 1), so the paper's
  * polynomial stays the noise of a white surface. Where the grey level is unknown (no colour
  * frames) the factor is 1 and the offset 0. The simulator's scenes have one albedo: it has no
  * generative form.
  */
struct CovariateIntensity
{
  static constexpr const char *kName = "covariate:intensity";
  static constexpr EffectText kText = {"intensity",
                                       "depth variance and bias that change with the surface's grey level (a term built from the data)",
                                       "a dark print returns a dim dot pattern that the sensor matches less precisely and a little off its place; the variance factor's and the disparity offset's shapes over the grey level are fitted, not assumed"};

  static constexpr unsigned kLabNeeds = kNeedsIntensity | kNeedsRepeatedFrames;

  /** \brief The knots' log variance factors, then their disparity offsets (px), at grey levels
    * 0, 1/4, 1/2, 3/4 (both 0 at white). */
  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"log_factor_black", 0.0, 0.1, 0.5},
            {"log_factor_quarter", 0.0, 0.1, 0.5},
            {"log_factor_half", 0.0, 0.1, 0.5},
            {"log_factor_three_quarters", 0.0, 0.1, 0.5},
            {"offset_px_black", 0.0, 0.0, 0.02, -INFINITY, true},
            {"offset_px_quarter", 0.0, 0.0, 0.02, -INFINITY, true},
            {"offset_px_half", 0.0, 0.0, 0.02, -INFINITY, true},
            {"offset_px_three_quarters", 0.0, 0.0, 0.02, -INFINITY, true}};
  }

  /** \brief The piecewise linear function of the grey level \a grey through \a knots at 0, 1/4,
    * 1/2, 3/4 and 0 at white. */
  static PCL_TEXLET_HD double
  atGrey (const double *knots, double grey)
  {
    const double x = 4.0 * (grey < 0.0 ? 0.0 : (grey > 1.0 ? 1.0 : grey));
    const int k = x >= 3.0 ? 3 : static_cast<int> (x);
    const double f = x - k;
    const double right = k == 3 ? 0.0 : knots[k + 1];
    return knots[k] * (1.0 - f) + right * f;
  }

  static PCL_TEXLET_HD double
  varianceFactor (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    return std::isfinite (ctx.intensity) ? std::exp (atGrey (p, ctx.intensity)) : 1.0;
  }

  /** \brief The depth bias of the offset at the grey level, mm (a positive offset: nearer). */
  static PCL_TEXLET_HD double
  bias (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    return std::isfinite (ctx.intensity) ? -depthPerDisparity (ctx) * atGrey (p + 4, ctx.intensity) : 0.0;
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
