#include <pcl_texlet/features/texlet_parameters.h>

#include <pcl/exceptions.h>

namespace pcl
{
namespace texlet
{

void
validate (const TexletParameters &p)
{
  const std::string problem = parameterProblem (p);
  if (!problem.empty ())
    throw pcl::BadArgumentException (problem);
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
