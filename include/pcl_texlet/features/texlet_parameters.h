/*
 * pcl_texlet: the settings of texlet extraction, shared by the class, the free function and
 * the apps.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Texlet extraction settings; defaults are the paper's (Table 1). */
struct TexletParameters
{
  int spacing = 6;                 ///< hexagonal grid spacing, pixels (>= 2)
  int radius = 6;                  ///< neighbourhood disc radius, pixels (1 .. 64)
  int ransac_iterations = 20;      ///< RANSAC hypotheses per texlet (1 .. 100000)
  double ransac_threshold = 0.0;   ///< point-to-plane inlier distance, metres; 0 = from the noise model
  double threshold_sigmas = 3.0;   ///< automatic threshold = this many depth SDs at the patch
  double robust_sigmas = 4.0;      ///< the automatic threshold widens to this many of the patch's own SDs; 0: never
  PlaneFitMethod fit = PlaneFitMethod::PCA;
  TexletCentre centre = TexletCentre::CentreRay; ///< which point of the plane is P
  UncertaintyMethod uncertainty = UncertaintyMethod::MonteCarlo;
  int samples = 50;                ///< Monte Carlo samples (2 .. 100000)
  std::uint32_t seed = 0;          ///< Philox key: results depend on (seed, texlet, draw) only
  int min_support = 6;             ///< fewest RANSAC inliers that make a texlet (>= 3)
  bool remove_model_bias = true;   ///< take the noise model's bias off each reading's depth first
  /** the window-shared noise's form by the windows' sums for every texlet; false: a disc missing
    * few readings or inliers takes it from tables made once (window_disc_form.h, its error in
    * docs/benchmarks.md) */
  bool exact_window_form = false;
  float viewpoint[3] = {0.0f, 0.0f, 0.0f}; ///< normals face this point (pcl::TexletEstimation:
                                           ///< unless it uses the cloud's sensor origin)
};

namespace detail
{
/** \brief Keeps the first rule broken: "texlet parameter 'FIELD' RULE (got VALUE)". */
struct ParameterRules
{
  std::string problem;

  template <typename T> void
  operator() (bool ok, const char *field, const T &value, const char *rule)
  {
    if (ok || !problem.empty ())
      return;
    std::ostringstream msg;
    msg << "texlet parameter '" << field << "' " << rule << " (got " << value << ")";
    problem = msg.str ();
  }
};
} // namespace detail

/** \brief The first field of \a p that breaks a rule, as a sentence naming the field, the rule
  * and the value; empty when every field is fine. The one set of rules for the CPU path and the
  * GPU backend (which builds without PCL): validate() and the GPU's validateParameters() throw it.
  */
inline std::string
parameterProblem (const TexletParameters &p)
{
  detail::ParameterRules require;
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
  require (p.robust_sigmas >= 0.0 && std::isfinite (p.robust_sigmas), "robust_sigmas", p.robust_sigmas,
           "must be a finite number of SDs, or 0 for the model's threshold alone");
  require (p.samples >= 2, "samples", p.samples, "must be at least 2 for a covariance");
  require (p.samples <= 100000, "samples", p.samples, "must be at most 100000");
  require (p.min_support >= 3, "min_support", p.min_support, "must be at least 3 points");
  require (std::isfinite (p.viewpoint[0]) && std::isfinite (p.viewpoint[1]) && std::isfinite (p.viewpoint[2]),
           "viewpoint", "non-finite", "must be finite");
  require (static_cast<int> (p.fit) >= 0 && static_cast<int> (p.fit) <= 2, "fit", static_cast<int> (p.fit),
           "must be PCA, SVD or Averaging");
  require (static_cast<int> (p.uncertainty) >= 0 && static_cast<int> (p.uncertainty) <= 2, "uncertainty",
           static_cast<int> (p.uncertainty), "must be None, Analytic or MonteCarlo");
  require (static_cast<int> (p.centre) >= 0 && static_cast<int> (p.centre) <= 1, "centre", static_cast<int> (p.centre),
           "must be CentreRay or InlierMean");
  return require.problem;
}

/** \brief Checks every field (parameterProblem()).
  * \throws pcl::BadArgumentException naming the field, the rule and the value
  */
void
validate (const TexletParameters &p);

/** \brief "pca", "svd", "averaging". */
std::string
toString (PlaneFitMethod m);

/** \brief "none", "analytic", "montecarlo". */
std::string
toString (UncertaintyMethod m);

/** \brief "ray", "mean". */
std::string
toString (TexletCentre c);

/** \throws pcl::BadArgumentException for an unknown name. */
TexletCentre
texletCentreFromString (const std::string &name);

/** \throws pcl::BadArgumentException for an unknown name. */
PlaneFitMethod
planeFitMethodFromString (const std::string &name);

/** \throws pcl::BadArgumentException for an unknown name. */
UncertaintyMethod
uncertaintyMethodFromString (const std::string &name);

} // namespace texlet
} // namespace pcl
