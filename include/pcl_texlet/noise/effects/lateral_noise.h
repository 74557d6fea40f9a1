/*
 * pcl_texlet effect `lateral_noise`: depth edges jitter across discontinuities.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `lateral_noise`: depth edges jitter across discontinuities.
  *
  * Physics: the correlation window straddling a depth edge matches either side, so the edge's
  * position in the image jitters by a fraction of a pixel to a pixel (Nguyen et al. 2012 measured
  * about 0.8 px for the Kinect v1). The simulator: each pixel and frame draws an offset from
  * N(0, sigma_px^2) in both image directions, rounded to whole pixels; if the pixel it lands on
  * lies across a depth jump larger than min_jump_m (or on no surface) the reading comes from
  * there (kernels::reportingPixel). Smooth surfaces are unaffected. The term adds a variance
  * sigma_edge^2 exp(-dist^2 / (2 width^2)) at a distance dist (pixels) from the nearest edge.
  */
struct LateralNoise
{
  static constexpr const char *kName = "lateral_noise";
  static constexpr EffectText kText = {"edge distance",
                                       "depth edges jitter across discontinuities",
                                       "the correlation window straddling a depth edge matches either side, so readings near edges jump between the two surfaces"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    double sigma_px = 0.8;    ///< SD of the edge position, pixels
    double min_jump_m = 0.02; ///< smallest depth difference that counts as an edge, metres
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"sigma_px", "px", "SD of the edge position", ParameterRange::NonNegative, &SimParameters::sigma_px},
            {"min_jump_m", "m", "smallest depth difference that counts as an edge", ParameterRange::Positive,
             &SimParameters::min_jump_m}};
  }

  static PCL_TEXLET_HD void
  frameSettings (const SimParameters &p, kernels::SensorFrameSettings &fs)
  {
    fs.lateral_sigma_px = p.sigma_px;
    fs.lateral_min_jump_m = p.min_jump_m;
  }

  // --- the noise model's term ----------------------------------------------------------------

  static constexpr bool kScaledByFactors = false; // the other side of the edge, not correlation noise
  static constexpr unsigned kLabNeeds = kNeedsDepthEdges | kNeedsRepeatedFrames;

  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"sigma_edge_mm", 0.0, 1.0, 1.0}, {"width_px", 1.5, 1.5, 1.0}};
  }

  /** \brief Variance of depth near an edge, mm^2: the jittered correlation window reads the
    * other side of the edge, most often at the edge itself: sigma_edge^2 exp(-dist^2 / (2 width^2)).
    */
  static PCL_TEXLET_HD double
  varianceAt (double sigma_edge_mm, double width_px, double edge_distance_px)
  {
    const double w = width_px > 1e-3 ? width_px : 1e-3;
    const double x = edge_distance_px / w;
    return sigma_edge_mm * sigma_edge_mm * std::exp (-0.5 * x * x);
  }

  static PCL_TEXLET_HD double
  variance (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    if (!std::isfinite (ctx.edge_distance_px))
      return 0.0;
    return varianceAt (p[0], p[1], ctx.edge_distance_px);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
