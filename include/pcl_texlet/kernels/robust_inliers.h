/*
 * pcl_texlet kernels: the inlier decision from the patch's own residual scale.
 *
 * The automatic RANSAC threshold is a multiple of the noise model's depth SD. Where the model
 * is too small for the data, that threshold rejects good points and makes texlets worse than a
 * plain least-squares fit. So after RANSAC, the inliers are refitted, and every disc point's
 * distance to that plane is measured. The patch's own noise scale is 1.4826 times the median
 * distance of the points within kRobustReach model thresholds (the points of other surfaces lie
 * beyond), and the threshold becomes the larger of the model's and the same multiple of that
 * scale. The inliers are then marked again against the refitted plane.
 * (docs/texlet_covariances.md.)
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/plane_fit.h>
#include <pcl_texlet/kernels/ransac.h>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief How far, in model thresholds, a point may lie from the refitted plane and still count
  * toward the patch's noise scale: the scale it can find is at most this many times the model's.
  */
constexpr int kRobustReach = 4;

/** \brief Refit-and-mark passes after RANSAC. */
constexpr int kRobustPasses = 2;

/** \brief Bisection steps of the median distance: its resolution is 2^-12 of the reach. */
constexpr int kRobustMedianSteps = 12;

/** \brief The plane of \a fit (its normal through its P) as RANSAC's plane type. */
template <typename S> PCL_TEXLET_HD Plane<S>
planeOf (const PlaneFit<S> &fit)
{
  return {fit.N, -dot (fit.N, fit.P)};
}

/** \brief The median of the distances below \a reach, by bisection: \a below (t) counts the
  * distances below t. \return 0 when there is none
  */
template <typename S, typename CountBelow> PCL_TEXLET_HD S
truncatedMedian (S reach, const CountBelow &below)
{
  const int half = (below (reach) + 1) / 2;
  S lo = S (0), hi = reach;
  if (half == 0)
    return S (0);
  for (int step = 0; step < kRobustMedianSteps; ++step)
  {
    const S mid = S (0.5) * (lo + hi);
    if (below (mid) >= half)
      hi = mid;
    else
      lo = mid;
  }
  return S (0.5) * (lo + hi);
}

/** \brief The inlier threshold from the model's \a threshold and the median distance \a median
  * of the patch's points: the larger of the model's and \a sigmas times the patch's own scale.
  */
template <typename S> PCL_TEXLET_HD S
robustThreshold (S threshold, S median, S sigmas)
{
  const S own = sigmas * S (1.4826) * median;
  return own > threshold ? own : threshold;
}

/** \brief One pass of refineInliers(). \return false (nothing changed) where the inliers have
  * no plane or fewer than \a min_support points would remain
  */
template <typename S> PCL_TEXLET_HD bool
refineInliersOnce (const Neighbourhood<S> &nb, S sigmas, S model_threshold, int min_support, S *work,
                   unsigned char *mask, Plane<S> &plane, S &threshold, int &inliers)
{
  PlaneMoments<S> m;
  m.reset (nb.point (0));
  for (int k = 0; k < nb.count; ++k)
    if (mask[k])
      m.add (nb.point (k));
  PlaneFit<S> fit;
  if (!fitPlanePca (m, fit))
    return false;
  const Plane<S> refit = planeOf (fit);
  const int n = nb.count;
  for (int k = 0; k < n; ++k)
    work[k] = pointPlaneDistance (refit, nb.point (k));
  const S median = truncatedMedian (S (kRobustReach) * model_threshold, [&] (S t) {
    int c = 0;
    for (int k = 0; k < n; ++k)
      c += work[k] < t ? 1 : 0;
    return c;
  });
  const S tau = robustThreshold (model_threshold, median, sigmas);
  int count = 0;
  for (int k = 0; k < n; ++k)
    count += work[k] <= tau ? 1 : 0;
  if (count < min_support)
    return false;
  for (int k = 0; k < n; ++k)
    mask[k] = work[k] <= tau ? 1 : 0;
  plane = refit;
  threshold = tau;
  inliers = count;
  return true;
}

/** \brief Refits the inliers (\a mask) of \a nb and marks them again against that plane with
  * robustThreshold() of the model's \a threshold, kRobustPasses times (a few inliers more or
  * fewer move the plane, and so the distances).
  * \param work scratch of nb.count values (the distances)
  * \param plane, threshold, inliers RANSAC's, replaced by the last refitted plane, its threshold
  *        and inlier count (those of the last pass that left at least \a min_support points)
  */
template <typename S> PCL_TEXLET_HD void
refineInliers (const Neighbourhood<S> &nb, S sigmas, int min_support, S *work, unsigned char *mask, Plane<S> &plane,
               S &threshold, int &inliers)
{
  const S model_threshold = threshold;
  for (int pass = 0; pass < kRobustPasses; ++pass)
    if (!refineInliersOnce (nb, sigmas, model_threshold, min_support, work, mask, plane, threshold, inliers))
      return;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
