/*
 * pcl_texlet: the settings of texlet extraction, shared by the class, the free function and
 * the apps.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <cstdint>
#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Texlet extraction settings; defaults are the paper's (Table 1). */
struct TexletParameters
{
  int spacing = 6;                 ///< hexagonal grid spacing, pixels (>= 2)
  int radius = 6;                  ///< neighbourhood disc radius, pixels
  int ransac_iterations = 20;      ///< RANSAC hypotheses per texlet (1 .. 100000)
  double ransac_threshold = 0.0;   ///< point-to-plane inlier distance, metres; 0 = from the noise model
  double threshold_sigmas = 3.0;   ///< automatic threshold = this many depth SDs at the patch
  PlaneFitMethod fit = PlaneFitMethod::PCA;
  UncertaintyMethod uncertainty = UncertaintyMethod::MonteCarlo;
  int samples = 50;                ///< Monte Carlo samples (2 .. 100000)
  std::uint32_t seed = 0;          ///< Philox key: results depend on (seed, texlet, draw) only
  int min_support = 6;             ///< fewest RANSAC inliers that make a texlet (>= 3)
  float viewpoint[3] = {0.0f, 0.0f, 0.0f}; ///< normals face this point
};

/** \brief Checks every field; \throws pcl::BadArgumentException naming the field and value. */
void
validate (const TexletParameters &p);

/** \brief "pca", "svd", "averaging". */
std::string
toString (PlaneFitMethod m);

/** \brief "none", "analytic", "montecarlo". */
std::string
toString (UncertaintyMethod m);

/** \throws pcl::BadArgumentException for an unknown name. */
PlaneFitMethod
planeFitMethodFromString (const std::string &name);

/** \throws pcl::BadArgumentException for an unknown name. */
UncertaintyMethod
uncertaintyMethodFromString (const std::string &name);

} // namespace texlet
} // namespace pcl
