/*
 * pcl_texlet simulator: the switchable physical effects of DESIGN.md section 5, by name.
 *
 * SensorEffects holds one parameter struct per effect (see kernels/sensor_effects.h for the
 * physics, parameters and units of each). The functions below reach effects and parameters by
 * their names, so that YAML files, the app's options and the model lab share one vocabulary.
 */
#pragma once

#include <pcl_texlet/kernels/sensor_effects.h>

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief Every effect of the simulator; all off by default (the paper's noise alone). */
struct SensorEffects
{
  kernels::AxialQuadratic axial_quadratic;             ///< `axial_quadratic`
  kernels::Radial radial;                              ///< `radial`
  kernels::DisparityQuantization disparity_quantization; ///< `disparity_quantization`
  kernels::IncidenceAngle incidence_angle;             ///< `incidence_angle`
  kernels::VerticalStripes vertical_stripes;           ///< `vertical_stripes`
  kernels::DepthDistortion depth_distortion;           ///< `depth_distortion`
  kernels::Interference interference;                  ///< `interference`
  kernels::TemporalDrift temporal_drift;               ///< `temporal_drift`
  kernels::LateralNoise lateral_noise;                 ///< `lateral_noise`
  kernels::Intrinsics intrinsics;                      ///< `intrinsics`
};

/** \brief Which values a parameter accepts. */
enum class ParameterRange
{
  Any,             ///< any finite number
  NonNegative,     ///< >= 0
  Positive,        ///< > 0
  PositiveInteger, ///< a whole number >= 1
  AngleDegrees     ///< in (0, 90]
};

/** \brief Text for a range, e.g. "> 0". */
std::string
toString (ParameterRange range);

/** \brief One parameter of an effect. */
struct EffectParameterInfo
{
  std::string name;        ///< e.g. "offset_px"
  std::string unit;        ///< e.g. "px", "m", "deg", "frames", "1" (dimensionless)
  std::string description; ///< one line
  ParameterRange range = ParameterRange::Any;
  double default_value = 0.0;
};

/** \brief One effect: its name (DESIGN.md section 5), a one-line summary, its parameters. */
struct EffectInfo
{
  std::string name;
  std::string summary;
  std::vector<EffectParameterInfo> parameters;
};

/** \brief All effects, in the order of DESIGN.md section 5. */
const std::vector<EffectInfo> &
effectCatalogue ();

/** \brief The entry of effect \a name. \throws pcl::BadArgumentException for an unknown name
  *        (the message lists the known ones).
  */
const EffectInfo &
effectInfo (const std::string &name);

/** \brief Whether effect \a name is on. \throws pcl::BadArgumentException for an unknown name. */
bool
isEffectEnabled (const SensorEffects &effects, const std::string &name);

/** \brief Switches effect \a name on or off. \throws pcl::BadArgumentException for an unknown name. */
void
setEffectEnabled (SensorEffects &effects, const std::string &name, bool enabled);

/** \brief Value of parameter \a parameter of effect \a effect.
  * \throws pcl::BadArgumentException for an unknown effect or parameter.
  */
double
effectParameter (const SensorEffects &effects, const std::string &effect, const std::string &parameter);

/** \brief Sets parameter \a parameter of effect \a effect (does not switch the effect on).
  * \throws pcl::BadArgumentException for an unknown effect or parameter, or a value outside the
  *         parameter's range (the message names effect, parameter, value and range).
  */
void
setEffectParameter (SensorEffects &effects, const std::string &effect, const std::string &parameter, double value);

/** \brief Names of the effects that are on, in catalogue order. */
std::vector<std::string>
enabledEffects (const SensorEffects &effects);

/** \brief Checks every parameter of every effect against its range.
  * \throws pcl::BadArgumentException naming the first offending parameter.
  */
void
validate (const SensorEffects &effects);

} // namespace sim
} // namespace texlet
} // namespace pcl
