/*
 * pcl_texlet kernels: one texlet from its neighbourhood (paper, Sect. 3.2, steps 2 and 3).
 *
 * RANSAC marks the inliers (then, with the automatic threshold, the patch's own residual scale
 * may widen them, robust_inliers.h), the chosen fit gives the plane and N, N is turned toward the
 * viewpoint, the centre definition gives P (centre_ray.h), and the chosen propagation gives
 * Sigma_P and Sigma_N. Each step is a stage function of its own, so the GPU's warp strategy can
 * spread them over lanes (src/gpu/texlet_warp_kernel.cuh) without restating them.
 * computeTexlet() allocates nothing: the caller passes an inlier mask of nb.count bytes and a
 * work buffer of texletWorkSize (nb.count) values.
 */
#pragma once

#include <pcl_texlet/kernels/centre_ray.h>
#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/plane_fit.h>
#include <pcl_texlet/kernels/ransac.h>
#include <pcl_texlet/kernels/robust_inliers.h>
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
  S robust_sigmas = S (0);       ///< > 0: refineInliers() with this many of the patch's own SDs
  PlaneFitMethod fit = PlaneFitMethod::PCA;
  TexletCentre centre = TexletCentre::CentreRay;
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

/** \brief Fewest RANSAC inliers that make a texlet: the setting, but never under 3. */
template <typename S> PCL_TEXLET_HD int
minSupport (const TexletSettings<S> &st)
{
  return st.min_support > 3 ? st.min_support : 3;
}

/** \brief Replaces the PCA plane \a fit of the inliers by their SVD plane (centred on the
  * same mean). \param work scratch of texletWorkSize (nb.count) values
  */
template <typename S> PCL_TEXLET_HD bool
refitInliersSvd (const Neighbourhood<S> &nb, const unsigned char *mask, S *work, PlaneFit<S> &fit)
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
  return fitPlaneSvd (work, n, fit.P, fit);
}

/** \brief Replaces the normal and centre of \a fit by normal averaging (Eq. 5) over the ring
  * points that are inliers of the RANSAC \a plane (\a ring_use), centred on the ring's centre.
  * The PCA eigenvalues stay: they give curvature and radius.
  */
template <typename S> PCL_TEXLET_HD bool
averageRingNormal (const Neighbourhood<S> &nb, const Plane<S> &plane, S threshold, bool ring_use[7], PlaneFit<S> &fit)
{
  for (int i = 0; i < 7; ++i)
    ring_use[i] = nb.ring_valid[i] && isInlier (plane, nb.ring[i], threshold);
  Vec3<S> n;
  if (!averagingNormal (nb.ring, ring_use, n))
    return false;
  fit.N = n;
  fit.P = nb.ring[0];
  return true;
}

/** \brief The plane fit \a method of the inliers (\a mask) of the RANSAC \a plane from their PCA
  * plane \a fit (fitInliersPca()): PCA keeps it, SVD refits it and averaging takes the ring's
  * normal (\a ring_use: which ring points it used; none for PCA and SVD).
  * \return false where no plane is defined
  */
template <typename S> PCL_TEXLET_HD bool
fitByMethod (const Neighbourhood<S> &nb, const unsigned char *mask, const Plane<S> &plane, S threshold,
             PlaneFitMethod method, S *work, PlaneFit<S> &fit, bool ring_use[7])
{
  for (int i = 0; i < 7; ++i)
    ring_use[i] = false;
  if (method == PlaneFitMethod::SVD)
    return refitInliersSvd (nb, mask, work, fit);
  if (method == PlaneFitMethod::Averaging)
    return averageRingNormal (nb, plane, threshold, ring_use, fit);
  return true;
}

/** \brief \a n or -n, whichever faces \a viewpoint from \a P. */
template <typename S> PCL_TEXLET_HD Vec3<S>
faceViewpoint (const Vec3<S> &n, const Vec3<S> &P, const Vec3<S> &viewpoint)
{
  return dot (n, viewpoint - P) < S (0) ? -n : n;
}

/** \brief Sigma_P and Sigma_N of the fit by the settings' uncertainty method (NaN for None), of
  * the texlet's \a centre (its N0, t1, t2: the texlet's normal, facing the viewpoint, and tangents).
  */
template <typename S> PCL_TEXLET_HD void
texletUncertainty (const Neighbourhood<S> &nb, const unsigned char *mask, const bool ring_use[7],
                   const PlaneFit<S> &fit, const TexletCentrePoint<S> &centre, const TexletSettings<S> &st,
                   std::uint32_t texlet, S *work, S cov_p[6], S cov_n[3])
{
  switch (st.uncertainty)
  {
  case UncertaintyMethod::Analytic:
    analyticCovariance (nb, mask, ring_use, st.fit, fit, centre, cov_p, cov_n);
    break;
  case UncertaintyMethod::MonteCarlo:
    if (st.fit == PlaneFitMethod::PCA)
      monteCarloPcaCovariance (nb, mask, fit, st.samples, st.seed, texlet, centre, cov_p, cov_n);
    else
      monteCarloCovariance (nb, mask, ring_use, st.fit, st.samples, st.seed, texlet, fit.P, centre, work, cov_p, cov_n);
    break;
  default:
    fillNaN (cov_p, 6);
    fillNaN (cov_n, 3);
  }
}

/** \brief The texlet's P, N, curvature, radius and support from its fit and \a centre
  * (covariances aside).
  */
template <typename S> PCL_TEXLET_HD void
finishTexlet (const PlaneFit<S> &fit, const TexletCentrePoint<S> &centre, int inliers, TexletResult<S> &out)
{
  const S sum = fit.lambda[0] + fit.lambda[1] + fit.lambda[2];
  out.P = centre.P;
  out.N = centre.N0;
  out.curvature = sum > S (0) ? fit.lambda[0] / sum : S (0);
  out.radius = std::sqrt (S (2) * (fit.lambda[1] + fit.lambda[2]));
  out.support = inliers;
  out.ok = true;
}

/** \brief Computes one texlet. \a texlet is its Philox key (the centre pixel's index). */
template <typename S> PCL_TEXLET_HD void
computeTexlet (const Neighbourhood<S> &nb, const TexletSettings<S> &st, std::uint32_t texlet,
               unsigned char *mask, S *work, TexletResult<S> &out)
{
  out.ok = false;
  out.support = 0;
  const int min_support = minSupport (st);
  if (nb.count < min_support)
    return;

  Plane<S> plane = {{S (0), S (0), S (0)}, S (0)};
  const int inliers = ransacPlane (nb.x, nb.y, nb.z, nb.count, st.ransac_iterations, st.threshold, st.seed, texlet, plane);
  if (inliers < min_support)
    return;

  markInliers (plane, nb.x, nb.y, nb.z, nb.count, st.threshold, mask);
  S threshold = st.threshold;
  int support = inliers;
  PlaneFit<S> fit;
  // The refinement's refit is the inliers' PCA plane when it left them as they were.
  const bool pca_fitted = (st.robust_sigmas > S (0) &&
                           refineInliers (nb, st.robust_sigmas, min_support, work, mask, plane, threshold, support, fit)) ||
                          fitInliersPca (nb, mask, fit);
  bool ring_use[7];
  if (!pca_fitted || !fitByMethod (nb, mask, plane, threshold, st.fit, work, fit, ring_use))
    return;
  const Vec3<S> N = faceViewpoint (fit.N, fit.P, st.viewpoint);
  Vec3<S> t1, t2;
  tangentFrame (N, t1, t2);
  const TexletCentrePoint<S> centre = texletCentre (nb, fit, N, t1, t2, st.centre, st.fit);
  texletUncertainty (nb, mask, ring_use, fit, centre, st, texlet, work, out.cov_p, out.cov_n);
  finishTexlet (fit, centre, support, out);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
