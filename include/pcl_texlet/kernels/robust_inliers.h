/*
 * pcl_texlet kernels: the inlier decision from the patch's own residual scale.
 *
 * The automatic RANSAC threshold is a multiple of the noise model's depth SD. Where the model
 * is too small for the data, that threshold rejects good points and makes texlets worse than a
 * plain least-squares fit. So after RANSAC, the inliers are refitted, and every disc point's
 * distance to that plane is measured. The patch's own noise scale is 1.4826 times the median
 * distance of the points within kRobustReach model thresholds (the points of other surfaces lie
 * beyond; the median is interpolated within a bin of a histogram of the distances), and the
 * threshold becomes the larger of the model's and robust_sigmas of that scale. The inliers are
 * then marked again against the refitted plane.
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

/** \brief Bins of the distances up to the reach: the median is interpolated within one. */
constexpr int kRobustBins = 64;

/** \brief The plane of \a fit (its normal through its P) as RANSAC's plane type. */
template <typename S> PCL_TEXLET_HD Plane<S>
planeOf (const PlaneFit<S> &fit)
{
  return {fit.N, -dot (fit.N, fit.P)};
}

/** \brief The bin of distance \a d for bins of 1 / \a inv_width (kRobustBins of them up to the
  * reach; beyond it: kRobustBins or more).
  */
template <typename S> PCL_TEXLET_HD int
distanceBin (S d, S inv_width)
{
  const S b = d * inv_width;
  return b < S (kRobustBins) ? static_cast<int> (b) : kRobustBins;
}

/** \brief The median of the distances below \a reach, interpolated within its bin:
  * \a below (b) counts the distances whose distanceBin() is below b (0 <= b <= kRobustBins).
  * \return 0 when there is none
  */
template <typename S, typename CountBelowBin> PCL_TEXLET_HD S
binnedMedian (S reach, const CountBelowBin &below)
{
  const int half = (below (kRobustBins) + 1) / 2;
  if (half == 0)
    return S (0);
  int lo = 0, hi = kRobustBins; // below (lo) < half <= below (hi)
  while (hi - lo > 1)
  {
    const int mid = (lo + hi) / 2;
    if (below (mid) >= half)
      hi = mid;
    else
      lo = mid;
  }
  const int c_lo = below (lo), c_hi = below (hi);
  return (S (lo) + S (half - c_lo) / S (c_hi - c_lo)) * (reach / S (kRobustBins));
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

/** \brief Refits the inliers (\a mask) of \a nb and marks them again against that plane with
  * robustThreshold() of the model's \a threshold.
  * \param work scratch of nb.count values (the distances)
  * \param plane, threshold, inliers RANSAC's, replaced by the refitted plane, its threshold and
  *        inlier count unless the inliers have no plane or fewer than \a min_support would remain
  *        (then the mask is RANSAC's again)
  * \param fit the refit (fitInliersPca() of the inliers it started from)
  * \return whether \a fit is the PCA plane of the inliers it leaves in \a mask (they have one, and
  *         the mask came back as it was)
  */
template <typename S> PCL_TEXLET_HD bool
refineInliers (const Neighbourhood<S> &nb, S sigmas, int min_support, S *work, unsigned char *mask, Plane<S> &plane,
               S &threshold, int &inliers, PlaneFit<S> &fit)
{
  if (!fitInliersPca (nb, mask, fit))
    return false;
  const Plane<S> refit = planeOf (fit);
  const int n = nb.count;
  const S *x = nb.x, *y = nb.y, *z = nb.z;
  for (int k = 0; k < n; ++k) // the operations of pointPlaneDistance, over the arrays
    work[k] = std::fabs (refit.n.x * x[k] + refit.n.y * y[k] + refit.n.z * z[k] + refit.d);
  const S reach = S (kRobustReach) * threshold, inv_width = S (kRobustBins) / reach;
  int cumulative[kRobustBins + 2] = {}; // cumulative[b + 1]: distances in bin b, then summed
  for (int k = 0; k < n; ++k)
    ++cumulative[distanceBin (work[k], inv_width) + 1];
  for (int b = 1; b <= kRobustBins; ++b)
    cumulative[b] += cumulative[b - 1];
  const S median = binnedMedian (reach, [&] (int b) { return cumulative[b]; });
  const S tau = robustThreshold (threshold, median, sigmas);
  int count = 0;
  bool changed = false;
  for (int k = 0; k < n; ++k)
  {
    const unsigned char in = work[k] <= tau ? 1 : 0;
    changed |= in != mask[k];
    mask[k] = in;
    count += in;
  }
  if (count < min_support)
  {
    markInliers (plane, x, y, z, n, threshold, mask); // RANSAC's inliers back
    return true;
  }
  plane = refit;
  threshold = tau;
  inliers = count;
  return !changed;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
