/*
 * pcl_texlet term `spatial_correlation`: neighbouring pixels' noise shared over a window, as the
 * matcher's correlation window shares it, a term whose form comes from the data rather than from
 * a law (docs/model_lab.md, "Terms built from the data").
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `spatial_correlation`: a share of each pixel's own noise is the mean of white noise
  * over a window of window_px x window_px pixels around it.
  *
  * Physics: a structured-light sensor finds a pixel's disparity by correlating a window of the
  * speckle image with the reference pattern; neighbours whose windows overlap see the same
  * speckles and err alike. Model: two pixels du, dv apart correlate by
  * share * tri(du) * tri(dv), tri(d) = max(0, 1 - |d| / window_px) (the overlap of their windows);
  * a pixel's variance is unchanged, so per-pixel moments cannot see the term: the lab fits it to
  * the residuals' correlation between neighbours, and the texlets' covariances use it
  * (docs/texlet_covariances.md). The simulator draws no window: it has no generative form.
  */
struct SpatialCorrelation
{
  static constexpr const char *kName = "spatial_correlation";
  static constexpr EffectText kText = {"neighbour",
                                       "neighbouring pixels share their noise over a window (a term built from the data)",
                                       "the matcher correlates a window of the speckle image, so pixels whose windows overlap err alike; the share and the window's width are fitted"};

  static constexpr bool kScaledByFactors = false;
  static constexpr unsigned kLabNeeds = kNeedsRepeatedFrames | kNeedsNeighbourCorrelation;

  /** \brief The share of a pixel's own variance that is correlated, and the window's width (px). */
  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"share", 0.0, 0.5, 0.5}, {"window_px", 1.0, 5.0, 5.0}};
  }

  static PCL_TEXLET_HD double
  windowShare (const double *p, const NoSettings &, const PixelContext &)
  {
    return p[0] > 0.0 ? (p[0] < 1.0 ? p[0] : 1.0) : 0.0;
  }

  static PCL_TEXLET_HD double
  windowPx (const double *p, const NoSettings &, const PixelContext &)
  {
    return p[1] > 1.0 ? p[1] : 1.0;
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
