#include <pcl_texlet/features/texlet_parameters.h>

#include <pcl/exceptions.h>

#include <initializer_list>

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

std::string
toString (TexletCentre c)
{
  switch (c)
  {
  case TexletCentre::CentreRay: return "ray";
  case TexletCentre::InlierMean: return "mean";
  }
  return "unknown";
}

namespace
{

/** The method called \a name, or an error listing the names (as "use a, b or c"). */
template <typename Method>
Method
methodFromString (const std::string &name, std::initializer_list<Method> methods, const char *what)
{
  for (Method m : methods)
    if (toString (m) == name)
      return m;
  std::string names;
  std::size_t k = 0;
  for (Method m : methods)
  {
    if (k > 0)
      names += k + 1 == methods.size () ? " or " : ", ";
    names += toString (m);
    ++k;
  }
  throw pcl::BadArgumentException ("unknown " + std::string (what) + " '" + name + "' (use " + names + ")");
}

} // namespace

PlaneFitMethod
planeFitMethodFromString (const std::string &name)
{
  return methodFromString (name, {PlaneFitMethod::PCA, PlaneFitMethod::SVD, PlaneFitMethod::Averaging},
                           "plane fit method");
}

TexletCentre
texletCentreFromString (const std::string &name)
{
  return methodFromString (name, {TexletCentre::CentreRay, TexletCentre::InlierMean}, "texlet centre");
}

UncertaintyMethod
uncertaintyMethodFromString (const std::string &name)
{
  return methodFromString (name, {UncertaintyMethod::None, UncertaintyMethod::Analytic, UncertaintyMethod::MonteCarlo},
                           "uncertainty method");
}

} // namespace texlet
} // namespace pcl
