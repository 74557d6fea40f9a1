/*
 * pcl_texlet kernels: one texlet from its neighbourhood (paper, Sect. 3.2, steps 2 and 3).
 *
 * RANSAC marks the inliers, the chosen fit gives P and N, N is turned toward the viewpoint,
 * and the chosen propagation gives Sigma_P and Sigma_N. The function allocates nothing: the
 * caller passes an inlier mask of nb.count bytes and a work buffer of
 * texletWorkSize (nb.count) values.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/plane_fit.h>
#include <pcl_texlet/kernels/ransac.h>
#include <pcl_texlet/kernels/tangent_frame.h>
#include <pcl_texlet/kernels/uncertainty.h>

namespace pcl
{
namespace texlet
{
namespace kernels
{

template <typename S>
struct TexletSettings
{
  int ransac_iterations = 20;
  S threshold = S (0);           ///< point-to-plane inlier distance, same unit as the points
  PlaneFitMethod fit = PlaneFitMethod::PCA;
  UncertaintyMethod uncertainty = UncertaintyMethod::MonteCarlo;
  int samples = 50;              ///< Monte Carlo samples
  std::uint32_t seed = 0;
  int min_support = 6;           ///< fewest RANSAC inliers that make a texlet
  Vec3<S> viewpoint = {0, 0, 0}; ///< normals are turned to face it
};

template <typename S>
struct TexletResult
{
  bool ok = false;
  Vec3<S> P, N;
  S cov_p[6];   ///< xx xy xz yy yz zz
  S cov_n[3];   ///< t1t1 t1t2 t2t2 (tangent_frame.h), rad^2
  S curvature;  ///< l0 / (l0 + l1 + l2) of the inliers' covariance (PCL's surface variation)
  S radius;     ///< sqrt(2 (l1 + l2)): radius of the disc with the inliers' in-plane spread
  int support;  ///< RANSAC inliers
};

/** \brief Scratch values computeTexlet() needs for a neighbourhood of \a count points. */
PCL_TEXLET_HD constexpr int
texletWorkSize (int count)
{
  return 3 * count; // the SVD fit's centred points
}

/** \brief Computes one texlet. \a texlet is its Philox key (the centre pixel's index). */
template <typename S> PCL_TEXLET_HD void
computeTexlet (const Neighbourhood<S> &nb, const TexletSettings<S> &st, std::uint32_t texlet,
               unsigned char *mask, S *work, TexletResult<S> &out)
{
  out.ok = false;
  out.support = 0;
  const int min_support = st.min_support > 3 ? st.min_support : 3;
  if (nb.count < min_support)
    return;

  Plane<S> plane = {{S (0), S (0), S (0)}, S (0)};
  const int inliers = ransacPlane (nb.x, nb.y, nb.z, nb.count, st.ransac_iterations, st.threshold, st.seed, texlet, plane);
  if (inliers < min_support)
    return;

  PlaneMoments<S> m;
  m.reset (nb.point (0)); // any point of the patch keeps the sums small
  markInliers (plane, nb.x, nb.y, nb.z, nb.count, st.threshold, mask);
  for (int k = 0; k < nb.count; ++k)
    if (mask[k])
      m.add (nb.point (k));
  PlaneFit<S> fit;
  if (!fitPlanePca (m, fit))
    return;

  bool ring_use[7] = {false, false, false, false, false, false, false};
  if (st.fit == PlaneFitMethod::SVD)
  {
    int n = 0;
    for (int k = 0; k < nb.count; ++k)
      if (mask[k])
      {
        const Vec3<S> q = nb.point (k) - fit.P;
        work[3 * n + 0] = q.x;
        work[3 * n + 1] = q.y;
        work[3 * n + 2] = q.z;
        ++n;
      }
    if (!fitPlaneSvd (work, n, fit.P, fit))
      return;
  }
  else if (st.fit == PlaneFitMethod::Averaging)
  {
    for (int i = 0; i < 7; ++i)
      ring_use[i] = nb.ring_valid[i] && pointPlaneDistance (plane, nb.ring[i]) <= st.threshold;
    Vec3<S> n;
    if (!averagingNormal (nb.ring, ring_use, n))
      return;
    fit.N = n;
    fit.P = nb.ring[0];
  }

  Vec3<S> N = fit.N;
  if (dot (N, st.viewpoint - fit.P) < S (0))
    N = -N;
  Vec3<S> t1, t2;
  tangentFrame (N, t1, t2);

  switch (st.uncertainty)
  {
  case UncertaintyMethod::Analytic:
    if (st.fit == PlaneFitMethod::Averaging)
      analyticAveragingCovariance (nb, ring_use, N, t1, t2, out.cov_p, out.cov_n);
    else
      analyticPlaneCovariance (nb, mask, fit, t1, t2, out.cov_p, out.cov_n);
    break;
  case UncertaintyMethod::MonteCarlo:
    if (st.fit == PlaneFitMethod::PCA)
      monteCarloPcaCovariance (nb, mask, fit, st.samples, st.seed, texlet, N, t1, t2, out.cov_p, out.cov_n);
    else
      monteCarloCovariance (nb, mask, ring_use, st.fit, st.samples, st.seed, texlet, fit.P, N, t1, t2, work,
                          out.cov_p, out.cov_n);
    break;
  default:
    fillNaN (out.cov_p, 6);
    fillNaN (out.cov_n, 3);
  }

  const S sum = fit.lambda[0] + fit.lambda[1] + fit.lambda[2];
  out.P = fit.P;
  out.N = N;
  out.curvature = sum > S (0) ? fit.lambda[0] / sum : S (0);
  out.radius = std::sqrt (S (2) * (fit.lambda[1] + fit.lambda[2]));
  out.support = inliers;
  out.ok = true;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
