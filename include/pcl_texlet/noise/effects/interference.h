/*
 * pcl_texlet effect `interference`: other sensors' projected patterns add noise and holes.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `interference`: other sensors' projected patterns add noise and holes.
  *
  * Physics: where another active projector lights the surface, its dots overlay the sensor's
  * own pattern and confuse the correlation (the paper's Sect. 4, Fig. 12). The foreign load L
  * at a surface point is the sum over other active projectors of their irradiance relative to
  * the sensor's own projector, (cos theta_j / r_j^2) / (cos theta_own / r_own^2), capped at 4
  * per projector (kernels::relativeIrradiance; zero where the other projector does not see the
  * point). The disparity SD is multiplied by sqrt(1 + noise_gain L) and the reading is lost with
  * probability 1 - exp(-dropout_rate L) per frame, decided per blob_px x blob_px block of pixels
  * since holes come in clumps. The term sees only the number P of active projectors: each other
  * one adds a load of about one (a wall lit by sensors standing side by side), so the variance
  * is multiplied by 1 + noise_gain (P - 1).
  */
struct Interference
{
  static constexpr const char *kName = "interference";
  static constexpr EffectText kText = {"projectors",
                                       "other active projectors add noise and holes where they overlap",
                                       "other sensors' projected dots overlay the sensor's own pattern and confuse the correlation: more noise (and holes) with every other active projector"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    double noise_gain = 1.0;   ///< variance added per unit of foreign load, relative
    double dropout_rate = 0.1; ///< hole rate per unit of foreign load
    int blob_px = 4;           ///< side of the blocks in which holes appear, pixels
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"noise_gain", "1", "variance added per unit of foreign load, relative", ParameterRange::NonNegative,
             &SimParameters::noise_gain},
            {"dropout_rate", "1", "hole rate per unit of foreign load: p = 1 - exp(-rate L)",
             ParameterRange::NonNegative, &SimParameters::dropout_rate},
            {"blob_px", "px", "side of the blocks in which holes appear", ParameterRange::PositiveInteger,
             &SimParameters::blob_px}};
  }

  /** \brief The simulator computes the foreign load (ray casts to every other projector) only
    * for effects that read it.
    */
  static constexpr bool kNeedsForeignLoad = true;

  /** \brief Factor on the disparity SD for a foreign projector load \a load. */
  static PCL_TEXLET_HD double
  factor (const SimParameters &p, double load)
  {
    return std::sqrt (1.0 + p.noise_gain * load);
  }

  /** \brief Probability per frame that a pixel under foreign load \a load has no reading. */
  static PCL_TEXLET_HD double
  dropoutAt (const SimParameters &p, double load)
  {
    return 1.0 - std::exp (-p.dropout_rate * load);
  }

  static PCL_TEXLET_HD double
  sdFactor (const SimParameters &p, const SimPixel &px)
  {
    return factor (p, px.foreign_load);
  }

  static PCL_TEXLET_HD double
  dropout (const SimParameters &p, const SimPixel &px)
  {
    return dropoutAt (p, px.foreign_load);
  }

  static PCL_TEXLET_HD void
  frameSettings (const SimParameters &p, kernels::SensorFrameSettings &fs)
  {
    fs.dropout_blob_px = p.blob_px;
  }

  // --- the noise model's term ----------------------------------------------------------------

  static constexpr unsigned kLabNeeds = kNeedsVariedProjectors | kNeedsRepeatedFrames;

  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"noise_gain", 0.0, 0.1, 0.1}};
  }

  /** \brief Factor on the depth variance for \a active_projectors projectors: 1 + gain (P - 1). */
  static PCL_TEXLET_HD double
  varianceFactorAt (double gain, double active_projectors)
  {
    const double others = active_projectors > 1.0 ? active_projectors - 1.0 : 0.0;
    const double f = 1.0 + gain * others;
    return f > 0.0 ? f : 0.0;
  }

  static PCL_TEXLET_HD double
  varianceFactor (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    return varianceFactorAt (p[0], ctx.active_projectors);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
