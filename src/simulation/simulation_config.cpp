#include <pcl_texlet/simulation/simulation_config.h>

#include <pcl_texlet/common/error_text.h>

#include <pcl/exceptions.h>

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{
namespace sim
{

namespace
{

/** Keys a meta.yaml carries besides the configuration's own; accepted and ignored. */
const std::set<std::string> &
metaOnlyKeys ()
{
  static const std::set<std::string> keys = {"generator",   "seed",          "first_frame", "frames",
                                             "scene",       "scene_parameters", "box_size_m", "mesh",
                                             "projectors",  "sensors",       "sensor",      "sensor_pose",
                                             "render_camera", "depth_range_m", "base_noise_terms"};
  return keys;
}

pcl::IOException
configError (const std::string &source, const std::string &problem)
{
  return pcl::IOException (source + ": " + problem);
}

/** \brief A key's text. yaml-cpp's own conversion throws YAML::BadConversion for a list or map
  * as a key (e.g. `{[a]: 1}`), which is not the pcl::IOException callers expect.
  */
std::string
keyText (const YAML::Node &key, const std::string &where, const std::string &source)
{
  if (!key.IsScalar ())
    throw configError (source, "a key of " + where + " must be a plain name, not a list or map");
  return key.Scalar ();
}

bool
asBool (const YAML::Node &node, const std::string &key, const std::string &source)
{
  bool value = false;
  if (!node.IsScalar () || !YAML::convert<bool>::decode (node, value))
    throw configError (source, key + " must be true or false (found '" + (node.IsScalar () ? node.Scalar () : "a " +
                                                                          std::string (node.IsMap () ? "map" : "list")) +
                                   "')");
  return value;
}

double
asNumber (const YAML::Node &node, const std::string &key, const std::string &source)
{
  if (!node.IsScalar ())
    throw configError (source, key + " must be a number");
  try
  {
    return node.as<double> ();
  }
  catch (const YAML::BadConversion &)
  {
    throw configError (source, key + " must be a number (found '" + node.Scalar () + "')");
  }
}

void
applyEffect (const std::string &name, const YAML::Node &value, SensorEffects &effects, const std::string &source)
{
  const std::string key = "effects." + name;
  try
  {
    effectInfo (name); // unknown names fail here, listing the known ones
    if (value.IsScalar ())
    {
      setEffectEnabled (effects, name, asBool (value, key, source));
      return;
    }
    if (value.IsNull ())
    {
      setEffectEnabled (effects, name, true);
      return;
    }
    if (!value.IsMap ())
      throw configError (source, key + " must be true, false or a map of parameters");
    bool enabled = true; // listing an effect's parameters switches it on unless told otherwise
    for (const auto &entry : value)
    {
      const std::string param = keyText (entry.first, key, source);
      if (param == "enabled")
        enabled = asBool (entry.second, key + ".enabled", source);
      else
        setEffectParameter (effects, name, param, asNumber (entry.second, key + "." + param, source));
    }
    setEffectEnabled (effects, name, enabled);
  }
  catch (const pcl::BadArgumentException &e)
  {
    throw configError (source, errorText (e));
  }
}

} // namespace

void
parseSimulationConfig (const std::string &yaml, SimulationSettings &settings, const std::string &source)
{
  YAML::Node root;
  try
  {
    root = YAML::Load (yaml);
  }
  catch (const YAML::ParserException &e)
  {
    throw configError (source, "not valid YAML (line " + std::to_string (e.mark.line + 1) + ", column " +
                                   std::to_string (e.mark.column + 1) + ": " + e.msg + ")");
  }
  if (root.IsNull ())
    return; // an empty file changes nothing
  if (!root.IsMap ())
    throw configError (source, "must be a YAML map (base_noise, projector_shadows, effects)");

  // Work on a copy so that a bad file leaves the settings as they were.
  SimulationSettings result = settings;
  for (const auto &entry : root)
  {
    const std::string key = keyText (entry.first, "the config", source);
    const YAML::Node &value = entry.second;
    if (key == "base_noise")
    {
      const std::string mode = value.IsScalar () ? value.Scalar () : "";
      if (mode == "paper")
      {
        result.base_noise = true;
        result.noise_model = NoiseModel::paper ();
      }
      else if (mode == "none")
        result.base_noise = false;
      else if (mode == "custom")
        throw configError (source, "base_noise 'custom' cannot be read back: set the noise model through the API");
      else
        throw configError (source, "base_noise must be 'paper' or 'none' (found '" + mode + "')");
    }
    else if (key == "projector_shadows")
      result.projector_shadows = asBool (value, key, source);
    else if (key == "effects")
    {
      if (value.IsNull ())
        continue;
      if (!value.IsMap ())
        throw configError (source, "effects must be a map from effect names to true, false or parameters");
      for (const auto &effect : value)
        applyEffect (keyText (effect.first, "effects", source), effect.second, result.effects, source);
    }
    else if (!metaOnlyKeys ().count (key))
      throw configError (source, "unknown key '" + key + "' (expected base_noise, projector_shadows, effects)");
  }
  settings = result;
}

void
loadSimulationConfig (const std::string &path, SimulationSettings &settings)
{
  const std::string source = "simulation config '" + path + "'";
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw configError (source, "does not exist");
  std::string text;
  {
    std::FILE *f = std::fopen (path.c_str (), "rb");
    if (!f)
      throw configError (source, std::string ("cannot open: ") + std::strerror (errno));
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread (buffer, 1, sizeof (buffer), f)) > 0)
      text.append (buffer, n);
    const bool failed = std::ferror (f) != 0;
    std::fclose (f);
    if (failed)
      throw configError (source, "cannot read");
  }
  parseSimulationConfig (text, settings, source);
}

void
applyEffectAssignment (const std::string &assignment, SensorEffects &effects)
{
  const std::size_t dot = assignment.find ('.'), eq = assignment.find ('=');
  if (dot == std::string::npos || eq == std::string::npos || dot == 0 || eq < dot + 2 || eq + 1 >= assignment.size ())
    throw pcl::BadArgumentException ("'" + assignment + "' is not of the form effect.parameter=value");
  const std::string effect = assignment.substr (0, dot), parameter = assignment.substr (dot + 1, eq - dot - 1),
                    value = assignment.substr (eq + 1);
  char *end = nullptr;
  errno = 0;
  const double number = std::strtod (value.c_str (), &end);
  if (end == value.c_str () || *end != '\0' || errno == ERANGE)
    throw pcl::BadArgumentException ("'" + assignment + "': the value '" + value + "' is not a number");
  setEffectParameter (effects, effect, parameter, number);
}

} // namespace sim
} // namespace texlet
} // namespace pcl
