/*
 * pcl_texlet GPU: one warp per texlet (Strategy::Warp), for PCA and averaging fits.
 *
 * One thread per texlet (texletKernel) streams a texlet's whole disc through local memory for
 * every Monte Carlo re-fit. Here the 32 lanes of a warp share one texlet and spread the texlet
 * stages (kernels/texlet_stages.h, kernels/texlet_kernel.h) over themselves: the disc is
 * gathered into shared memory in the CPU's order (visitDiscPixel per lane, compacted by ballot
 * and prefix count), the depth SDs and the inlier mask are lane-strided, the RANSAC hypotheses
 * run one a lane (ransacHypothesis; the first with the most inliers wins, as in the sequential
 * loop, so the inliers are the CPU's) and the Monte Carlo samples one a lane (averagingSample,
 * or the Gaussian moment model's addPcaModelPoints and addPcaSample for PCA), their sums
 * reduced over the warp. The cheap sequential stages (fit, orientation, analytic propagation,
 * finish) run on every lane from the same data. Only the order of the sums differs from the
 * CPU's (rounding).
 */
#pragma once

#include <pcl_texlet/gpu/frame_texlet.h>

namespace pcl
{
namespace texlet
{
namespace gpu
{
namespace warp
{

constexpr unsigned kFull = 0xffffffffu;
constexpr int kWarpsPerBlock = 4;

/** Shared-memory bytes of one warp's disc of \a disc points: x, y, z, sigma, pixel, mask. */
template <typename S> __host__ __device__ inline std::size_t
warpBytes (int disc)
{
  return ((4 * sizeof (S) + sizeof (int) + 1) * static_cast<std::size_t> (disc) + 15) / 16 * 16;
}

/** One warp's disc in its slice \a base of shared memory (no SVD work: the warp has no SVD). */
template <typename S> __device__ inline kernels::TexletScratch<S>
warpScratch (unsigned char *base, int disc)
{
  S *x = reinterpret_cast<S *> (base);
  int *pixel = reinterpret_cast<int *> (x + 4 * disc);
  return {x, x + disc, x + 2 * disc, x + 3 * disc, nullptr, pixel, reinterpret_cast<unsigned char *> (pixel + disc)};
}

template <typename S> __device__ inline S
warpSum (S v)
{
  for (int o = 16; o > 0; o >>= 1)
    v += __shfl_xor_sync (kFull, v, o);
  return v;
}

/** The sums of \a acc over the warp's lanes, on every lane. */
template <typename S> __device__ inline void
warpReduce (kernels::SampleCovariance<S> &acc)
{
  for (int q = 0; q < 3; ++q)
  {
    acc.sp[q] = warpSum (acc.sp[q]);
    acc.saa[q] = warpSum (acc.saa[q]);
  }
  for (int q = 0; q < 6; ++q)
    acc.spp[q] = warpSum (acc.spp[q]);
  acc.sa[0] = warpSum (acc.sa[0]);
  acc.sa[1] = warpSum (acc.sa[1]);
  acc.n = warpSum (acc.n);
}

/** The RANSAC plane of the \a count gathered points, hypothesis = lane; 0 below min_support. */
template <typename S> __device__ inline int
warpRansac (const kernels::TexletScratch<S> &ws, int count, const kernels::TexletSettings<S> &st, S threshold,
            std::uint32_t centre, int lane, kernels::Plane<S> &plane)
{
  namespace k = texlet::kernels;
  int best = 0;
  if (count < k::minSupport (st))
    return 0;
  for (int it0 = 0; it0 < st.ransac_iterations; it0 += 32)
  {
    const int it = it0 + lane;
    int inliers = 0;
    k::Plane<S> hyp = {{S (0), S (0), S (0)}, S (0)};
    if (it < st.ransac_iterations && k::ransacHypothesis (ws.x, ws.y, ws.z, count, k::ransacWords (st.seed, centre, it), hyp))
      inliers = k::countInliers (hyp, ws.x, ws.y, ws.z, 0, count, threshold);
    // Most inliers, then the lowest iteration: key = inliers * 32 + (31 - lane).
    int key = inliers * 32 + (31 - lane);
    for (int o = 16; o > 0; o >>= 1)
      key = max (key, __shfl_xor_sync (kFull, key, o));
    const int winner = 31 - (key & 31), most = key >> 5;
    if (most > best)
    {
      best = most;
      plane.n.x = __shfl_sync (kFull, hyp.n.x, winner);
      plane.n.y = __shfl_sync (kFull, hyp.n.y, winner);
      plane.n.z = __shfl_sync (kFull, hyp.n.z, winner);
      plane.d = __shfl_sync (kFull, hyp.d, winner);
    }
  }
  return best;
}

/** refineInliers() over the warp: the refit and threshold on every lane, the distances and the
  * mask lane-strided (the warp has no scratch for the distances: they are recomputed, and the
  * median's bin counts are found by bisection instead of a histogram).
  */
template <typename S> __device__ inline bool
warpRefineInliers (const kernels::Neighbourhood<S> &nb, S sigmas, int min_support, int lane, unsigned char *mask,
                   kernels::Plane<S> &plane, S &threshold, int &inliers, kernels::PlaneFit<S> &fit)
{
  namespace k = texlet::kernels;
  if (!k::fitInliersPca (nb, mask, fit))
    return false;
  const k::Plane<S> refit = k::planeOf (fit);
  const S reach = S (k::kRobustReach) * threshold, inv_width = S (k::kRobustBins) / reach;
  auto below = [&] (int b) {
    int c = 0;
    for (int q = lane; q < nb.count; q += 32)
      c += k::distanceBin (k::pointPlaneDistance (refit, nb.point (q)), inv_width) < b ? 1 : 0;
    return warpSum (c);
  };
  const S tau = k::robustThreshold (threshold, k::binnedMedian (reach, below), sigmas);
  int count = 0;
  for (int q = lane; q < nb.count; q += 32)
    count += k::pointPlaneDistance (refit, nb.point (q)) <= tau ? 1 : 0;
  count = warpSum (count);
  if (count < min_support)
    return true; // the mask is still RANSAC's
  __syncwarp ();
  bool changed = false;
  for (int q = lane; q < nb.count; q += 32)
  {
    const unsigned char in = k::pointPlaneDistance (refit, nb.point (q)) <= tau ? 1 : 0;
    changed |= in != mask[q];
    mask[q] = in;
  }
  changed = __any_sync (kFull, changed);
  __syncwarp ();
  plane = refit;
  threshold = tau;
  inliers = count;
  return !changed;
}

/** Monte Carlo covariances, sample = lane, the sums reduced over the warp. */
template <typename S> __device__ inline void
warpMonteCarlo (const kernels::Neighbourhood<S> &nb, const unsigned char *mask, const bool ring_use[7],
                const kernels::PlaneFit<S> &fit, const kernels::TexletCentrePoint<S> &point,
                const kernels::TexletSettings<S> &st, std::uint32_t centre, int lane, S cov_p[6], S cov_n[3])
{
  namespace k = texlet::kernels;
  const k::Vec3<S> &N = point.N0, &t1 = point.t1, &t2 = point.t2;
  k::SampleCovariance<S> acc;
  acc.reset (point);
  if (st.fit == texlet::PlaneFitMethod::Averaging)
    for (int s = lane; s < st.samples; s += 32)
    {
      k::Vec3<S> P, Ns;
      // The device's noise is never shared (frame_texlet.h): no ring correlation to draw.
      if (k::averagingSample<S> (nb, ring_use, nullptr, st.seed, centre, s, P, Ns))
        k::addMonteCarloSample (P, Ns, fit.P, N, t1, t2, acc);
    }
  else
  {
    // The Gaussian moment model of kernels/pca_sampler.h: its sums over the inliers
    // lane-strided and reduced, then the CPU's samples (draws (seed, texlet, sample, block 0..3)).
    k::PcaModelSums<S> sums;
    sums.reset ();
    const int n_in = warpSum (k::addPcaModelPoints (nb, mask, k::pcaModelBasis (fit), lane, 32, sums));
    for (int j = 0; j < k::PcaModelSums<S>::kCount; ++j)
      sums.v[j] = warpSum (sums.v[j]);
    if (n_in >= 3)
    {
      k::PcaSampleModel<S> md;
      k::preparePcaSampleModel (sums, n_in, nb.shared_fraction, fit, N, t1, t2, md);
      for (int s = lane; s < st.samples; s += 32)
        k::addPcaSample (md, st.seed, centre, s, acc);
    }
  }
  warpReduce (acc);
  acc.finish (cov_p, cov_n);
}

template <typename S>
__global__ void __launch_bounds__ (32 * kWarpsPerBlock)
texletWarpKernel (DeviceFrame frame, kernels::FrameSettings<S> fs, kernels::HexGrid grid, DeviceTexlet *out,
                  unsigned int *made)
{
  namespace k = texlet::kernels;
  extern __shared__ __align__ (16) unsigned char smem[];
  const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
  const int i = blockIdx.x * kWarpsPerBlock + warp;
  if (i >= grid.size ())
    return; // the whole warp leaves together
  const int disc = fs.disc.size;
  const k::TexletScratch<S> ws = warpScratch<S> (smem + warpBytes<S> (disc) * warp, disc);
  int cu, cv;
  k::hexCentre (grid, i, cu, cv);
  const std::uint32_t centre = static_cast<std::uint32_t> (cv) * static_cast<std::uint32_t> (frame.width ()) + cu;
  const k::TexletSettings<S> &st = fs.kernel;

  // 1. The disc's valid points, compacted in disc order.
  int count = 0;
  for (int o0 = 0; o0 < disc; o0 += 32)
  {
    const int o = o0 + lane;
    DevicePoint p;
    int index = 0;
    const bool valid = o < disc && k::visitDiscPixel (frame, fs.disc, cu, cv, o, [&] (const DevicePoint &q, int at) {
                         p = q;
                         index = at;
                       });
    const unsigned ballot = __ballot_sync (kFull, valid);
    if (valid)
      k::storePoint (ws, count + __popc (ballot & ((1u << lane) - 1u)), p, index);
    count += __popc (ballot);
  }
  __syncwarp ();

  DeviceTexlet t;
  bool ok = false;
  if (count > 0)
  {
    k::Neighbourhood<S> nb;
    nb.x = ws.x;
    nb.y = ws.y;
    nb.z = ws.z;
    nb.count = count;
    k::gatherRing (frame, fs, cu, cv, nb);
    k::gatherCentreRay (frame, cu, cv, nb);
    if (fs.need_sigma)
    {
      k::pointSigmas (frame, ws, lane, count, 32);
      __syncwarp ();
      nb.sigma = ws.sigma;
    }
    const double zsum = k::depthSum (ws.z, count);
    const k::CentreNoise noise = frame.centreNoise (cu, cv, zsum / count);
    k::discSharedNoise (noise, ws.pixel, frame.width (), nb);
    S threshold = k::ransacThreshold (fs, noise, nb);

    // 2. RANSAC, lane = hypothesis.
    k::Plane<S> plane = {{S (0), S (0), S (0)}, S (0)};
    int best = warpRansac (ws, count, st, threshold, centre, lane, plane);

    // 3. The inliers (lane-strided), then the fit on every lane: PCA, and for averaging the ring.
    k::PlaneFit<S> fit;
    bool fitted = false;
    bool ring_use[7] = {false, false, false, false, false, false, false};
    if (best >= k::minSupport (st))
    {
      for (int q = lane; q < count; q += 32)
        ws.mask[q] = k::isInlier (plane, nb.point (q), threshold) ? 1 : 0;
      __syncwarp ();
      // The refinement's refit is the inliers' PCA plane when it left them as they were.
      const bool pca_fitted =
          (st.robust_sigmas > S (0) &&
           warpRefineInliers (nb, st.robust_sigmas, k::minSupport (st), lane, ws.mask, plane, threshold, best, fit)) ||
          k::fitInliersPca (nb, ws.mask, fit);
      fitted = pca_fitted &&
               (st.fit != texlet::PlaneFitMethod::Averaging || k::averageRingNormal (nb, plane, threshold, ring_use, fit));
    }

    if (fitted)
    {
      const k::Vec3<S> N = k::faceViewpoint (fit.N, fit.P, st.viewpoint);
      k::Vec3<S> t1, t2;
      k::tangentFrame (N, t1, t2);
      const k::TexletCentrePoint<S> point = k::texletCentre (nb, fit, N, t1, t2, st.centre, st.fit);
      k::TexletResult<S> r;
      // 4. The uncertainty: Monte Carlo over the lanes, the others on every lane.
      if (st.uncertainty == texlet::UncertaintyMethod::MonteCarlo)
        warpMonteCarlo (nb, ws.mask, ring_use, fit, point, st, centre, lane, r.cov_p, r.cov_n);
      else if (st.uncertainty == texlet::UncertaintyMethod::Analytic)
        k::analyticCovariance (nb, ws.mask, ring_use, st.fit, fit, point, r.cov_p, r.cov_n);
      else
      {
        k::fillNaN (r.cov_p, 6);
        k::fillNaN (r.cov_n, 3);
      }
      k::finishTexlet (fit, point, best, r);
      if (fs.need_sigma)
        k::scaleCovariances (frame.varianceScale (cu, cv, r), r);
      if (lane == 0)
        k::writeTexlet (r, k::meanColour (frame, ws.pixel, ws.mask, count), centre, t);
      ok = true;
    }
  }
  if (lane == 0)
  {
    if (!ok)
      k::writeFailedTexlet (centre, t);
    out[i] = t;
    if (ok)
      atomicAdd (made, 1u);
  }
}

} // namespace warp
} // namespace gpu
} // namespace texlet
} // namespace pcl
