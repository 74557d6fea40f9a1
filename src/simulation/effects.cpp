#include <pcl_texlet/simulation/effects.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{
namespace sim
{

namespace
{

const EffectRegistry &
registry ()
{
  return EffectRegistry::vocabulary ();
}

/** Index of parameter \a parameter of effect \a effect. */
std::size_t
parameterIndex (const std::string &effect, const std::string &parameter)
{
  const EffectInfo &info = effectInfo (effect);
  std::string names;
  for (std::size_t k = 0; k < info.parameters.size (); ++k)
  {
    if (info.parameters[k].name == parameter)
      return k;
    names += (names.empty () ? "" : ", ") + info.parameters[k].name;
  }
  throw pcl::BadArgumentException ("effect '" + effect + "' has no parameter '" + parameter + "' (its parameters: " +
                                   names + ")");
}

void
checkRange (const std::string &effect, const EffectParameterInfo &p, double value)
{
  if (!inRange (p.range, value))
  {
    std::ostringstream msg;
    msg << "effect '" << effect << "': parameter " << p.name << " must be " << toString (p.range) << " (got " << value
        << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
}

} // namespace

SensorEffects::SensorEffects ()
{
  const EffectRegistry &r = registry ();
  enabled_.assign (r.size (), 0);
  for (std::size_t i = 0; i < r.size (); ++i)
  {
    std::vector<double> defaults;
    for (const auto &p : r.info (i).parameters)
      defaults.push_back (p.default_value);
    values_.push_back (defaults);
  }
}

std::size_t
SensorEffects::indexOf (const std::string &name)
{
  return registry ().index (name);
}

bool
isEffectEnabled (const SensorEffects &effects, const std::string &name)
{
  return effects.enabled (registry ().index (name));
}

void
setEffectEnabled (SensorEffects &effects, const std::string &name, bool enabled)
{
  const std::size_t index = registry ().index (name);
  if (enabled && !registry ().info (index).simulated)
    throw pcl::BadArgumentException ("effect '" + name + "' is a term of the noise model only (" +
                                     registry ().info (index).summary + "): the simulator cannot draw it");
  effects.setEnabled (index, enabled);
}

double
effectParameter (const SensorEffects &effects, const std::string &effect, const std::string &parameter)
{
  const std::size_t k = parameterIndex (effect, parameter);
  return effects.values (registry ().index (effect))[k];
}

void
setEffectParameter (SensorEffects &effects, const std::string &effect, const std::string &parameter, double value)
{
  const std::size_t k = parameterIndex (effect, parameter);
  const std::size_t i = registry ().index (effect);
  checkRange (effect, registry ().info (i).parameters[k], value);
  effects.setValue (i, k, value);
}

std::vector<std::string>
enabledEffects (const SensorEffects &effects)
{
  std::vector<std::string> names;
  for (std::size_t i = 0; i < effects.size (); ++i)
    if (effects.enabled (i))
      names.push_back (registry ().info (i).name);
  return names;
}

void
validate (const SensorEffects &effects)
{
  const EffectRegistry &r = registry ();
  for (std::size_t i = 0; i < r.size (); ++i)
  {
    const EffectInfo &info = r.info (i);
    for (std::size_t k = 0; k < info.parameters.size (); ++k)
      checkRange (info.name, info.parameters[k], effects.values (i)[k]);
  }
}

GenerativeEffects
generativeEffects (const SensorEffects &effects)
{
  const EffectRegistry &r = registry ();
  GenerativeEffects out;
  for (std::size_t i = 0; i < r.size (); ++i)
  {
    GenerativeEffect::ConstPtr g = r.generative (i, effects.values (i));
    if (!g)
      continue;
    out.all.push_back (g);
    out.enabled.push_back (effects.enabled (i));
    if (effects.enabled (i))
      out.on.push_back (g);
  }
  return out;
}

} // namespace sim
} // namespace texlet
} // namespace pcl
