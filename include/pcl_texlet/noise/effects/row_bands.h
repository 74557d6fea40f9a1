/*
 * pcl_texlet term `rows`: horizontal bands whose disparity offsets change from frame to frame, a
 * term whose form comes from the data rather than from a law (docs/model_lab.md, "Terms built
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

/** \brief `rows`: the pixels of a row share a disparity offset in each frame (horizontal bands).
  *
  * Physics: no law is assumed; the term is the residual structure `rows` made a model. A sensor
  * whose matcher or read-out works line by line (a rolling read-out, a line-wise correlation of
  * the reference pattern) moves whole rows together. Model: about `bands` bands of rows, each
  * with an offset drawn from N(0, offset_px^2) in every frame, their boundaries falling at random
  * (a Poisson process, bands - 1 per image height); so two rows dv apart share a band with
  * probability exp(-dv / L), L = height / (bands - 1), and a frame's mean offset, the mean of
  * that process over the height, has variance offset_px^2 * 2 (x - 1 + exp(-x)) / x^2 with
  * x = bands - 1. The rows' counterpart of vertical_stripes' columns. The simulator draws no
  * row bands: it has no generative form.
  */
struct RowBands
{
  static constexpr const char *kName = "rows";
  static constexpr EffectText kText = {"row",
                                       "rows that share a disparity offset changing from frame to frame (a term built from the data)",
                                       "the pixels of a row move together in each frame, as a line-wise read-out or matcher would move them; the offsets' SD and the bands' count are fitted"};

  static constexpr bool kScaledByFactors = false; // an offset added after the correlation
  static constexpr unsigned kLabNeeds = kNeedsFrameSplit | kNeedsRepeatedFrames;

  /** \brief The offsets' SD (px) and the number of bands per image height. */
  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"offset_px", 0.0, 0.05, 0.02}, {"bands", 8.0, 8.0, 1.0, 1.0}};
  }

  static PCL_TEXLET_HD double
  rowVariance (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    const double s = p[0] * depthPerDisparity (ctx);
    return s * s;
  }

  static PCL_TEXLET_HD double
  frameVariance (const double *p, const NoSettings &s, const PixelContext &ctx)
  {
    const double x = p[1] - 1.0; // boundaries per image height
    const double share = x > 1e-6 ? 2.0 * (x - 1.0 + exp (-x)) / (x * x) : 1.0;
    return rowVariance (p, s, ctx) * share;
  }

  /** \brief height / (bands - 1): rows apart over which a boundary falls between them about once. */
  static PCL_TEXLET_HD double
  rowCorrelationPx (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    return bandCorrelationPx (p[1], ctx.image_height_px);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
