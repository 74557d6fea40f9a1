/*
 * pcl_texlet GPU: one warp per texlet (Strategy::Warp), for PCA and averaging fits.
 *
 * computeTexlet is sequential per texlet, so run one per thread (texletKernel) a texlet's
 * Monte Carlo re-fits stream its whole disc 50 times through local memory. Here the 32
 * lanes of a warp share one texlet: the disc is gathered into shared memory (in the CPU's
 * order, by ballot and prefix count), the lanes try RANSAC hypotheses in parallel (lane =
 * iteration) and run Monte Carlo samples in parallel (lane = sample), reading the points as
 * shared-memory broadcasts. The cheap sequential steps (moments, fit, analytic propagation)
 * run redundantly on every lane from the same data, so they need no broadcast. The per-
 * hypothesis and per-sample bodies are those of kernels::ransacPlane,
 * kernels::monteCarloCovariance (averaging) and kernels::monteCarloPcaCovariance (PCA: the
 * Gaussian moment model of kernels/pca_sampler.h, its sums over the inliers lane-strided and
 * reduced over the warp); the pieces are the kernels' own (distinctTriple, philoxWords,
 * normalQuad, PlaneMoments, fitPlanePca, averagingNormal, pcaModelPoint, PcaModelSums,
 * preparePcaSampleModel, pcaSampleNormals, pcaSampleRefit, SampleCovariance). RANSAC picks the
 * first iteration with the most inliers, as the sequential loop does, so the inliers are the
 * CPU's, and the Monte Carlo samples are the CPU's; only the order of the sums differs
 * (rounding).
 */
#pragma once

#include <pcl_texlet/gpu/frame_texlet.h>

namespace pcl
{
namespace gpu
{
namespace warp
{

constexpr unsigned kFull = 0xffffffffu;
constexpr int kWarpsPerBlock = 4;

/** Shared-memory bytes of one warp's disc of \a disc points. */
template <typename S> __host__ __device__ inline std::size_t
warpBytes (int disc)
{
  return (4 * sizeof (S) * static_cast<std::size_t> (disc) + static_cast<std::size_t> (disc) + 15) / 16 * 16;
}

template <typename S> __device__ inline S
warpSum (S v)
{
  for (int o = 16; o > 0; o >>= 1)
    v += __shfl_xor_sync (kFull, v, o);
  return v;
}

template <typename S>
__global__ void __launch_bounds__ (32 * kWarpsPerBlock)
texletWarpKernel (CloudView cloud, FrameTexletContext<S> ctx, kernels::HexGrid grid, DeviceTexlet *out,
                  unsigned int *made)
{
  namespace k = texlet::kernels;
  extern __shared__ __align__ (16) unsigned char smem[];
  const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
  const int i = blockIdx.x * kWarpsPerBlock + warp;
  if (i >= grid.size ())
    return; // the whole warp leaves together
  unsigned char *base = smem + warpBytes<S> (ctx.disc) * warp;
  S *xs = reinterpret_cast<S *> (base), *ys = xs + ctx.disc, *zs = ys + ctx.disc, *ss = zs + ctx.disc;
  unsigned char *mask = reinterpret_cast<unsigned char *> (ss + ctx.disc);

  int cu, cv;
  k::hexCentre (grid, i, cu, cv);
  const int w = cloud.width, h = cloud.height;
  const std::uint32_t centre = static_cast<std::uint32_t> (cv) * static_cast<std::uint32_t> (w) + cu;
  const bool need_sigma = ctx.params.uncertainty != texlet::UncertaintyMethod::None;
  const k::TexletSettings<S> &st = ctx.settings;

  // 1. The disc's valid points, compacted in disc order.
  int count = 0;
  for (int o0 = 0; o0 < ctx.disc; o0 += 32)
  {
    const int o = o0 + lane;
    bool valid = false;
    DevicePoint p;
    int u = 0, v = 0;
    if (o < ctx.disc)
    {
      u = cu + ctx.disc_du[o];
      v = cv + ctx.disc_dv[o];
      if (u >= 0 && v >= 0 && u < w && v < h)
      {
        p = cloud.at (u, v);
        valid = isValidDevicePoint (p);
      }
    }
    const unsigned ballot = __ballot_sync (kFull, valid);
    if (valid)
    {
      const int pos = count + __popc (ballot & ((1u << lane) - 1u));
      xs[pos] = p.x;
      ys[pos] = p.y;
      zs[pos] = p.z;
      if (need_sigma)
        ss[pos] = static_cast<S> (ctx.sigmaMetres (u, v, p.z));
    }
    count += __popc (ballot);
  }
  __syncwarp ();

  DeviceTexlet t;
  bool ok = false;
  if (count > 0)
  {
    k::Neighbourhood<S> nb;
    nb.x = xs;
    nb.y = ys;
    nb.z = zs;
    nb.sigma = need_sigma ? ss : nullptr;
    nb.count = count;
    double zsum = 0.0; // in the CPU's order, so the threshold is the CPU's to the bit
    for (int q = 0; q < count; ++q)
      zsum += static_cast<float> (zs[q]);
    for (int r = 0; r < 7; ++r)
    {
      int du = 0, dv = 0;
      if (r > 0)
        k::hexNeighbourOffset (r - 1, ctx.params.radius, du, dv);
      const int u = cu + du, v = cv + dv;
      nb.ring_valid[r] = false;
      nb.ring[r] = {S (0), S (0), S (0)};
      nb.ring_sigma[r] = S (0);
      if (u < 0 || v < 0 || u >= w || v >= h || !isValidDevicePoint (cloud.at (u, v)))
        continue;
      const DevicePoint &p = cloud.at (u, v);
      nb.ring[r] = {S (p.x), S (p.y), S (p.z)};
      nb.ring_valid[r] = true;
      nb.ring_sigma[r] = static_cast<S> (ctx.sigmaMetres (u, v, p.z));
    }
    const S threshold = static_cast<S> (ctx.params.ransac_threshold > 0.0
                                            ? ctx.params.ransac_threshold
                                            : ctx.params.threshold_sigmas * ctx.sigmaMetres (cu, cv, zsum / count));
    const int min_support = st.min_support > 3 ? st.min_support : 3;

    // 2. RANSAC, lane = iteration; the first iteration with the most inliers wins.
    k::Plane<S> plane = {{S (0), S (0), S (0)}, S (0)};
    int best = 0;
    if (count >= min_support)
      for (int it0 = 0; it0 < st.ransac_iterations; it0 += 32)
      {
        const int it = it0 + lane;
        int inliers = 0;
        k::Plane<S> hyp = {{S (0), S (0), S (0)}, S (0)};
        if (it < st.ransac_iterations)
        {
          int ia, ib, ic;
          k::distinctTriple (k::philoxWords (st.seed, centre, static_cast<std::uint32_t> (it), 0u, k::RandomStream::Ransac),
                             count, ia, ib, ic);
          const k::Vec3<S> pa = {xs[ia], ys[ia], zs[ia]};
          const k::Vec3<S> ab = k::make3 (xs[ib], ys[ib], zs[ib]) - pa, ac = k::make3 (xs[ic], ys[ic], zs[ic]) - pa;
          const k::Vec3<S> c = k::cross (ab, ac);
          const S c2 = k::squaredNorm (c);
          if (c2 > S (1e-10) * k::squaredNorm (ab) * k::squaredNorm (ac))
          {
            hyp.n = (S (1) / std::sqrt (c2)) * c;
            hyp.d = -k::dot (hyp.n, pa);
            for (int q = 0; q < count; ++q)
              inliers += k::pointPlaneDistance (hyp, k::make3 (xs[q], ys[q], zs[q])) <= threshold ? 1 : 0;
          }
        }
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

    k::PlaneFit<S> fit;
    bool fitted = false;
    bool ring_use[7] = {false, false, false, false, false, false, false};
    if (best >= min_support)
    {
      // 3. Inliers, moments and the fit (every lane, same data, same result).
      for (int q = lane; q < count; q += 32)
        mask[q] = k::pointPlaneDistance (plane, nb.point (q)) <= threshold ? 1 : 0;
      __syncwarp ();
      k::PlaneMoments<S> m;
      m.reset (nb.point (0));
      for (int q = 0; q < count; ++q)
        if (mask[q])
          m.add (nb.point (q));
      fitted = k::fitPlanePca (m, fit);
      if (fitted && st.fit == texlet::PlaneFitMethod::Averaging)
      {
        for (int r = 0; r < 7; ++r)
          ring_use[r] = nb.ring_valid[r] && k::pointPlaneDistance (plane, nb.ring[r]) <= threshold;
        k::Vec3<S> n;
        fitted = k::averagingNormal (nb.ring, ring_use, n);
        fit.N = n;
        fit.P = nb.ring[0];
      }
    }

    if (fitted)
    {
      k::Vec3<S> N = fit.N;
      if (k::dot (N, st.viewpoint - fit.P) < S (0))
        N = -N;
      k::Vec3<S> t1, t2;
      k::tangentFrame (N, t1, t2);
      S cov_p[6], cov_n[3];
      if (st.uncertainty == texlet::UncertaintyMethod::Analytic)
      {
        if (st.fit == texlet::PlaneFitMethod::Averaging)
          k::analyticAveragingCovariance (nb, ring_use, N, t1, t2, cov_p, cov_n);
        else
          k::analyticPlaneCovariance (nb, mask, fit, t1, t2, cov_p, cov_n);
      }
      else if (st.uncertainty == texlet::UncertaintyMethod::MonteCarlo)
      {
        // 4. Monte Carlo, lane = sample, sums reduced over the warp.
        k::SampleCovariance<S> acc;
        acc.reset ();
        if (st.fit == texlet::PlaneFitMethod::Averaging)
        {
          // monteCarloCovariance's body.
          float g[4];
          for (int s = lane; s < st.samples; s += 32)
          {
            k::Vec3<S> ring[7], Ns;
            for (int r = 0; r < 7; ++r)
            {
              if ((r & 3) == 0)
                k::normalQuad (st.seed, centre, static_cast<std::uint32_t> (s), static_cast<std::uint32_t> (r >> 2), g);
              ring[r] = ring_use[r] ? (S (1) + S (g[r & 3]) * nb.ring_sigma[r] / nb.ring[r].z) * nb.ring[r] : nb.ring[r];
            }
            if (!k::averagingNormal (ring, ring_use, Ns))
              continue;
            if (k::dot (Ns, N) < S (0))
              Ns = -Ns;
            acc.add (ring[0] - fit.P, k::dot (Ns, t1), k::dot (Ns, t2));
          }
        }
        else
        {
          // monteCarloPcaCovariance's pieces (kernels/pca_sampler.h): the model's sums over the
          // inliers, lane-strided and reduced over the warp, then the same samples as the CPU
          // (draws (seed, texlet, sample, block 0..3)), one per lane.
          const k::Vec3<S> axes[3] = {fit.N, fit.e1, fit.e2};
          const S P0b[3] = {k::dot (axes[0], fit.P), k::dot (axes[1], fit.P), k::dot (axes[2], fit.P)};
          k::PcaModelSums<S> sums;
          sums.reset ();
          int n_in = 0;
          for (int q = lane; q < count; q += 32)
          {
            S qb[3], ab[3];
            k::pcaModelPoint (nb, mask, q, fit.P, axes, P0b, qb, ab);
            sums.add (qb, ab);
            n_in += mask[q] ? 1 : 0;
          }
          for (int j = 0; j < k::PcaModelSums<S>::kCount; ++j)
            sums.v[j] = warpSum (sums.v[j]);
          n_in = warpSum (n_in);
          if (n_in >= 3)
          {
            k::PcaSampleModel<S> md;
            k::preparePcaSampleModel (sums, n_in, fit, N, t1, t2, md);
            for (int s = lane; s < st.samples; s += 32)
            {
              S z[k::kPcaSampleNormals], a1, a2;
              k::Vec3<S> dP;
              k::pcaSampleNormals (st.seed, centre, static_cast<std::uint32_t> (s), z);
              if (k::pcaSampleRefit (md, z, dP, a1, a2))
                acc.add (dP, a1, a2);
            }
          }
        }
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
        acc.finish (cov_p, cov_n);
      }
      else
      {
        k::fillNaN (cov_p, 6);
        k::fillNaN (cov_n, 3);
      }

      if (lane == 0)
      {
        const S sum = fit.lambda[0] + fit.lambda[1] + fit.lambda[2];
        t.x = static_cast<float> (fit.P.x);
        t.y = static_cast<float> (fit.P.y);
        t.z = static_cast<float> (fit.P.z);
        t.data_w = 1.0f;
        t.normal_x = static_cast<float> (N.x);
        t.normal_y = static_cast<float> (N.y);
        t.normal_z = static_cast<float> (N.z);
        t.data_nw = 0.0f;
        t.curvature = static_cast<float> (sum > S (0) ? fit.lambda[0] / sum : S (0));
        t.data_c2 = t.data_c3 = 0.0f;
        t.radius = static_cast<float> (std::sqrt (S (2) * (fit.lambda[1] + fit.lambda[2])));
        t.support = static_cast<std::uint32_t> (best);
        t.cov_p_xx = static_cast<float> (cov_p[0]);
        t.cov_p_xy = static_cast<float> (cov_p[1]);
        t.cov_p_xz = static_cast<float> (cov_p[2]);
        t.cov_p_yy = static_cast<float> (cov_p[3]);
        t.cov_p_yz = static_cast<float> (cov_p[4]);
        t.cov_p_zz = static_cast<float> (cov_p[5]);
        t.cov_n_11 = static_cast<float> (cov_n[0]);
        t.cov_n_12 = static_cast<float> (cov_n[1]);
        t.cov_n_22 = static_cast<float> (cov_n[2]);
        t.pixel_index = centre;
        t.rgba = 0;
        if (ctx.colour)
        {
          unsigned rs = 0, gs = 0, bs = 0, n = 0;
          int q = 0;
          for (int o = 0; o < ctx.disc; ++o)
          {
            const int u = cu + ctx.disc_du[o], v = cv + ctx.disc_dv[o];
            if (u < 0 || v < 0 || u >= w || v >= h)
              continue;
            const DevicePoint &p = cloud.at (u, v);
            if (!isValidDevicePoint (p))
              continue;
            if (mask[q++])
            {
              rs += (p.rgba >> 16) & 0xffu;
              gs += (p.rgba >> 8) & 0xffu;
              bs += p.rgba & 0xffu;
              ++n;
            }
          }
          t.rgba = (0xffu << 24) | (((rs + n / 2) / n) << 16) | (((gs + n / 2) / n) << 8) | ((bs + n / 2) / n);
        }
      }
      ok = true;
    }
  }
  if (lane == 0)
  {
    if (!ok)
      failTexlet (centre, t);
    out[i] = t;
    if (ok)
      atomicAdd (made, 1u);
  }
}

} // namespace warp
} // namespace gpu
} // namespace pcl
