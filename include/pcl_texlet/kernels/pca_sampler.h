/*
 * pcl_texlet kernels: Monte Carlo re-fits of a PCA plane from a Gaussian model of the noisy
 * moments, 15 normals per sample whatever the number of points.
 *
 * The exact sampler (kernels::monteCarloCovariance) moves inlier k along its ray,
 * d_k = q_k + g_k a_k, with q_k = p_k - P0 (P0 the measured centroid), a_k = (sigma_k / z_k) p_k
 * and g_k iid N(0, 1), and re-fits the plane to the moments of the d_k:
 *
 *   m = (1/n) sum d_k = mq + (1/n) sum g_k a_k                       (mq = (1/n) sum q_k ~ 0)
 *   S = (1/n) sum d_k d_k' = (1/n) [sum q q' + sum g_k B_k + sum g_k^2 A_k],
 *       B_k = q_k a_k' + a_k q_k',  A_k = a_k a_k',
 *   c = S - m m'  (the re-fit's covariance; its smallest eigenvector is the sample's normal).
 *
 * The re-fit depends on the g_k only through y = (1/n) sum g_k w_k with w_k = (a_k, B_k) (9
 * values) and the quadratic term (1/n) sum g_k^2 A_k (6 values). Here:
 *
 * - y is drawn exactly: it is a linear function of Gaussians, hence Gaussian with covariance
 *   C_lin = (1/n^2) sum w_k w_k'. y = F9 z with F9 F9' = C_lin (semidefinite_factor.h) and z 9
 *   standard normals has exactly the law of the per-point sampler's y.
 * - (1/n) sum g_k^2 A_k = (1/n) sum A_k (its mean, exact) + (1/n) sum (g_k^2 - 1) A_k. The
 *   fluctuation has mean 0 and covariance C_quad = (2/n^2) sum vec(A_k) vec(A_k)', and is
 *   uncorrelated with y (E g^3 = E g = 0). It is drawn as a Gaussian with that covariance,
 *   F6 z' from 6 more normals, independent of y.
 *
 * So (y, quadratic term) has the same mean and covariance as under the per-point sampler and
 * y has the same law; only the quadratic term's higher moments differ (a sum of ~n scaled
 * chi-square(1) variables replaced by a Gaussian; by the central limit theorem the difference
 * vanishes as n grows) and its dependence on y beyond correlation. That term is of order
 * sigma^2 where the linear one is of order sigma * extent: a relative difference of order
 * sigma / extent in the sample's moments, and smaller still in the covariances of P and N.
 * Everything is written in the measured fit's eigenbasis (N, e1, e2), where c is nearly
 * diagonal: the re-fit is then smallestEigen3NearFirstAxis() (sym_eigen3.h), a few Newton
 * steps, not a 3x3 eigen solve.
 *
 * Cost per sample: 15 normals (four Philox blocks), a 9x9 and a 6x6 triangular product and the
 * Newton steps, against n normals and n moment updates for the per-point sampler. The sums over
 * the points (PcaModelSums) are made once per texlet.
 */
#pragma once

#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/normal_blocks.h>
#include <pcl_texlet/kernels/plane_fit.h>
#include <pcl_texlet/kernels/semidefinite_factor.h>
#include <pcl_texlet/kernels/shared_noise.h>
#include <pcl_texlet/kernels/window_disc_form.h>
#include <pcl_texlet/kernels/sym_eigen3.h>

#include <cstring>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Standard normals one Monte Carlo sample of the PCA model draws: blocks 0..3 of the
  * Philox stream (seed, texlet, sample): 15 for the points' own noise, the last for the noise
  * they share.
  */
constexpr int kPcaSampleNormals = 16;

/** \brief A point's weights w = (a, q a' + a q' packed) in the moments' part linear in its
  * noise: the sample's y gains g w / n.
  */
template <typename V> PCL_TEXLET_HD void
pcaModelWeights (const V *q, const V *a, V w[9])
{
  w[0] = a[0]; w[1] = a[1]; w[2] = a[2];
  PCL_TEXLET_UNROLL_LOOP
  for (int i = 0, k = 0; i < 3; ++i)
    PCL_TEXLET_UNROLL_LOOP
    for (int j = i; j < 3; ++j, ++k)
      w[3 + k] = q[i] * a[j] + a[i] * q[j];
}

/** \brief Adds one point's terms to the sums of the Gaussian model of a PCA re-fit (layout:
  * PcaModelSums), from its q (offset from P0) and a (ray direction times sigma / z), both in
  * the measured fit's eigenbasis and zero for an outlier. \a V is the scalar or a SIMD lane
  * type (deduced, so that GCC keeps its vector attribute): the same arithmetic either way.
  */
template <typename V> PCL_TEXLET_HD void
addPcaModelTerms (V *v, const V *q, const V *a)
{
  V w[9], A[6];
  pcaModelWeights (q, a, w);
  PCL_TEXLET_UNROLL_LOOP
  for (int i = 0, k = 0; i < 3; ++i)
    PCL_TEXLET_UNROLL_LOOP
    for (int j = i; j < 3; ++j, ++k)
    {
      A[k] = a[i] * a[j];
      v[3 + k] += q[i] * q[j];
    }
  PCL_TEXLET_UNROLL_LOOP
  for (int i = 0; i < 3; ++i)
    v[i] += q[i];
  PCL_TEXLET_UNROLL_LOOP
  for (int i = 0, k = 9; i < 9; ++i)
    PCL_TEXLET_UNROLL_LOOP
    for (int j = i; j < 9; ++j, ++k)
      v[k] += w[i] * w[j];
  PCL_TEXLET_UNROLL_LOOP
  for (int i = 0, k = 54; i < 6; ++i)
    PCL_TEXLET_UNROLL_LOOP
    for (int j = i; j < 6; ++j, ++k)
      v[k] += A[i] * A[j];
  PCL_TEXLET_UNROLL_LOOP
  for (int i = 0; i < 9; ++i)
    v[75 + i] += w[i];
}

/** \brief Sums over the inliers that define the Gaussian model of a PCA re-fit. */
template <typename S>
struct PcaModelSums
{
  static constexpr int kQ = 0, kQQ = 3, kWW = 9, kAA = 54, kW = 75, kCount = 84;
  /** sum q (3), sum q q' (6, packed), sum w w' (45, packed 9x9; its leading 3x3 block is
    * sum a a'), sum vec(A) vec(A)' (21, packed 6x6), sum w (9), w = (a, q a' + a q' packed),
    * A = a a'. */
  S v[kCount];

  PCL_TEXLET_HD void
  reset ()
  {
    for (int i = 0; i < kCount; ++i)
      v[i] = S (0);
  }

  PCL_TEXLET_HD void
  add (const S q[3], const S a[3])
  {
    addPcaModelTerms (v, q, a);
  }
};

/** \brief What one sample of the PCA model needs: the measured fit's eigenbasis, the constant
  * parts of the moments and the square-root factors of the random parts, all in that basis.
  */
template <typename S>
struct PcaSampleModel
{
  Vec3<S> axes[3];               ///< N, e1, e2 of the measured fit (world frame)
  S mean[3];                     ///< (1/n) sum q
  S base[6];                     ///< (1/n) (sum q q' + sum a a'), packed
  SemidefiniteFactor<S, 9> lin;  ///< of C_lin = (1/n^2) sum w w' (its points' own part)
  SemidefiniteFactor<S, 6> quad; ///< of C_quad = (2/n^2) sum vec(A) vec(A)' (likewise)
  bool shared = false;           ///< a part of the noise is shared (shared_w, shared_a)
  S shared_w[9];                 ///< sqrt(rho) (1/n) sum w: y's shared part per unit h0
  S shared_a[6];                 ///< rho (1/n) sum A: the quadratic term's, per unit h0^2 - 1
  Vec3<S> n0, t1, t2;            ///< the reference normal and the tangent frame, in the basis
};

/** \brief The measured fit's eigenbasis (N, e1, e2) and its centre P0 in that basis: the frame
  * in which the model's sums are taken.
  */
template <typename S>
struct PcaModelBasis
{
  Vec3<S> P0;
  Vec3<S> axes[3];
  S P0b[3];
};

template <typename S> PCL_TEXLET_HD PcaModelBasis<S>
pcaModelBasis (const PlaneFit<S> &fit)
{
  PcaModelBasis<S> b;
  b.P0 = fit.P;
  b.axes[0] = fit.N;
  b.axes[1] = fit.e1;
  b.axes[2] = fit.e2;
  for (int i = 0; i < 3; ++i)
    b.P0b[i] = dot (b.axes[i], b.P0);
  return b;
}

/** \brief A point's q and a in the basis \a b (N, e1, e2), zero where \a use is 0, from its
  * coordinates, depth SD \a sd and whether it is an inlier (\a use, 1 or 0). \a V is S or a SIMD
  * lane type holding several points, one a lane: the same arithmetic either way.
  */
template <typename S, typename V> PCL_TEXLET_HD void
pcaModelPointOf (const PcaModelBasis<S> &b, V px, V py, V pz, V sd, V use, V q[3], V a[3])
{
  const V dx = px - b.P0.x, dy = py - b.P0.y, dz = pz - b.P0.z;
  const V f = use * sd / pz;
  PCL_TEXLET_UNROLL_LOOP
  for (int i = 0; i < 3; ++i)
  {
    const V qi = b.axes[i].x * dx + b.axes[i].y * dy + b.axes[i].z * dz;
    q[i] = use * qi;
    a[i] = f * (qi + b.P0b[i]);
  }
}

/** \brief Point \a k's q and a in the basis \a b (pcaModelPointOf()), zero for an outlier. */
template <typename S> PCL_TEXLET_HD void
pcaModelPoint (const Neighbourhood<S> &nb, const unsigned char *mask, int k, const PcaModelBasis<S> &b, S q[3],
               S a[3])
{
  pcaModelPointOf<S, S> (b, nb.x[k], nb.y[k], nb.z[k], nb.sigma[k], mask[k] ? S (1) : S (0), q, a);
}

/** \brief Adds points first, first + stride, ... of \a nb to \a sums (pcaModelPoint()).
  * \return how many of them are inliers
  */
template <typename S> PCL_TEXLET_HD int
addPcaModelPoints (const Neighbourhood<S> &nb, const unsigned char *mask, const PcaModelBasis<S> &b, int first,
                   int stride, PcaModelSums<S> &sums)
{
  int n = 0;
  for (int k = first; k < nb.count; k += stride)
  {
    S q[3], a[3];
    pcaModelPoint (nb, mask, k, b, q, a);
    sums.add (q, a);
    n += mask[k] ? 1 : 0;
  }
  return n;
}

/** \brief The sums of the Gaussian model over every point of \a nb (pcaModelPoint()), four
  * points at a time in SIMD lanes on the host, one at a time on the device. Where \a weights is
  * not null, point k's linear weights (pcaModelWeights()) are also kept at weights[k], for the
  * window's form (shared_noise.h); where \a disc is (the points' rows of a whole disc's window
  * tables, windowDiscBasisOf()), their projections on its basis go to \a projection
  * (windowDiscFormOf()).
  */
template <typename S> PCL_TEXLET_HD void
pcaModelSumsOf (const Neighbourhood<S> &nb, const unsigned char *mask, const PcaModelBasis<S> &b,
                PcaModelSums<S> &sums, S (*weights)[9], const S (*disc)[kWindowDiscBasis][4] = nullptr,
                S (*projection)[9] = nullptr)
{
#if defined(__GNUC__) && !defined(__CUDACC__)
  typedef S Lane __attribute__ ((vector_size (4 * sizeof (S))));
  Lane lanes[PcaModelSums<S>::kCount] = {};
  Lane lw[kWindowDiscBasis][9];
  if (disc)
    for (int a = 0; a < kWindowDiscBasis; ++a)
      for (int j = 0; j < 9; ++j)
        lw[a][j] = Lane{};
  for (int k = 0; k < nb.count; k += 4)
  {
    S bx[4], by[4], bz[4], bs[4], bu[4];
    PCL_TEXLET_UNROLL_LOOP
    for (int i = 0; i < 4; ++i)
    {
      const bool in = k + i < nb.count;
      bx[i] = in ? nb.x[k + i] : S (0);
      by[i] = in ? nb.y[k + i] : S (0);
      bz[i] = in ? nb.z[k + i] : S (1);
      bs[i] = in ? nb.sigma[k + i] : S (0);
      bu[i] = in && mask[k + i] ? S (1) : S (0);
    }
    Lane px, py, pz, sd, use;
    std::memcpy (&px, bx, sizeof px);
    std::memcpy (&py, by, sizeof py);
    std::memcpy (&pz, bz, sizeof pz);
    std::memcpy (&sd, bs, sizeof sd);
    std::memcpy (&use, bu, sizeof use);
    Lane q[3], a[3];
    pcaModelPointOf (b, px, py, pz, sd, use, q, a);
    addPcaModelTerms (lanes, q, a);
    if (weights || disc)
    {
      Lane w[9];
      pcaModelWeights (q, a, w);
      if (weights)
        for (int i = 0; i < 4 && k + i < nb.count; ++i)
          for (int j = 0; j < 9; ++j)
            weights[k + i][j] = w[j][i];
      if (disc) // the tables are zero beyond the disc
        PCL_TEXLET_UNROLL_LOOP
        for (int c = 0; c < kWindowDiscBasis; ++c)
        {
          Lane t;
          std::memcpy (&t, disc[k >> 2][c], sizeof t);
          PCL_TEXLET_UNROLL_LOOP
          for (int j = 0; j < 9; ++j)
            lw[c][j] += t * w[j];
        }
    }
  }
  for (int i = 0; i < PcaModelSums<S>::kCount; ++i)
    sums.v[i] = (lanes[i][0] + lanes[i][1]) + (lanes[i][2] + lanes[i][3]);
  if (disc)
    for (int c = 0; c < kWindowDiscBasis; ++c)
      for (int j = 0; j < 9; ++j)
        projection[c][j] = (lw[c][j][0] + lw[c][j][1]) + (lw[c][j][2] + lw[c][j][3]);
#else
  sums.reset ();
  if (disc)
    for (int c = 0; c < kWindowDiscBasis; ++c)
      for (int j = 0; j < 9; ++j)
        projection[c][j] = S (0);
  for (int k = 0; k < nb.count; ++k)
  {
    S q[3], a[3];
    pcaModelPoint (nb, mask, k, b, q, a);
    sums.add (q, a);
    if (weights || disc)
    {
      S w[9];
      pcaModelWeights (q, a, w);
      for (int j = 0; j < 9; ++j)
      {
        if (weights)
          weights[k][j] = w[j];
        if (disc)
          for (int c = 0; c < kWindowDiscBasis; ++c)
            projection[c][j] += disc[k >> 2][c][k & 3] * w[j];
      }
    }
  }
#endif
}

/** \brief Makes the model from the sums over \a n inliers; \a n0, \a t1, \a t2 are the
  * reference normal (samples are turned toward it) and the tangent frame, world frame.
  *
  * With a part \a rho of every point's noise shared by all (Neighbourhood::shared_fraction),
  * g_k = sqrt(1 - rho) h_k + sqrt(rho) h0, h0 the sample's last normal (z[15]), drawn as it
  * is: y = F9 z + sqrt(rho) h0 (1/n) sum w, and the quadratic term is its mean, plus
  * rho (h0^2 - 1) (1/n) sum A exactly (a Gaussian there would let the variance along the rays go
  * negative), plus a Gaussian of covariance (2/n^2)(1 - rho^2) sum vec(A) vec(A)' for the
  * points' own and cross terms; all uncorrelated, as under the per-point sampler. The linear
  * and quadratic shared parts must come from the same h0: for a shift of the whole patch along
  * the rays they cancel in the covariance of the moments. Where the shared noise falls off
  * across columns, pcaLineSampleMoments() takes one such normal per column instead.
  *
  * With a part \a window of the noise shared over a window (shared_noise.h) and \a window_ww
  * its form of the points' w (windowForm() of pcaModelWeights(), 45 values), y's covariance is
  * (1/n^2) ((1 - rho - window) sum w w' + window window_ww): Gaussian, so y keeps the per-point
  * sampler's law exactly. Without the form (a disc wider than windowBox() resolves) the window's
  * part is own noise whose variance is multiplied by \a inflation (windowInflation()), as in the
  * analytic propagation. The quadratic term's fluctuation keeps the covariance of independent
  * own noise (the window's correlation of the g_k^2 is left out: docs/texlet_covariances.md).
  */
template <typename S> PCL_TEXLET_HD void
preparePcaSampleModel (const PcaModelSums<S> &sums, int n, S rho, const PlaneFit<S> &fit, const Vec3<S> &n0,
                       const Vec3<S> &t1, const Vec3<S> &t2, PcaSampleModel<S> &md, S window = S (0),
                       const S *window_ww = nullptr, S inflation = S (1))
{
  typedef PcaModelSums<S> Sums;
  md.axes[0] = fit.N;
  md.axes[1] = fit.e1;
  md.axes[2] = fit.e2;
  const S inv_n = S (1) / S (n), inv_n2 = inv_n * inv_n;
  for (int i = 0; i < 3; ++i)
    md.mean[i] = sums.v[Sums::kQ + i] * inv_n;
  for (int i = 0, k = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j, ++k)
      md.base[k] = (sums.v[Sums::kQQ + k] + sums.v[Sums::kWW + packedIndex<9> (i, j)]) * inv_n;
  md.shared = rho > S (0);
  const S own = md.shared ? S (1) - rho : S (1), own_quad = md.shared ? S (1) - rho * rho : S (1);
  const bool windowed = window_ww && window > S (0);
  const S own_lin = windowed ? own - window : own + window * (inflation - S (1));
  S c[45];
  for (int k = 0; k < 45; ++k)
    c[k] = (own_lin * sums.v[Sums::kWW + k] + (windowed ? window * window_ww[k] : S (0))) * inv_n2;
  factorSemidefinite<S, 9> (c, md.lin);
  for (int k = 0; k < 21; ++k)
    c[k] = own_quad * S (2) * sums.v[Sums::kAA + k] * inv_n2;
  factorSemidefinite<S, 6> (c, md.quad);
  const S root = md.shared ? std::sqrt (rho) : S (0);
  for (int i = 0; i < 9; ++i)
    md.shared_w[i] = root * sums.v[Sums::kW + i] * inv_n;
  for (int i = 0, k = 0; i < 3; ++i) // sum A: the leading 3x3 block of sum w w'
    for (int j = i; j < 3; ++j, ++k)
      md.shared_a[k] = rho * sums.v[Sums::kWW + packedIndex<9> (i, j)] * inv_n;
  md.n0 = make3 (dot (n0, fit.N), dot (n0, fit.e1), dot (n0, fit.e2));
  md.t1 = make3 (dot (t1, fit.N), dot (t1, fit.e1), dot (t1, fit.e2));
  md.t2 = make3 (dot (t2, fit.N), dot (t2, fit.e1), dot (t2, fit.e2));
}

/** \brief The normals of Philox blocks \a block .. \a block + \a blocks - 1 of sample \a sample,
  * one sample at a time (the GPU's way): the bits of normalSamples() for those blocks, block b's
  * four at z[4 (b - block) + 0..3].
  */
template <typename S> PCL_TEXLET_HD void
sampleNormalBlocks (std::uint32_t seed, std::uint32_t texlet, std::uint32_t sample, std::uint32_t block, int blocks,
                    S *z)
{
  for (int b = 0; b < blocks; ++b)
  {
    const r123::Philox4x32::ctr_type w =
        philoxWords (seed, texlet, sample, block + static_cast<std::uint32_t> (b), RandomStream::MonteCarlo);
    float x0, y0, x1, y1;
    boxMullerFloat (w.v[0], w.v[1], x0, y0);
    boxMullerFloat (w.v[2], w.v[3], x1, y1);
    z[4 * b + 0] = x0;
    z[4 * b + 1] = y0;
    z[4 * b + 2] = x1;
    z[4 * b + 3] = y1;
  }
}

/** \brief The kPcaSampleNormals normals of sample \a sample (blocks 0..3, z[15]: the shared
  * noise's), one at a time.
  */
template <typename S> PCL_TEXLET_HD void
pcaSampleNormals (std::uint32_t seed, std::uint32_t texlet, std::uint32_t sample, S z[kPcaSampleNormals])
{
  sampleNormalBlocks (seed, texlet, sample, 0u, 4, z);
}

/** \brief Philox blocks of a sample's column normals (pcaLineSampleMoments()): from
  * kSharedNoiseBlock, four columns a block.
  */
PCL_TEXLET_HD int
pcaLineNormalBlocks (int columns)
{
  return (columns + 3) / 4;
}

/** \brief The moments of a sample from its linear term \a y and quadratic fluctuation \a u. */
template <typename S, typename V> PCL_TEXLET_HD void
pcaSampleMomentsOf (const PcaSampleModel<S> &md, const V y[9], const V u[6], V m[3], V c[6])
{
  for (int i = 0; i < 3; ++i)
    m[i] = md.mean[i] + y[i];
  for (int i = 0, k = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j, ++k)
      c[k] = (md.base[k] + y[3 + k] + u[k]) - m[i] * m[j];
}

/** \brief The moments of one sample from its normals \a z: the mean offset \a m from P0 and
  * the (1/n) covariance \a c (packed), both in the model's basis. \a V is S or a SIMD lane
  * type holding several samples, one a lane: the same arithmetic.
  */
template <typename S, typename V> PCL_TEXLET_HD void
pcaSampleMoments (const PcaSampleModel<S> &md, const V *z, V m[3], V c[6])
{
  V y[9], u[6];
  md.lin.apply (z, y);
  md.quad.apply (z + 9, u);
  if (md.shared)
  {
    const V h0 = z[15], h2 = h0 * h0 - S (1);
    for (int i = 0; i < 9; ++i)
      y[i] += md.shared_w[i] * h0;
    for (int k = 0; k < 6; ++k)
      u[k] += md.shared_a[k] * h2;
  }
  pcaSampleMomentsOf (md, y, u, m, c);
}

/** \brief Where the shared noise falls off across columns (shared_noise.h): the column sums of
  * the points' w and A that its column normals e_x multiply, scaled for the moments.
  */
template <typename S>
struct PcaLineSums
{
  int count = 0;
  S w[kMaxSharedLines][9]; ///< sqrt(rho) (1/n) sum over the column of w
  S A[kMaxSharedLines][6]; ///< rho (1/n) sum over the column of A = a a'
};

/** \brief The column sums of the inliers (\a mask) of \a nb over \a columns, \a n inliers. */
template <typename S> PCL_TEXLET_HD void
pcaLineSums (const Neighbourhood<S> &nb, const unsigned char *mask, const PcaModelBasis<S> &b,
               const LineSpan &columns, int n, PcaLineSums<S> &out)
{
  const S rho = nb.shared_fraction, root = std::sqrt (rho) / S (n), scale = rho / S (n);
  out.count = columns.count;
  for (int x = 0; x < columns.count; ++x)
  {
    for (int i = 0; i < 9; ++i)
      out.w[x][i] = S (0);
    for (int i = 0; i < 6; ++i)
      out.A[x][i] = S (0);
  }
  for (int k = 0; k < nb.count; ++k)
  {
    S q[3], a[3], wk[9];
    pcaModelPoint (nb, mask, k, b, q, a);
    pcaModelWeights (q, a, wk);
    S *w = out.w[nb.line (k) - columns.first], *A = out.A[nb.line (k) - columns.first];
    for (int i = 0; i < 9; ++i)
      w[i] += root * wk[i];
    for (int i = 0, m = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j, ++m)
        A[m] += scale * a[i] * a[j];
  }
}

/** \brief pcaSampleMoments() with the shared noise by column: its column normals \a e
  * (lineSeries(): the per-point sampler's SharedDraw::e law) in place of the whole patch's
  * z[15]. \a V is S or a SIMD lane type holding several samples, one a lane.
  */
template <typename S, typename V> PCL_TEXLET_HD void
pcaLineSampleMoments (const PcaSampleModel<S> &md, const PcaLineSums<S> &cols, const V *z, const V *e, V m[3],
                      V c[6])
{
  V y[9], u[6];
  md.lin.apply (z, y);
  md.quad.apply (z + 9, u);
  for (int x = 0; x < cols.count; ++x)
  {
    const V h2 = e[x] * e[x] - S (1);
    for (int i = 0; i < 9; ++i)
      y[i] += cols.w[x][i] * e[x];
    for (int k = 0; k < 6; ++k)
      u[k] += cols.A[x][k] * h2;
  }
  pcaSampleMomentsOf (md, y, u, m, c);
}

/** \brief A sample's moments with its shared noise as the texlet has it: by column where
  * \a cols has columns (\a e: the sample's column normals, made into their series across the
  * columns in place, lineSeries() with correlation \a line_a; pcaLineSampleMoments()), else
  * shared by the whole patch (pcaSampleMoments()). \a V is S or a SIMD lane type.
  */
template <typename S, typename V> PCL_TEXLET_HD void
pcaSharedNoiseSampleMoments (const PcaSampleModel<S> &md, const PcaLineSums<S> &cols, S line_a, const V *z, V *e,
                             V m[3], V c[6])
{
  if (cols.count > 0)
  {
    lineSeries (cols.count, line_a, e);
    pcaLineSampleMoments (md, cols, z, e, m, c);
  }
  else
    pcaSampleMoments (md, z, m, c);
}

/** \brief The end of a sample's re-fit from its normal \a v (in the measured fit's eigenbasis)
  * and its moments' mean \a m: v turned toward the model's n0, its components \a a1, \a a2 along
  * t1 and t2, and the centre's step \a dP (world frame). \a V is the scalar \a S or a SIMD lane of
  * them (pcaSampleRefitLanes()), so both take the same arithmetic.
  */
template <typename S, typename V> PCL_TEXLET_HD void
pcaSampleRefitOf (const PcaSampleModel<S> &md, V v[3], const V m[3], V dP[3], V &a1, V &a2)
{
  const auto flip = v[0] * md.n0.x + v[1] * md.n0.y + v[2] * md.n0.z < S (0);
  for (int k = 0; k < 3; ++k)
    v[k] = flip ? -v[k] : v[k];
  a1 = v[0] * md.t1.x + v[1] * md.t1.y + v[2] * md.t1.z;
  a2 = v[0] * md.t2.x + v[1] * md.t2.y + v[2] * md.t2.z;
  dP[0] = m[0] * md.axes[0].x + m[1] * md.axes[1].x + m[2] * md.axes[2].x;
  dP[1] = m[0] * md.axes[0].y + m[1] * md.axes[1].y + m[2] * md.axes[2].y;
  dP[2] = m[0] * md.axes[0].z + m[1] * md.axes[1].z + m[2] * md.axes[2].z;
}

/** \brief The re-fit of one sample from its moments (pcaSampleMoments()), as fitPlanePca()
  * does it: no plane for (nearly) collinear points (eigenvalue 1 not above collinearityLimit()
  * times eigenvalue 2).
  * \param dP the sample's centre minus P0 (world frame)
  * \param a1,a2 the sample's normal, turned toward the model's n0, along t1 and t2
  * \return false when the sample has no plane
  */
template <typename S> PCL_TEXLET_HD bool
pcaSampleRefitMoments (const PcaSampleModel<S> &md, const S m[3], const S c[6], Vec3<S> &dP, S &a1, S &a2)
{
  SmallestEigen3<S> eig;
  if (!smallestEigen3NearFirstAxis (c, eig))
  {
    const Vec3<S> axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    SymEigen3<S> full;
    if (!symmetricEigen3Near (c, axes, full) && !symmetricEigen3 (c, full))
      return false;
    eig.vector = full.vectors[0];
    for (int i = 0; i < 3; ++i)
      eig.values[i] = full.values[i];
  }
  if (!(eig.values[1] > collinearityLimit<S> () * eig.values[2]))
    return false;
  S v[3] = {eig.vector.x, eig.vector.y, eig.vector.z}, d[3];
  pcaSampleRefitOf (md, v, m, d, a1, a2);
  dP = make3 (d[0], d[1], d[2]);
  return true;
}

#if defined(__GNUC__) && !defined(__CUDACC__)
/** \brief std::sqrt of each lane of a GCC vector of four S, in place (otherEigenvaluesOf() in
  * lanes). */
template <typename Lane>
struct LaneSqrt
{
  void
  operator() (Lane &v) const
  {
    for (int i = 0; i < 4; ++i)
      v[i] = std::sqrt (v[i]);
  }
};

/** \brief pcaSampleRefitMoments() of four samples at once, one a lane of \a m and \a c (\a Lane:
  * a GCC vector of four S): smallestEigen3NearFirstAxis()'s Newton steps and the rest of the
  * re-fit with the same arithmetic, lane by lane. A lane whose steps fail there is left to
  * pcaSampleRefitMoments(), which goes on to the full eigen solves.
  * \return bit l set where lane l's steps converged; of those, bit l of \a keep is set where its
  * sample has a plane (\a dP, \a a1, \a a2 in lane l) and clear where its points are collinear.
  */
template <typename S, typename Lane> inline int
pcaSampleRefitLanes (const PcaSampleModel<S> &md, const Lane m[3], const Lane c[6], Lane dP[3], Lane &a1, Lane &a2,
                     int &keep)
{
  const Lane scale = (c[3] < S (0) ? -c[3] : c[3]) + (c[5] < S (0) ? -c[5] : c[5]);
  const Lane tol = S (4) * machineEpsilon<S> () * scale;
  typedef decltype (scale < tol) Mask; // all ones in a lane where true
  Mask active = (scale > S (0)) & (scale < S (INFINITY)), converged = Mask {};
  Lane l = c[0], x = Lane {}, y = Lane {};
  for (int step = 0; step < 8; ++step)
  {
    bool any = false;
    for (int i = 0; i < 4; ++i)
      any = any || active[i] != 0;
    if (!any)
      break;
    Lane a11, det, sx, sy, dl;
    nearFirstAxisNewtonStep<S> (c, l, a11, det, sx, sy, dl);
    const Mask step_on = active & (a11 > S (0)) & (det > S (0)); // off: l not below the trailing block's
    l = step_on ? l + dl : l;
    x = step_on ? sx : x;
    y = step_on ? sy : y;
    const Mask done = step_on & ((dl < S (0) ? -dl : dl) <= tol);
    converged |= done;
    active = step_on & ~done;
  }
  Lane norm = S (1) + x * x + y * y;
  LaneSqrt<Lane> () (norm);
  const Lane inv_norm = S (1) / norm;
  Lane v[3] = {inv_norm, x * inv_norm, y * inv_norm};
  Lane l1, l2;
  otherEigenvaluesOf<S> (c, l, LaneSqrt<Lane> (), l1, l2);
  const Mask plane = converged & (l1 > collinearityLimit<S> () * l2);
  pcaSampleRefitOf (md, v, m, dP, a1, a2);
  int bits = 0;
  keep = 0;
  for (int i = 0; i < 4; ++i)
  {
    bits |= converged[i] != 0 ? 1 << i : 0;
    keep |= plane[i] != 0 ? 1 << i : 0;
  }
  return bits;
}
#endif

/** \brief One sample from its normals \a z (pcaSampleNormals()): moments and re-fit. */
template <typename S> PCL_TEXLET_HD bool
pcaSampleRefit (const PcaSampleModel<S> &md, const S z[kPcaSampleNormals], Vec3<S> &dP, S &a1, S &a2)
{
  S m[3], c[6];
  pcaSampleMoments (md, z, m, c);
  return pcaSampleRefitMoments (md, m, c, dP, a1, a2);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
