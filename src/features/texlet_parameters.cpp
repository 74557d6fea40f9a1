#include <pcl_texlet/features/texlet_parameters.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{

namespace
{
template <typename T> void
require (bool ok, const char *field, T value, const char *rule)
{
  if (ok)
    return;
  std::ostringstream msg;
  msg << "texlet parameter '" << field << "' " << rule << " (got " << value << ")";
  throw pcl::BadArgumentException (msg.str ());
}
} // namespace

void
validate (const TexletParameters &p)
{
  require (p.spacing >= 2, "spacing", p.spacing, "must be at least 2 pixels (hexagonal rows closer than that collide)");
  require (p.radius >= 1, "radius", p.radius, "must be at least 1 pixel");
  require (p.radius <= 64, "radius", p.radius, "must be at most 64 pixels");
  require (p.ransac_iterations >= 1, "ransac_iterations", p.ransac_iterations, "must be at least 1");
  // Upper bounds: beyond them a frame takes hours, which looks like a hang.
  require (p.ransac_iterations <= 100000, "ransac_iterations", p.ransac_iterations, "must be at most 100000");
  require (p.ransac_threshold >= 0.0 && std::isfinite (p.ransac_threshold), "ransac_threshold", p.ransac_threshold,
           "must be a finite distance in metres, or 0 for the noise model's");
  require (p.threshold_sigmas > 0.0 && std::isfinite (p.threshold_sigmas), "threshold_sigmas", p.threshold_sigmas,
           "must be positive");
  require (p.samples >= 2, "samples", p.samples, "must be at least 2 for a covariance");
  require (p.samples <= 100000, "samples", p.samples, "must be at most 100000");
  require (p.min_support >= 3, "min_support", p.min_support, "must be at least 3 points");
  require (std::isfinite (p.viewpoint[0]) && std::isfinite (p.viewpoint[1]) && std::isfinite (p.viewpoint[2]),
           "viewpoint", "non-finite", "must be finite");
  require (static_cast<int> (p.fit) >= 0 && static_cast<int> (p.fit) <= 2, "fit", static_cast<int> (p.fit),
           "must be PCA, SVD or Averaging");
  require (static_cast<int> (p.uncertainty) >= 0 && static_cast<int> (p.uncertainty) <= 2, "uncertainty",
           static_cast<int> (p.uncertainty), "must be None, Analytic or MonteCarlo");
}

std::string
toString (PlaneFitMethod m)
{
  switch (m)
  {
  case PlaneFitMethod::PCA: return "pca";
  case PlaneFitMethod::SVD: return "svd";
  case PlaneFitMethod::Averaging: return "averaging";
  }
  return "unknown";
}

std::string
toString (UncertaintyMethod m)
{
  switch (m)
  {
  case UncertaintyMethod::None: return "none";
  case UncertaintyMethod::Analytic: return "analytic";
  case UncertaintyMethod::MonteCarlo: return "montecarlo";
  }
  return "unknown";
}

PlaneFitMethod
planeFitMethodFromString (const std::string &name)
{
  for (PlaneFitMethod m : {PlaneFitMethod::PCA, PlaneFitMethod::SVD, PlaneFitMethod::Averaging})
    if (toString (m) == name)
      return m;
  throw pcl::BadArgumentException ("unknown plane fit method '" + name + "' (use pca, svd or averaging)");
}

UncertaintyMethod
uncertaintyMethodFromString (const std::string &name)
{
  for (UncertaintyMethod m : {UncertaintyMethod::None, UncertaintyMethod::Analytic, UncertaintyMethod::MonteCarlo})
    if (toString (m) == name)
      return m;
  throw pcl::BadArgumentException ("unknown uncertainty method '" + name + "' (use none, analytic or montecarlo)");
}

} // namespace texlet
} // namespace pcl
