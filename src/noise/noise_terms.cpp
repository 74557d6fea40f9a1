#include <pcl_texlet/noise/effect_registry.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{

EffectTerm::EffectTerm (std::string name, std::vector<std::string> parameter_names, std::vector<double> values)
  : name_ (std::move (name)), names_ (std::move (parameter_names)), values_ (std::move (values))
{
}

void
EffectTerm::setParameters (const std::vector<double> &values)
{
  if (values.size () != values_.size ())
  {
    std::ostringstream msg;
    msg << "noise term '" << name_ << "': expected " << values_.size () << " parameters, got " << values.size ();
    throw pcl::BadArgumentException (msg.str ());
  }
  for (std::size_t i = 0; i < values.size (); ++i)
  {
    if (!std::isfinite (values[i]))
      throw pcl::BadArgumentException ("noise term '" + name_ + "': parameter " + names_[i] + " is not finite");
    if (values[i] < lowestValue (i))
    {
      std::ostringstream msg;
      msg << "noise term '" << name_ << "': parameter " << names_[i] << " is " << values[i] << ", below its least value "
          << lowestValue (i);
      throw pcl::BadArgumentException (msg.str ());
    }
  }
  values_ = values;
}

const std::vector<std::string> &
noiseEffectNames ()
{
  static const std::vector<std::string> names = [] {
    const EffectRegistry &r = EffectRegistry::vocabulary ();
    std::vector<std::string> n;
    for (std::size_t i = 0; i < r.size (); ++i)
      if (r.info (i).has_term)
        n.push_back (r.info (i).name);
    return n;
  }();
  return names;
}

NoiseTerm::Ptr
makeNoiseTerm (const std::string &name)
{
  if (name == "polynomial")
    return std::make_shared<PolynomialSigmaTerm> ();
  const EffectRegistry &r = EffectRegistry::vocabulary ();
  const int i = r.find (name);
  if (i >= 0 && r.info (i).has_term)
    return r.makeTerm (i);
  std::string known = "polynomial";
  for (const auto &n : noiseEffectNames ())
    known += ", " + n;
  throw pcl::BadArgumentException ("unknown noise term '" + name + "' (known: " + known + ")");
}

} // namespace texlet
} // namespace pcl
