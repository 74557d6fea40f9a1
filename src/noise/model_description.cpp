#include <pcl_texlet/noise/model_description.h>

namespace pcl
{
namespace texlet
{

ModelDescription
describeModel (const NoiseModel &model)
{
  ModelDescription d;
  d.min_sigma_mm = model.minSigmaMm ();
  for (const auto &t : model.terms ())
  {
    TermDescription term;
    term.name = t->name ();
    term.settings = t->settings ();
    const auto names = t->parameterNames ();
    const auto values = t->parameters ();
    for (std::size_t k = 0; k < names.size () && k < values.size (); ++k)
      term.parameters.emplace_back (names[k], values[k]);
    d.terms.push_back (std::move (term));
  }
  return d;
}

} // namespace texlet
} // namespace pcl
