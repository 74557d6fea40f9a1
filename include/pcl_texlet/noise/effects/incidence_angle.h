/*
 * pcl_texlet effect `incidence_angle`: noise grows toward grazing angles.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `incidence_angle`: noise grows toward grazing angles.
  *
  * Physics: on a surface seen at angle theta from its normal the pattern is stretched by
  * 1 / cos(theta) across the correlation window, which blurs the correlation peak. The
  * disparity SD is multiplied by 1 + gain (1 / cos(theta) - 1); beyond max_angle_deg the
  * pattern is too stretched to match and the pixel has no reading. The term multiplies the
  * variance by the square of that factor.
  */
struct IncidenceAngle
{
  static constexpr const char *kName = "incidence_angle";
  static constexpr EffectText kText = {"incidence",
                                       "noise grows toward grazing angles: SD x (1 + gain (1/cos - 1))",
                                       "on an oblique surface the dot pattern is stretched by 1 / cos(theta) across the correlation window, blurring the correlation peak"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    double gain = 0.5;           ///< SD increase per unit of 1/cos(theta) - 1
    double max_angle_deg = 80.0; ///< no reading beyond this angle, degrees
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"gain", "1", "SD increase per unit of 1/cos(theta) - 1", ParameterRange::NonNegative,
             &SimParameters::gain},
            {"max_angle_deg", "deg", "no reading beyond this angle", ParameterRange::AngleDegrees,
             &SimParameters::max_angle_deg}};
  }

  /** \brief Factor on the disparity SD for a surface seen at angle acos(\a cos_theta). */
  static PCL_TEXLET_HD double
  factor (const SimParameters &p, double cos_theta)
  {
    return 1.0 + p.gain * (1.0 / cos_theta - 1.0);
  }

  /** \brief True when the surface is too oblique to give a reading. */
  static PCL_TEXLET_HD bool
  tooOblique (const SimParameters &p, double cos_theta)
  {
    return cos_theta < std::cos (p.max_angle_deg * 0.017453292519943295);
  }

  static PCL_TEXLET_HD bool
  readable (const SimParameters &p, const SimPixel &px)
  {
    return !tooOblique (p, px.cos_incidence);
  }

  static PCL_TEXLET_HD double
  sdFactor (const SimParameters &p, const SimPixel &px)
  {
    return factor (p, px.cos_incidence);
  }

  // --- the noise model's term ----------------------------------------------------------------

  static constexpr unsigned kLabNeeds = kNeedsRepeatedFrames;

  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"gain", 0.0, 0.1, 0.1}};
  }

  /** \brief Factor on the depth variance: (1 + gain (1 / cos(theta) - 1))^2; cos(theta) is
    * clamped to 0.05 (87 degrees).
    */
  static PCL_TEXLET_HD double
  varianceFactorAt (double gain, double cos_theta)
  {
    const double c = cos_theta > 0.05 ? cos_theta : 0.05;
    const double f = 1.0 + gain * (1.0 / c - 1.0);
    return f > 0.0 ? f * f : 0.0;
  }

  static PCL_TEXLET_HD double
  varianceFactor (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    return varianceFactorAt (p[0], ctx.cos_incidence);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
