/*
 * pcl_texlet simulator: simulation settings from YAML files and "effect.parameter=value" text.
 *
 * The YAML file is a map:
 *
 *   base_noise: paper          # paper (default) or none
 *   projector_shadows: true    # the own projector's shadows (default true)
 *   effects:
 *     disparity_quantization: true          # on, default parameters
 *     vertical_stripes: {bands: 8}          # on, one parameter set
 *     incidence_angle: {enabled: false, gain: 1.0}
 *
 * A meta.yaml written by the simulator is a valid file too (its other keys are ignored), so a
 * recording's effects can be reproduced from it.
 */
#pragma once

#include <pcl_texlet/simulation/simulation_settings.h>

#include <string>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief Applies the YAML file \a path to \a settings (keys it does not name keep their values).
  * \throws pcl::IOException naming the file and the problem: missing, not YAML, an unknown key,
  *         effect or parameter, or a value of the wrong type or out of range.
  */
void
loadSimulationConfig (const std::string &path, SimulationSettings &settings);

/** \brief As loadSimulationConfig for YAML text; \a source names it in error messages. */
void
parseSimulationConfig (const std::string &yaml, SimulationSettings &settings, const std::string &source = "config");

/** \brief Applies "effect.parameter=value" (the app's --set) to \a effects; does not switch the
  * effect on.
  * \throws pcl::BadArgumentException for malformed text, an unknown effect or parameter, or a
  *         value out of range.
  */
void
applyEffectAssignment (const std::string &assignment, SensorEffects &effects);

} // namespace sim
} // namespace texlet
} // namespace pcl
