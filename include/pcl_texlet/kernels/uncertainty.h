/*
 * pcl_texlet kernels: propagation of per-point depth noise into the covariance of the texlet's
 * centre P (3x3, packed xx xy xz yy yz zz) and normal N (2x2, packed 11 12 22, in the tangent
 * frame of tangent_frame.h, radians).
 *
 * Both methods keep the inlier set of the measured data fixed and perturb each inlier's depth
 * along its ray with its own SD. Monte Carlo (paper, Sect. 3.2) re-fits the plane for every
 * sample; the analytic method is the first-order expansion of the same fit: the mean for P,
 * the eigenvector perturbation  de0 = -sum_j e_j (e_j' dC e0) / (l_j - l0)  for PCA and SVD,
 * and central differences of Eq. 5 for averaging.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/normal_blocks.h>
#include <pcl_texlet/kernels/philox_rng.h>
#include <pcl_texlet/kernels/plane_fit.h>
#include <pcl_texlet/kernels/tangent_frame.h>

#include <cstring>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Fills a packed covariance with quiet NaN (no uncertainty available). */
template <typename S> PCL_TEXLET_HD void
fillNaN (S *c, int n)
{
  for (int i = 0; i < n; ++i)
    c[i] = S (NAN);
}

/** \brief Adds point \a k's first-order terms to lane sums (see analyticPlaneCovariance). */
template <typename S> PCL_TEXLET_HD void
analyticPlaneTerms (const Neighbourhood<S> &nb, const unsigned char *mask, int k, const PlaneFit<S> &fit, S inv_d1,
                    S inv_d2, S e1t1, S e1t2, S e2t1, S e2t2, S cp[6], S cn[3])
{
  const Vec3<S> p = nb.point (k);
  const Vec3<S> r = (S (1) / p.z) * p; // dp = r dz
  const Vec3<S> q = p - fit.P;
  const S var = mask[k] ? nb.sigma[k] * nb.sigma[k] : S (0);
  cp[0] += var * r.x * r.x; cp[1] += var * r.x * r.y; cp[2] += var * r.x * r.z;
  cp[3] += var * r.y * r.y; cp[4] += var * r.y * r.z; cp[5] += var * r.z * r.z;
  const S h = dot (q, fit.N), re0 = dot (r, fit.N);
  const S c1 = -(dot (fit.e1, r) * h + dot (fit.e1, q) * re0) * inv_d1;
  const S c2 = -(dot (fit.e2, r) * h + dot (fit.e2, q) * re0) * inv_d2;
  const S j1 = c1 * e1t1 + c2 * e2t1, j2 = c1 * e1t2 + c2 * e2t2;
  cn[0] += var * j1 * j1;
  cn[1] += var * j1 * j2;
  cn[2] += var * j2 * j2;
}

/** \brief First-order covariances of a PCA or SVD fit of the inliers (mask) of \a nb.
  * Points are summed in four interleaved lanes, which the compiler keeps in SIMD registers.
  */
template <typename S> PCL_TEXLET_HD void
analyticPlaneCovariance (const Neighbourhood<S> &nb, const unsigned char *mask, const PlaneFit<S> &fit,
                         const Vec3<S> &t1, const Vec3<S> &t2, S cov_p[6], S cov_n[3])
{
  int n_in = 0;
  for (int k = 0; k < nb.count; ++k)
    n_in += mask[k] ? 1 : 0;
  const S d1 = S (n_in) * (fit.lambda[1] - fit.lambda[0]), d2 = S (n_in) * (fit.lambda[2] - fit.lambda[0]);
  const S inv_d1 = S (1) / d1, inv_d2 = S (1) / d2;
  // Where the tangents point in the eigenbasis: de0 = c1 e1 + c2 e2 -> (de0.t1, de0.t2).
  const S e1t1 = dot (fit.e1, t1), e1t2 = dot (fit.e1, t2), e2t1 = dot (fit.e2, t1), e2t2 = dot (fit.e2, t2);
  S cp[4][6], cn[4][3];
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 6; ++j)
      cp[i][j] = S (0);
    for (int j = 0; j < 3; ++j)
      cn[i][j] = S (0);
  }
  const int full = nb.count & ~3;
#if defined(__GNUC__) && !defined(__CUDACC__)
  // The same terms as analyticPlaneTerms, four points at a time in vector types.
  typedef S Lane __attribute__ ((vector_size (4 * sizeof (S))));
  Lane lp[6] = {}, ln[3] = {};
  for (int k = 0; k < full; k += 4)
  {
    Lane px, py, pz, sd;
    std::memcpy (&px, nb.x + k, sizeof px);
    std::memcpy (&py, nb.y + k, sizeof py);
    std::memcpy (&pz, nb.z + k, sizeof pz);
    std::memcpy (&sd, nb.sigma + k, sizeof sd);
    Lane use;
    for (int i = 0; i < 4; ++i)
      use[i] = mask[k + i] ? S (1) : S (0);
    const Lane iz = S (1) / pz;
    const Lane rx = iz * px, ry = iz * py, rz = iz * pz;
    const Lane qx = px - fit.P.x, qy = py - fit.P.y, qz = pz - fit.P.z;
    const Lane var = use * (sd * sd);
    lp[0] += var * rx * rx; lp[1] += var * rx * ry; lp[2] += var * rx * rz;
    lp[3] += var * ry * ry; lp[4] += var * ry * rz; lp[5] += var * rz * rz;
    const Lane h = qx * fit.N.x + qy * fit.N.y + qz * fit.N.z, re0 = rx * fit.N.x + ry * fit.N.y + rz * fit.N.z;
    const Lane c1 = -((rx * fit.e1.x + ry * fit.e1.y + rz * fit.e1.z) * h +
                      (qx * fit.e1.x + qy * fit.e1.y + qz * fit.e1.z) * re0) * inv_d1;
    const Lane c2 = -((rx * fit.e2.x + ry * fit.e2.y + rz * fit.e2.z) * h +
                      (qx * fit.e2.x + qy * fit.e2.y + qz * fit.e2.z) * re0) * inv_d2;
    const Lane j1 = c1 * e1t1 + c2 * e2t1, j2 = c1 * e1t2 + c2 * e2t2;
    ln[0] += var * j1 * j1;
    ln[1] += var * j1 * j2;
    ln[2] += var * j2 * j2;
  }
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 6; ++j)
      cp[i][j] = lp[j][i];
    for (int j = 0; j < 3; ++j)
      cn[i][j] = ln[j][i];
  }
#else
  for (int k = 0; k < full; k += 4)
    for (int i = 0; i < 4; ++i)
      analyticPlaneTerms (nb, mask, k + i, fit, inv_d1, inv_d2, e1t1, e1t2, e2t1, e2t2, cp[i], cn[i]);
#endif
  for (int k = full; k < nb.count; ++k)
    analyticPlaneTerms (nb, mask, k, fit, inv_d1, inv_d2, e1t1, e1t2, e2t1, e2t2, cp[k - full], cn[k - full]);
  const S inv_n2 = S (1) / (S (n_in) * S (n_in));
  for (int j = 0; j < 6; ++j)
    cov_p[j] = ((cp[0][j] + cp[1][j]) + (cp[2][j] + cp[3][j])) * inv_n2;
  for (int j = 0; j < 3; ++j)
    cov_n[j] = (cn[0][j] + cn[1][j]) + (cn[2][j] + cn[3][j]);
}

/** \brief First-order covariances of normal averaging (P is the centre point), by central
  * differences of Eq. 5 in each used ring point's depth.
  */
template <typename S> PCL_TEXLET_HD void
analyticAveragingCovariance (const Neighbourhood<S> &nb, const bool use[7], const Vec3<S> &normal,
                             const Vec3<S> &t1, const Vec3<S> &t2, S cov_p[6], S cov_n[3])
{
  const Vec3<S> c = nb.ring[0];
  const Vec3<S> rc = (S (1) / c.z) * c;
  const S vc = nb.ring_sigma[0] * nb.ring_sigma[0];
  cov_p[0] = vc * rc.x * rc.x; cov_p[1] = vc * rc.x * rc.y; cov_p[2] = vc * rc.x * rc.z;
  cov_p[3] = vc * rc.y * rc.y; cov_p[4] = vc * rc.y * rc.z; cov_p[5] = vc * rc.z * rc.z;
  for (int i = 0; i < 3; ++i)
    cov_n[i] = S (0);
  Vec3<S> ring[7];
  for (int i = 0; i < 7; ++i)
    ring[i] = nb.ring[i];
  for (int i = 0; i < 7; ++i)
  {
    if (!use[i])
      continue;
    const S h = S (1e-4) * nb.ring[i].z;
    Vec3<S> np, nm;
    ring[i] = (S (1) + h / nb.ring[i].z) * nb.ring[i];
    const bool okp = averagingNormal (ring, use, np);
    ring[i] = (S (1) - h / nb.ring[i].z) * nb.ring[i];
    const bool okm = averagingNormal (ring, use, nm);
    ring[i] = nb.ring[i];
    if (!okp || !okm)
      continue;
    if (dot (np, normal) < S (0)) np = -np;
    if (dot (nm, normal) < S (0)) nm = -nm;
    const Vec3<S> dn = (S (0.5) / h) * (np - nm);
    const S j1 = dot (dn, t1), j2 = dot (dn, t2), var = nb.ring_sigma[i] * nb.ring_sigma[i];
    cov_n[0] += var * j1 * j1;
    cov_n[1] += var * j1 * j2;
    cov_n[2] += var * j2 * j2;
  }
}

/** \brief Accumulates samples of (P - P0) and of the normal's tangent components. */
template <typename S>
struct SampleCovariance
{
  S sp[3], spp[6], sa[2], saa[3];
  int n;

  PCL_TEXLET_HD void
  reset ()
  {
    for (int i = 0; i < 3; ++i) { sp[i] = S (0); saa[i] = S (0); }
    for (int i = 0; i < 6; ++i) spp[i] = S (0);
    sa[0] = sa[1] = S (0);
    n = 0;
  }

  PCL_TEXLET_HD void
  add (const Vec3<S> &dp, S a1, S a2)
  {
    sp[0] += dp.x; sp[1] += dp.y; sp[2] += dp.z;
    spp[0] += dp.x * dp.x; spp[1] += dp.x * dp.y; spp[2] += dp.x * dp.z;
    spp[3] += dp.y * dp.y; spp[4] += dp.y * dp.z; spp[5] += dp.z * dp.z;
    sa[0] += a1; sa[1] += a2;
    saa[0] += a1 * a1; saa[1] += a1 * a2; saa[2] += a2 * a2;
    ++n;
  }

  /** \brief Unbiased (1/(n-1)) covariances; NaN with fewer than 2 samples. */
  PCL_TEXLET_HD void
  finish (S cov_p[6], S cov_n[3]) const
  {
    if (n < 2)
    {
      fillNaN (cov_p, 6);
      fillNaN (cov_n, 3);
      return;
    }
    const S inv = S (1) / S (n), inv1 = S (1) / S (n - 1);
    for (int r = 0, k = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c, ++k)
        cov_p[k] = (spp[k] - sp[r] * sp[c] * inv) * inv1;
    cov_n[0] = (saa[0] - sa[0] * sa[0] * inv) * inv1;
    cov_n[1] = (saa[1] - sa[0] * sa[1] * inv) * inv1;
    cov_n[2] = (saa[2] - sa[1] * sa[1] * inv) * inv1;
  }
};

/** \brief Monte Carlo covariances: \a samples re-fits of the inliers with depth noise drawn
  * from Philox counters (seed, texlet, sample, point block).
  * \param work scratch of 3 * nb.count values (used by the SVD fit only)
  */
template <typename S> PCL_TEXLET_HD void
monteCarloCovariance (const Neighbourhood<S> &nb, const unsigned char *mask, const bool ring_use[7],
                      PlaneFitMethod method, int samples, std::uint32_t seed, std::uint32_t texlet,
                      const Vec3<S> &P0, const Vec3<S> &N0, const Vec3<S> &t1, const Vec3<S> &t2,
                      S *work, S cov_p[6], S cov_n[3])
{
  SampleCovariance<S> acc;
  acc.reset ();
  float g[4];
  for (int s = 0; s < samples; ++s)
  {
    Vec3<S> P, N;
    bool ok;
    if (method == PlaneFitMethod::Averaging)
    {
      Vec3<S> ring[7];
      for (int i = 0; i < 7; ++i)
      {
        if ((i & 3) == 0)
          normalQuad (seed, texlet, static_cast<std::uint32_t> (s), static_cast<std::uint32_t> (i >> 2), g);
        ring[i] = ring_use[i] ? (S (1) + S (g[i & 3]) * nb.ring_sigma[i] / nb.ring[i].z) * nb.ring[i] : nb.ring[i];
      }
      ok = averagingNormal (ring, ring_use, N);
      P = ring[0];
    }
    else
    {
      PlaneMoments<S> m;
      m.reset (P0);
      for (int k = 0; k < nb.count; ++k)
      {
        if ((k & 3) == 0)
          normalQuad (seed, texlet, static_cast<std::uint32_t> (s), static_cast<std::uint32_t> (k >> 2), g);
        if (!mask[k])
          continue;
        const Vec3<S> p = (S (1) + S (g[k & 3]) * nb.sigma[k] / nb.z[k]) * nb.point (k);
        if (method == PlaneFitMethod::SVD)
        {
          work[3 * m.n + 0] = p.x;
          work[3 * m.n + 1] = p.y;
          work[3 * m.n + 2] = p.z;
        }
        m.add (p);
      }
      PlaneFit<S> fit;
      if (method == PlaneFitMethod::SVD)
      {
        const Vec3<S> mean = m.mean ();
        for (int i = 0; i < m.n; ++i)
        {
          work[3 * i + 0] -= mean.x;
          work[3 * i + 1] -= mean.y;
          work[3 * i + 2] -= mean.z;
        }
        ok = fitPlaneSvd (work, m.n, mean, fit);
      }
      else
        ok = fitPlanePca (m, fit);
      P = fit.P;
      N = fit.N;
    }
    if (!ok)
      continue;
    if (dot (N, N0) < S (0))
      N = -N;
    acc.add (P - P0, dot (N, t1), dot (N, t2));
  }
  acc.finish (cov_p, cov_n);
}

/** \brief Sums of offsets d_i = q_i + g_i a_i and of their products over points, in four
  * lanes (one per point of a Philox block) so that they map onto SIMD registers: with GCC or
  * Clang on the host as vector types, elsewhere as plain arrays; the arithmetic is the same.
  */
template <typename S>
struct PointMomentLanes
{
#if defined(__GNUC__) && !defined(__CUDACC__)
  typedef S Lane __attribute__ ((vector_size (4 * sizeof (S))));
  Lane sx = {}, sy = {}, sz = {}, sxx = {}, sxy = {}, sxz = {}, syy = {}, syz = {}, szz = {};

  /** \brief Adds the four points at q[0..3] + g[0..3] a[0..3]. */
  void
  add (const S *qx, const S *qy, const S *qz, const S *ax, const S *ay, const S *az, const S *g)
  {
    Lane gk, x, y, z, u, v, w; // memcpy: unaligned loads, and no vector passed by value (ABI)
    std::memcpy (&gk, g, sizeof gk);
    std::memcpy (&x, qx, sizeof x); std::memcpy (&y, qy, sizeof y); std::memcpy (&z, qz, sizeof z);
    std::memcpy (&u, ax, sizeof u); std::memcpy (&v, ay, sizeof v); std::memcpy (&w, az, sizeof w);
    const Lane dx = x + gk * u, dy = y + gk * v, dz = z + gk * w;
    sx += dx; sy += dy; sz += dz;
    sxx += dx * dx; sxy += dx * dy; sxz += dx * dz;
    syy += dy * dy; syz += dy * dz; szz += dz * dz;
  }

  static S
  total (const Lane &v)
  {
    S l[4];
    std::memcpy (l, &v, sizeof l);
    return (l[0] + l[1]) + (l[2] + l[3]);
  }
#else
  S sx[4] = {}, sy[4] = {}, sz[4] = {}, sxx[4] = {}, sxy[4] = {}, sxz[4] = {}, syy[4] = {}, syz[4] = {}, szz[4] = {};

  PCL_TEXLET_HD void
  add (const S *qx, const S *qy, const S *qz, const S *ax, const S *ay, const S *az, const S *g)
  {
    for (int i = 0; i < 4; ++i)
    {
      const S dx = qx[i] + g[i] * ax[i], dy = qy[i] + g[i] * ay[i], dz = qz[i] + g[i] * az[i];
      sx[i] += dx; sy[i] += dy; sz[i] += dz;
      sxx[i] += dx * dx; sxy[i] += dx * dy; sxz[i] += dx * dz;
      syy[i] += dy * dy; syz[i] += dy * dz; szz[i] += dz * dz;
    }
  }

  static PCL_TEXLET_HD S
  total (const S v[4]) { return (v[0] + v[1]) + (v[2] + v[3]); }
#endif

  /** \brief Mean offset \a m and (1/n) covariance \a c (packed) of the n points added. */
  PCL_TEXLET_HD void
  moments (S inv_n, S m[3], S c[6]) const
  {
    m[0] = total (sx) * inv_n;
    m[1] = total (sy) * inv_n;
    m[2] = total (sz) * inv_n;
    c[0] = total (sxx) * inv_n - m[0] * m[0];
    c[1] = total (sxy) * inv_n - m[0] * m[1];
    c[2] = total (sxz) * inv_n - m[0] * m[2];
    c[3] = total (syy) * inv_n - m[1] * m[1];
    c[4] = total (syz) * inv_n - m[1] * m[2];
    c[5] = total (szz) * inv_n - m[2] * m[2];
  }
};

/** \brief Scratch values monteCarloPcaCovariance() needs for \a count points. */
PCL_TEXLET_HD constexpr int
monteCarloPcaWorkSize (int count)
{
  return 6 * ((count + 3) / 4) * 4;
}

/** \brief Monte Carlo covariances of a PCA fit: the same samples as monteCarloCovariance()
  * with PlaneFitMethod::PCA (draws from Philox counters (seed, texlet, sample, point block)),
  * to floating-point rounding, computed faster.
  *
  * A sample moves inlier k along its ray, p_k (1 + g_k sigma_k / z_k), so its offset from P0 is
  * q_k + g_k a_k with q_k = p_k - P0 and a_k = (sigma_k / z_k) p_k, precomputed once per texlet
  * (zero for outliers, which then add nothing). The normals come block-parallel from
  * normalBlocks(); the moments are summed in four lanes (one per point of a Philox block) that
  * the compiler keeps in SIMD registers; the re-fit's eigenvectors are found by Jacobi rotations
  * from those of the measured fit, \a fit, which is close to every sample's.
  * \param work scratch of monteCarloPcaWorkSize (nb.count) values
  */
template <typename S> PCL_TEXLET_HD void
monteCarloPcaCovariance (const Neighbourhood<S> &nb, const unsigned char *mask, const PlaneFit<S> &fit, int samples,
                         std::uint32_t seed, std::uint32_t texlet, const Vec3<S> &N0, const Vec3<S> &t1,
                         const Vec3<S> &t2, S *work, S cov_p[6], S cov_n[3])
{
  const int blocks = (nb.count + 3) / 4, padded = 4 * blocks;
  S *qx = work, *qy = work + padded, *qz = work + 2 * padded;
  S *ax = work + 3 * padded, *ay = work + 4 * padded, *az = work + 5 * padded;
  const Vec3<S> P0 = fit.P;
  int n = 0;
  for (int k = 0; k < padded; ++k)
  {
    if (k < nb.count && mask[k])
    {
      const Vec3<S> p = nb.point (k), q = p - P0;
      const S f = nb.sigma[k] / nb.z[k];
      qx[k] = q.x; qy[k] = q.y; qz[k] = q.z;
      ax[k] = f * p.x; ay[k] = f * p.y; az[k] = f * p.z;
      ++n;
    }
    else
      qx[k] = qy[k] = qz[k] = ax[k] = ay[k] = az[k] = S (0);
  }
  const Vec3<S> basis[3] = {fit.N, fit.e1, fit.e2};
  const S inv_n = S (1) / S (n);

  constexpr int chunk = 32; // Philox blocks per batch of normals (128 points)
  std::uint32_t words[4 * chunk];
  S g[4 * chunk];
  SampleCovariance<S> acc;
  acc.reset ();
  for (int s = 0; s < samples; ++s)
  {
    // Moments of the sample's offsets from P0, one lane per point of a block.
    S m[3], c[6];
    {
      PointMomentLanes<S> lanes;
      for (int first = 0; first < blocks; first += chunk)
      {
        const int nblk = blocks - first < chunk ? blocks - first : chunk;
        // Draws for a whole number of 8-block SIMD steps (the spare ones go unused): no
        // scalar remainder loop.
        const int ndraw = (nblk + 7) / 8 * 8;
        normalBlocks (seed, texlet, static_cast<std::uint32_t> (s), first, ndraw, words, g);
        const int k0 = 4 * first;
        for (int b = 0; b < nblk; ++b)
          lanes.add (qx + k0 + 4 * b, qy + k0 + 4 * b, qz + k0 + 4 * b, ax + k0 + 4 * b, ay + k0 + 4 * b,
                     az + k0 + 4 * b, g + 4 * b);
      }
      lanes.moments (inv_n, m, c);
    }
    // The re-fit as fitPlanePca() does it: no plane for (nearly) collinear points.
    SymEigen3<S> eig;
    if (!symmetricEigen3Near (c, basis, eig) && !symmetricEigen3 (c, eig))
      continue;
    if (!(eig.values[1] > collinearityLimit<S> () * eig.values[2]))
      continue;
    Vec3<S> N = eig.vectors[0];
    if (dot (N, N0) < S (0))
      N = -N;
    acc.add (make3 (m[0], m[1], m[2]), dot (N, t1), dot (N, t2));
  }
  acc.finish (cov_p, cov_n);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
