/*
 * pcl_texlet simulator: which physical effects a simulation draws, by name, with their
 * parameter values.
 *
 * The effects are those of the effect registry (noise/effect_registry.h; each defined in its
 * file noise/effects/<name>.h, with its physics, parameters and units). The functions below
 * reach effects and parameters by their names, so that YAML files, the app's options and the
 * model lab share one vocabulary; the typed accessors reach an effect through its file.
 */
#pragma once

#include <pcl_texlet/noise/effect_registry.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace sim
{

using texlet::EffectInfo;
using texlet::EffectParameterInfo;
using texlet::ParameterRange;
using texlet::effectCatalogue;
using texlet::effectInfo;
using texlet::toString;

/** \brief Every effect of the registry, on or off, with its simulator parameters; all off at
  * their defaults when constructed (the paper's noise alone).
  */
class SensorEffects
{
public:
  SensorEffects ();

  /** \brief Number of effects (the registry's). */
  std::size_t
  size () const { return enabled_.size (); }

  /** \brief Whether effect \a index (registry order) is on. */
  bool
  enabled (std::size_t index) const { return enabled_.at (index) != 0; }

  void
  setEnabled (std::size_t index, bool on) { enabled_.at (index) = on ? 1 : 0; }

  /** \brief Parameter values of effect \a index, in the order of its catalogue entry. */
  const std::vector<double> &
  values (std::size_t index) const { return values_.at (index); }

  /** \brief Sets parameter \a parameter of effect \a index without checking its range
    * (validate () does; setEffectParameter checks at once).
    */
  void
  setValue (std::size_t index, std::size_t parameter, double value) { values_.at (index).at (parameter) = value; }

  /** \brief The parameters of effect file \a Effect (e.g. effects::Radial) as its struct. */
  template <typename Effect>
  typename Effect::SimParameters
  parameters () const
  {
    return effects::withFieldValues (Effect::simParameters (), values (indexOf (Effect::kName)));
  }

  /** \brief Sets all parameters of effect file \a Effect from its struct, unchecked (validate ()
    * checks them), and switches it on or off.
    */
  template <typename Effect>
  void
  set (const typename Effect::SimParameters &parameters, bool on = true)
  {
    const std::size_t i = indexOf (Effect::kName);
    values_.at (i) = effects::fieldValues (Effect::simParameters (), parameters);
    setEnabled (i, on);
  }

  /** \brief Whether effect file \a Effect is on. */
  template <typename Effect>
  bool
  isEnabled () const { return enabled (indexOf (Effect::kName)); }

private:
  static std::size_t
  indexOf (const std::string &name);

  std::vector<std::uint8_t> enabled_;
  std::vector<std::vector<double>> values_;
};

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

/** \brief The simulator's hooks of the effects in registry order, each with whether it is on. */
struct GenerativeEffects
{
  std::vector<GenerativeEffect::ConstPtr> all; ///< every simulated effect
  std::vector<bool> enabled;                   ///< per entry of all
  std::vector<GenerativeEffect::ConstPtr> on;  ///< the enabled ones, in order
};

/** \brief The hooks of \a effects at their values (call validate () first). */
GenerativeEffects
generativeEffects (const SensorEffects &effects);

} // namespace sim
} // namespace texlet
} // namespace pcl
