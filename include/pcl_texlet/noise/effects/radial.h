/*
 * pcl_texlet effect `radial`: noise grows away from the optical centre.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `radial`: noise grows away from the optical centre.
  *
  * Physics: lens vignetting (cos^4 fall-off) and the projector's own fall-off darken the dot
  * pattern toward the image border; a dimmer pattern localises worse. To second order in the
  * radius the disparity SD is multiplied by 1 + gain (r / reference_radius_px)^2, r being the
  * distance in pixels from the principal point; the term multiplies the variance of the
  * correlation noise by the square of that.
  */
struct Radial
{
  static constexpr const char *kName = "radial";
  static constexpr EffectText kText = {"radius",
                                       "noise grows away from the optical centre: SD x (1 + gain (r/r_ref)^2)",
                                       "vignetting and the projector's fall-off dim the dot pattern toward the border, where it localises worse"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    double gain = 0.5;                  ///< relative SD increase at the reference radius
    double reference_radius_px = 400.0; ///< radius where the SD has grown by `gain`, pixels
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"gain", "1", "relative SD increase at r_ref", ParameterRange::NonNegative, &SimParameters::gain},
            {"reference_radius_px", "px", "reference radius r_ref from the principal point", ParameterRange::Positive,
             &SimParameters::reference_radius_px}};
  }

  /** \brief Factor on the disparity SD at distance \a r_px from the principal point. */
  static PCL_TEXLET_HD double
  factor (const SimParameters &p, double r_px)
  {
    const double x = r_px / p.reference_radius_px;
    return 1.0 + p.gain * x * x;
  }

  static PCL_TEXLET_HD double
  sdFactor (const SimParameters &p, const SimPixel &px)
  {
    return factor (p, px.radius_px);
  }

  // --- the noise model's term ----------------------------------------------------------------

  static constexpr unsigned kLabNeeds = kNeedsRepeatedFrames;

  struct TermSettings
  {
    double reference_radius_px = SimParameters ().reference_radius_px; ///< r_ref, pixels
  };

  static std::vector<Field<TermSettings>>
  termSettings ()
  {
    return {{"reference_radius_px", "px", "reference radius r_ref from the principal point", ParameterRange::Positive,
             &TermSettings::reference_radius_px}};
  }

  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"gain", 0.0, 0.1, 0.1}};
  }

  /** \brief Factor on the depth variance: (1 + gain (r / r_ref)^2)^2, never negative. */
  static PCL_TEXLET_HD double
  varianceFactorAt (double gain, double r_px, double reference_radius_px)
  {
    const double x = r_px / reference_radius_px;
    const double f = 1.0 + gain * x * x;
    return f > 0.0 ? f * f : 0.0;
  }

  static PCL_TEXLET_HD double
  varianceFactor (const double *p, const TermSettings &s, const PixelContext &ctx)
  {
    return varianceFactorAt (p[0], ctx.radius_px, s.reference_radius_px);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
