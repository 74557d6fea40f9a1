#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/noise/model_description.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <pcl/exceptions.h>

#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/common/error_text.h>

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

namespace pcl
{
namespace texlet
{

namespace
{

std::string
number (double x)
{
  std::ostringstream s;
  s << std::setprecision (17) << x;
  return s.str ();
}

[[noreturn]] void
fail (const std::string &source, const std::string &problem)
{
  throw pcl::IOException (source + ": " + problem);
}

double
finiteValue (const YAML::Node &node, const std::string &source, const std::string &what)
{
  double x = 0;
  try
  {
    x = node.as<double> ();
  }
  catch (const YAML::Exception &)
  {
    fail (source, what + " is not a number");
  }
  if (!std::isfinite (x))
    fail (source, what + " is not finite");
  return x;
}

/** \brief A key's or name's text. yaml-cpp's own conversion throws YAML::BadConversion for a
  * list or map (e.g. the complex key `? - a`), which is not the pcl::IOException callers expect.
  */
std::string
scalarText (const YAML::Node &node, const std::string &source, const std::string &what)
{
  if (!node.IsScalar ())
    fail (source, what + " must be a plain name, not a list or map");
  return node.Scalar ();
}

} // namespace

std::string
noiseModelToYaml (const NoiseModel &model)
{
  const ModelDescription d = describeModel (model);
  const auto map = [] (const std::vector<std::pair<std::string, double>> &entries) {
    std::string text = "{";
    for (std::size_t i = 0; i < entries.size (); ++i)
      text += (i ? ", " : "") + entries[i].first + ": " + number (entries[i].second);
    return text + "}";
  };
  std::ostringstream out;
  out << "# pcl_texlet noise model: depth SD and bias in mm (its terms: docs/architecture.md, section 4)\n";
  out << "min_sigma_mm: " << number (d.min_sigma_mm) << "\n";
  out << "terms:\n";
  for (const auto &t : d.terms)
  {
    out << "  - name: " << t.name << "\n";
    if (!t.settings.empty ())
      out << "    settings: " << map (t.settings) << "\n";
    out << "    parameters: " << map (t.parameters) << "\n";
  }
  return out.str ();
}

NoiseModel
parseNoiseModelYaml (const std::string &yaml, const std::string &source)
{
  YAML::Node root;
  try
  {
    root = YAML::Load (yaml);
  }
  catch (const YAML::Exception &e)
  {
    fail (source, std::string ("not valid YAML (") + e.what () + ")");
  }
  if (!root.IsMap ())
    fail (source, "not a YAML map with a 'terms' list");
  for (const auto &kv : root)
  {
    const std::string key = scalarText (kv.first, source, "a key");
    if (key != "terms" && key != "min_sigma_mm")
      fail (source, "unknown key '" + key + "' (known: min_sigma_mm, terms)");
  }
  const YAML::Node terms = root["terms"];
  if (!terms || !terms.IsSequence () || terms.size () == 0)
    fail (source, "'terms' must be a non-empty list");
  NoiseModel model;
  if (root["min_sigma_mm"])
  {
    const double floor = finiteValue (root["min_sigma_mm"], source, "min_sigma_mm");
    if (!(floor > 0))
      fail (source, "min_sigma_mm must be positive");
    model.setMinSigmaMm (floor);
  }
  std::set<std::string> seen;
  for (std::size_t k = 0; k < terms.size (); ++k)
  {
    const YAML::Node t = terms[k];
    const std::string where = "term " + std::to_string (k + 1);
    if (!t.IsMap () || !t["name"])
      fail (source, where + " has no name");
    const std::string name = scalarText (t["name"], source, where + "'s name");
    if (!seen.insert (name).second)
      fail (source, "term '" + name + "' is listed twice");
    NoiseTerm::Ptr term;
    try
    {
      term = makeNoiseTerm (name);
    }
    catch (const pcl::BadArgumentException &e)
    {
      fail (source, errorText (e));
    }
    for (const auto &kv : t)
    {
      const std::string key = scalarText (kv.first, source, "a key of term '" + name + "'");
      if (key != "name" && key != "settings" && key != "parameters")
        fail (source, "term '" + name + "': unknown key '" + key + "' (known: name, settings, parameters)");
    }
    if (t["settings"])
    {
      if (!t["settings"].IsMap ())
        fail (source, "term '" + name + "': 'settings' must be a map of the term's settings");
      for (const auto &kv : t["settings"])
      {
        const std::string key = scalarText (kv.first, source, "a key of term '" + name + "'");
        try
        {
          term->setSetting (key, finiteValue (kv.second, source, "term '" + name + "' setting " + key));
        }
        catch (const pcl::BadArgumentException &e)
        {
          fail (source, errorText (e));
        }
      }
    }
    const YAML::Node params = t["parameters"];
    if (!params || !params.IsMap ())
      fail (source, "term '" + name + "' has no 'parameters' map");
    const auto names = term->parameterNames ();
    std::map<std::string, double> given;
    for (const auto &kv : params)
    {
      const std::string key = scalarText (kv.first, source, "a key of term '" + name + "'");
      given[key] = finiteValue (kv.second, source, "term '" + name + "' parameter " + key);
    }
    std::vector<double> values;
    for (const auto &n : names)
    {
      const auto it = given.find (n);
      if (it == given.end ())
        fail (source, "term '" + name + "': parameter '" + n + "' is missing");
      values.push_back (it->second);
      given.erase (it);
    }
    if (!given.empty ())
      fail (source, "term '" + name + "': unknown parameter '" + given.begin ()->first + "'");
    try
    {
      term->setParameters (values);
    }
    catch (const pcl::BadArgumentException &e)
    {
      fail (source, errorText (e));
    }
    model.add (*term);
  }
  return model;
}

NoiseModel
loadNoiseModelYaml (const std::string &path)
{
  std::ifstream in (path);
  if (!in)
    throw pcl::IOException ("noise model '" + path + "': cannot be opened (missing or unreadable)");
  std::stringstream text;
  text << in.rdbuf ();
  return parseNoiseModelYaml (text.str (), "noise model '" + path + "'");
}

void
saveNoiseModelYaml (const std::string &path, const NoiseModel &model)
{
  AtomicFile file (path);
  {
    std::ofstream out (file.temporaryPath ());
    out << noiseModelToYaml (model);
    out.close (); // a failed flush (disk full) shows only here
    if (!out)
      throw pcl::IOException ("noise model '" + path + "': cannot be written");
  }
  file.commit ();
}

} // namespace texlet
} // namespace pcl
