/*
 * pcl_texlet kernels: propagation of per-point depth noise into the covariance of the texlet's
 * centre P (3x3, packed xx xy xz yy yz zz) and normal N (2x2, packed 11 12 22, in the tangent
 * frame of tangent_frame.h, radians).
 *
 * Both methods keep the inlier set of the measured data fixed and perturb each inlier's depth
 * along its ray with its own SD. P is the texlet's centre (centre_ray.h): the inliers' mean, or
 * where the centre pixel's ray meets the plane, whose perturbation is a step along that ray.
 * Monte Carlo (paper, Sect. 3.2) re-fits the plane for every sample: monteCarloCovariance()
 * draws every inlier's noise (the reference definition, used for SVD and averaging);
 * monteCarloPcaCovariance() draws the PCA fit's moments from a statistically equivalent
 * Gaussian model instead (pca_sampler.h). The analytic method is the first-order expansion of
 * the same fit: the mean (or the ray's step) for P, the eigenvector perturbation
 * de0 = -sum_j e_j (e_j' dC e0) / (l_j - l0) for PCA and SVD,
 * and central differences of Eq. 5 for averaging.
 */
#pragma once

#include <pcl_texlet/kernels/centre_ray.h>
#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/normal_blocks.h>
#include <pcl_texlet/kernels/pca_sampler.h>
#include <pcl_texlet/kernels/philox_rng.h>
#include <pcl_texlet/kernels/plane_fit.h>
#include <pcl_texlet/kernels/shared_noise.h>
#include <pcl_texlet/kernels/tangent_frame.h>
#include <pcl_texlet/kernels/window_disc_form.h>

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

/** \brief How many of \a nb's points \a mask calls inliers (not 0). */
template <typename S> PCL_TEXLET_HD int
inlierCount (const Neighbourhood<S> &nb, const unsigned char *mask)
{
  int n = 0;
  for (int k = 0; k < nb.count; ++k)
    n += mask[k] != 0;
  return n;
}

/** \brief The measured fit's factors in the first-order terms of analyticPlaneCovariance(). */
template <typename S>
struct AnalyticPlaneFactors
{
  S inv_d1, inv_d2;         ///< 1 / (n (l1 - l0)), 1 / (n (l2 - l0)), n inliers
  S e1t1, e1t2, e2t1, e2t2; ///< the eigenvectors e1, e2 dot the tangents t1, t2
  S inv_n, e1m, e2m;        ///< the ray step's: 1 / n, and e1, e2 dot the mean's offset M - P
};

/** \brief Adds the first-order terms of one point, or of four in SIMD lanes (\a V: the scalar or
  * a lane type, the same arithmetic either way), at (\a px, \a py, \a pz) with depth SD \a sd
  * and \a use 1 for an inlier, 0 else: the variance-weighted products of its Jacobians per unit
  * depth step (r = dp/dz, the normal's tangent angles j1 and j2, the ray step a) to \a cp,
  * \a cn and \a ct, and where \a shared its SD-weighted Jacobians (r, j1, j2, a) into \a G and
  * onto \a cs, which the shared part of the noise sums before it squares them.
  */
template <typename V, typename S> PCL_TEXLET_HD void
addAnalyticPlaneTerms (const V &px, const V &py, const V &pz, const V &sd, const V &use, const PlaneFit<S> &fit,
                       const AnalyticPlaneFactors<S> &f, bool shared, V cp[6], V cn[3], V &ct, V cs[6], V G[6])
{
  const V iz = S (1) / pz;
  const V rx = iz * px, ry = iz * py, rz = iz * pz; // dp = r dz
  const V qx = px - fit.P.x, qy = py - fit.P.y, qz = pz - fit.P.z;
  const V su = use * sd, var = su * sd;
  cp[0] += var * rx * rx; cp[1] += var * rx * ry; cp[2] += var * rx * rz;
  cp[3] += var * ry * ry; cp[4] += var * ry * rz; cp[5] += var * rz * rz;
  const V h = qx * fit.N.x + qy * fit.N.y + qz * fit.N.z, re0 = rx * fit.N.x + ry * fit.N.y + rz * fit.N.z;
  const V c1 = -((rx * fit.e1.x + ry * fit.e1.y + rz * fit.e1.z) * h +
                 (qx * fit.e1.x + qy * fit.e1.y + qz * fit.e1.z) * re0) * f.inv_d1;
  const V c2 = -((rx * fit.e2.x + ry * fit.e2.y + rz * fit.e2.z) * h +
                 (qx * fit.e2.x + qy * fit.e2.y + qz * fit.e2.z) * re0) * f.inv_d2;
  const V j1 = c1 * f.e1t1 + c2 * f.e2t1, j2 = c1 * f.e1t2 + c2 * f.e2t2;
  cn[0] += var * j1 * j1;
  cn[1] += var * j1 * j2;
  cn[2] += var * j2 * j2;
  const V a = re0 * f.inv_n + c1 * f.e1m + c2 * f.e2m;
  ct += var * a * a;
  if (shared)
  {
    G[0] = su * rx; G[1] = su * ry; G[2] = su * rz;
    G[3] = su * j1; G[4] = su * j2; G[5] = su * a;
    PCL_TEXLET_UNROLL_LOOP
    for (int j = 0; j < 6; ++j)
      cs[j] += G[j];
  }
}

/** \brief Where analyticPlaneTermsOfAll() also adds each point's SD-weighted Jacobians (6
  * values): nowhere (null \a rows), row k per point k (the window's form), or summed by line,
  * row line (k) - \a first_line (the lines' form); and, with a whole disc's window tables
  * \a disc, values \a lo .. \a hi - 1 (3 .. 5, or 0 .. 4) times each basis value a onto projection[a]
  * (windowDiscFormOf()).
  */
template <typename S>
struct JacobianRows
{
  S (*rows)[6] = nullptr;
  bool by_line = false;
  int first_line = 0;
  const S (*disc)[kWindowDiscBasis][4] = nullptr; ///< the points' basis rows (WindowDiscForm::lanes, or gathered)
  S (*projection)[6] = nullptr;
  int lo = 0, hi = 6;

  PCL_TEXLET_HD S *
  of (const Neighbourhood<S> &nb, int k) const
  {
    return rows[by_line ? nb.line (k) - first_line : k];
  }
};

/** \brief addAnalyticPlaneTerms() of every point of \a nb into the four slots k mod 4 of \a cp,
  * \a cn, \a ct and \a cs (which start at 0), four points at a time in SIMD lanes on the host;
  * each point's SD-weighted Jacobians also added to their row of \a out (which starts at 0).
  * \a cs is summed only where the noise has a shared part or \a out has rows.
  */
template <typename S> PCL_TEXLET_HD void
analyticPlaneTermsOfAll (const Neighbourhood<S> &nb, const unsigned char *mask, const PlaneFit<S> &fit,
                         const AnalyticPlaneFactors<S> &f, S cp[4][6], S cn[4][3], S ct[4], S cs[4][6],
                         const JacobianRows<S> &out)
{
  const bool shared = nb.shared_fraction > S (0) || out.rows || out.disc;
  int scalar_from = 0;
#if defined(__GNUC__) && !defined(__CUDACC__)
  typedef S Lane __attribute__ ((vector_size (4 * sizeof (S))));
  Lane lp[6] = {}, ln[3] = {}, lt = {}, ls[6] = {}, lw[kWindowDiscBasis][6];
  if (out.disc)
    for (int a = 0; a < kWindowDiscBasis; ++a)
      for (int j = 0; j < 6; ++j)
        lw[a][j] = Lane{};
  // The block of values projected, fixed so that the loops below unroll: (j1, j2, a) or (r, j1, j2).
  const bool ray_block = out.lo == 3;
  scalar_from = nb.count & ~3;
  for (int k = 0; k < scalar_from; k += 4)
  {
    Lane px, py, pz, sd, use, G[6] = {}; // G is set only where the noise is shared
    std::memcpy (&px, nb.x + k, sizeof px);
    std::memcpy (&py, nb.y + k, sizeof py);
    std::memcpy (&pz, nb.z + k, sizeof pz);
    std::memcpy (&sd, nb.sigma + k, sizeof sd);
    typedef unsigned char Bytes __attribute__ ((vector_size (4)));
    Bytes in;
    std::memcpy (&in, mask + k, sizeof in);
    use = __builtin_convertvector ((in != 0) & 1, Lane); // 1 for an inlier, 0 else
    addAnalyticPlaneTerms (px, py, pz, sd, use, fit, f, shared, lp, ln, lt, ls, G);
    if (out.rows)
      for (int i = 0; i < 4; ++i)
      {
        S *row = out.of (nb, k + i);
        for (int j = 0; j < 6; ++j)
          row[j] += G[j][i];
      }
    if (out.disc)
      PCL_TEXLET_UNROLL_LOOP
      for (int a = 0; a < kWindowDiscBasis; ++a)
      {
        Lane b;
        std::memcpy (&b, out.disc[k >> 2][a], sizeof b);
        if (ray_block)
        {
          PCL_TEXLET_UNROLL_LOOP
          for (int j = 3; j < 6; ++j)
            lw[a][j] += b * G[j];
        }
        else
        {
          PCL_TEXLET_UNROLL_LOOP
          for (int j = 0; j < 5; ++j)
            lw[a][j] += b * G[j];
        }
      }
  }
  if (out.disc)
    for (int a = 0; a < kWindowDiscBasis; ++a)
      for (int j = out.lo; j < out.hi; ++j)
        out.projection[a][j] = (lw[a][j][0] + lw[a][j][1]) + (lw[a][j][2] + lw[a][j][3]);
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 6; ++j)
    {
      cp[i][j] = lp[j][i];
      cs[i][j] = ls[j][i];
    }
    for (int j = 0; j < 3; ++j)
      cn[i][j] = ln[j][i];
    ct[i] = lt[i];
  }
#endif
  for (int k = scalar_from; k < nb.count; ++k) // the lanes' remainder; every point on the device
  {
    S G[6] = {};
    const int i = k & 3;
    addAnalyticPlaneTerms (nb.x[k], nb.y[k], nb.z[k], nb.sigma[k], mask[k] ? S (1) : S (0), fit, f, shared, cp[i],
                           cn[i], ct[i], cs[i], G);
    if (out.rows)
    {
      S *row = out.of (nb, k);
      for (int j = 0; j < 6; ++j)
        row[j] += G[j];
    }
    if (out.disc)
      for (int a = 0; a < kWindowDiscBasis; ++a)
        for (int j = out.lo; j < out.hi; ++j)
          out.projection[a][j] += out.disc[k >> 2][a][k & 3] * G[j];
  }
}

/** \brief Adds the shared parts of the noise to covariances of independent noise \a c (packed
  * \a dim x \a dim): the lines' part \a rho times the block of rows first .. first + dim - 1 of
  * \a form (packed 6 x 6: the SD-weighted Jacobians' lineForm()) and the window's part
  * \a window times that block of \a window_form (windowForm()), both scaled by \a scale, and
  * what is left of \a c. Without a window form (null) the window's part stays independent with
  * its variance multiplied by \a inflation (windowInflation()).
  */
template <typename S, int dim> PCL_TEXLET_HD void
addSharedNoise (S rho, const S form[21], int first, S scale, S *c, S window = S (0), const S *window_form = nullptr,
                S inflation = S (1))
{
  const S own = window_form ? S (1) - rho - window : S (1) - rho + window * (inflation - S (1));
  for (int i = 0, k = 0; i < dim; ++i)
    for (int j = i; j < dim; ++j, ++k)
    {
      const int f = packedIndex<6> (first + i, first + j);
      c[k] = own * c[k] + scale * (rho * form[f] + (window_form ? window * window_form[f] : S (0)));
    }
}

/** \brief First-order covariances of a PCA or SVD fit of the inliers (mask) of \a nb, with P
  * the texlet's \a centre. On the centre ray, P = ray (N.M) / (N.ray) moves by
  * dt = (N.dM + dN.(M - P)) / (N.ray) along it, M the inliers' mean. With a shared part rho of
  * the noise (Neighbourhood::shared_fraction) the covariance of the depths is
  * (1 - rho) diag(sigma^2) + rho sigma sigma', so each result is (1 - rho) J diag(sigma^2) J' +
  * rho (J sigma)(J sigma)': one more sum per Jacobian row.
  * Points are summed in four interleaved lanes, which the compiler keeps in SIMD registers.
  */
template <typename S> PCL_TEXLET_HD void
analyticPlaneCovariance (const Neighbourhood<S> &nb, const unsigned char *mask, const PlaneFit<S> &fit,
                         const TexletCentrePoint<S> &centre, const Vec3<S> &t1, const Vec3<S> &t2, S cov_p[6],
                         S cov_n[3])
{
  const int n_in = inlierCount (nb, mask);
  const S d1 = S (n_in) * (fit.lambda[1] - fit.lambda[0]), d2 = S (n_in) * (fit.lambda[2] - fit.lambda[0]);
  AnalyticPlaneFactors<S> f;
  f.inv_d1 = S (1) / d1;
  f.inv_d2 = S (1) / d2;
  // Where the tangents point in the eigenbasis: de0 = c1 e1 + c2 e2 -> (de0.t1, de0.t2).
  f.e1t1 = dot (fit.e1, t1);
  f.e1t2 = dot (fit.e1, t2);
  f.e2t1 = dot (fit.e2, t1);
  f.e2t2 = dot (fit.e2, t2);
  // The ray step's terms: N.dM per point's dz is (N.r) / n, dN.(M - P) is c1 e1m + c2 e2m.
  f.inv_n = S (1) / S (n_in);
  f.e1m = dot (fit.e1, centre.mean_offset);
  f.e2m = dot (fit.e2, centre.mean_offset);
  S cp[4][6], cn[4][3], ct[4] = {S (0), S (0), S (0), S (0)}, cs[4][6];
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 6; ++j)
      cp[i][j] = cs[i][j] = S (0);
    for (int j = 0; j < 3; ++j)
      cn[i][j] = S (0);
  }
  const S rho = nb.shared_fraction, window = nb.window_fraction;
  S form[21] = {}; // the shared part's quadratic form of the SD-weighted Jacobians (r, j1, j2, a)
  S window_form[21];
  bool window_resolved = false;
  const LineSpan columns = sharedLines (nb);
#if !defined(__CUDA_ARCH__) // the device's noise is never shared (gpu/frame_texlet.h)
  // A disc with tables takes its window form from them (window_disc_form.h), without the points'
  // pixels; its pixels without a reading or an inlier, at most kMaxWindowDiscGaps, are gaps the
  // tables fill.
  int gap[kMaxWindowDiscGaps];
  const int gaps = windowDiscGaps (nb, mask, gap);
  const bool by_tables = gaps >= 0 && window > S (0);
  int pu[kMaxWindowPoints], pv[kMaxWindowPoints];
  const WindowBox box = by_tables ? WindowBox () : windowBox (nb, pu, pv);
#else
  [[maybe_unused]] const bool by_tables = false;
  const WindowBox box = WindowBox ();
#endif
  // (r, j1, j2, a): the normal needs j1, j2; P on the centre ray a, else r.
  const int form_lo = centre.on ? 3 : 0, form_hi = centre.on ? 6 : 5;
  JacobianRows<S> rows; // where the points' SD-weighted Jacobians go besides the sums
#if !defined(__CUDA_ARCH__)
  // With tables, they are projected on the tables' basis as they are summed.
  S projection[kWindowDiscBasis][6] = {};
  S gathered[(kMaxWindowPoints + 3) / 4][kWindowDiscBasis][4];
  if (by_tables)
  {
    rows.disc = windowDiscBasisOf (nb, gathered);
    rows.projection = projection;
    rows.lo = form_lo;
    rows.hi = form_hi;
  }
#endif
  if (box.on)
  {
#if !defined(__CUDA_ARCH__)
    // Every point's SD-weighted Jacobians kept, for the window's pairs (shared_noise.h).
    S Gp[kMaxWindowPoints][6];
    for (int k = 0; k < nb.count; ++k)
      for (int j = 0; j < 6; ++j)
        Gp[k][j] = S (0);
    rows.rows = Gp;
    analyticPlaneTermsOfAll (nb, mask, fit, f, cp, cn, ct, cs, rows);
    if (rho > S (0))
    {
      S G[kMaxSharedLines][6] = {};
      const int lines = columns.count > 0 ? columns.count : 1;
      for (int k = 0; k < nb.count; ++k)
        for (int j = 0; j < 6; ++j)
          G[columns.count > 0 ? nb.line (k) - columns.first : 0][j] += Gp[k][j];
      lineForm<S, 6> (G, lines, columns.count > 0 ? nb.line_correlation : S (1), form);
    }
    if (centre.on)
      windowForm<S, 6, 3, 6> (Gp, pu, pv, nb.count, box.u0, box.v0, box.nu, box.nv, nb.window_px, window_form);
    else
      windowForm<S, 6, 0, 5> (Gp, pu, pv, nb.count, box.u0, box.v0, box.nu, box.nv, nb.window_px, window_form);
    window_resolved = true;
#endif
  }
  else if (columns.count > 0) // the shared part by column (shared_noise.h)
  {
#if !defined(__CUDA_ARCH__) // the device's noise is never shared (gpu/frame_texlet.h)
    S G[kMaxSharedLines][6] = {};
    rows.rows = G;
    rows.by_line = true;
    rows.first_line = columns.first;
    analyticPlaneTermsOfAll (nb, mask, fit, f, cp, cn, ct, cs, rows);
    lineForm<S, 6> (G, columns.count, nb.line_correlation, form);
#endif
  }
  else
  {
    analyticPlaneTermsOfAll (nb, mask, fit, f, cp, cn, ct, cs, rows);
    if (rho > S (0)) // the patch shares it whole
    {
      S G[1][6];
      for (int j = 0; j < 6; ++j)
        G[0][j] = (cs[0][j] + cs[1][j]) + (cs[2][j] + cs[3][j]);
      lineForm<S, 6> (G, 1, S (1), form);
    }
  }
#if !defined(__CUDA_ARCH__)
  if (by_tables)
  {
    windowDiscFormOf<S, 6> (projection, form_lo, form_hi, *nb.window_disc, gap, gaps, window_form);
    window_resolved = true;
  }
#endif
  const S *wf = window_resolved ? window_form : nullptr;
  const S inflation = windowInflation (nb);
  const bool shared = rho > S (0) || window > S (0);
  if (centre.on)
  {
    S var_t = (ct[0] + ct[1]) + (ct[2] + ct[3]);
    if (shared)
      addSharedNoise<S, 1> (rho, form, 5, S (1), &var_t, window, wf, inflation);
    var_t *= centre.inv_n_ray * centre.inv_n_ray;
    const Vec3<S> &r = centre.ray;
    cov_p[0] = var_t * r.x * r.x; cov_p[1] = var_t * r.x * r.y; cov_p[2] = var_t * r.x * r.z;
    cov_p[3] = var_t * r.y * r.y; cov_p[4] = var_t * r.y * r.z; cov_p[5] = var_t * r.z * r.z;
  }
  else
  {
    const S inv_n2 = f.inv_n * f.inv_n;
    for (int j = 0; j < 6; ++j)
      cov_p[j] = ((cp[0][j] + cp[1][j]) + (cp[2][j] + cp[3][j])) * inv_n2;
    if (shared)
      addSharedNoise<S, 3> (rho, form, 0, inv_n2, cov_p, window, wf, inflation);
  }
  for (int j = 0; j < 3; ++j)
    cov_n[j] = (cn[0][j] + cn[1][j]) + (cn[2][j] + cn[3][j]);
  if (shared)
    addSharedNoise<S, 2> (rho, form, 3, S (1), cov_n, window, wf, inflation);
}

/** \brief The correlation of ring points \a i and \a j's depth noise (normal averaging): 1 for
  * i = j; else the lines' part shared_fraction line_correlation^|dl| (dl: their columns', or
  * rows', distance) plus the window's window_fraction tri(du) tri(dv), where their pixel offsets
  * are known (Neighbourhood::ring_offsets); without them the lines' part is shared whole and
  * the window's is taken as each point's own.
  */
template <typename S> PCL_TEXLET_HD S
ringCorrelation (const Neighbourhood<S> &nb, int i, int j)
{
  if (i == j)
    return S (1);
  if (!nb.ring_offsets)
    return nb.shared_fraction;
  const int du = nb.ring_du[i] > nb.ring_du[j] ? nb.ring_du[i] - nb.ring_du[j] : nb.ring_du[j] - nb.ring_du[i];
  const int dv = nb.ring_dv[i] > nb.ring_dv[j] ? nb.ring_dv[i] - nb.ring_dv[j] : nb.ring_dv[j] - nb.ring_dv[i];
  S lines = nb.shared_fraction;
  for (int d = 0; d < (nb.lines_are_rows ? dv : du); ++d)
    lines *= nb.line_correlation;
  return lines + nb.window_fraction * windowOverlap<S> (du, nb.window_px) * windowOverlap<S> (dv, nb.window_px);
}

/** \brief Whether ring points' depth noise correlates between points (ringCorrelation() is not
  * 0 for every pair): the lines' part always, the window's where the ring's offsets are known.
  */
template <typename S> PCL_TEXLET_HD bool
ringNoiseShared (const Neighbourhood<S> &nb)
{
  return nb.shared_fraction > S (0) || (nb.ring_offsets && nb.window_fraction > S (0));
}

/** \brief First-order covariances of normal averaging (P is the centre point), by central
  * differences of Eq. 5 in each used ring point's depth; the points' shared noise by
  * ringCorrelation().
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
  S g[7][2] = {}; // each used point's SD-weighted Jacobian, for the shared part of the noise
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
    g[i][0] = nb.ring_sigma[i] * j1;
    g[i][1] = nb.ring_sigma[i] * j2;
  }
  // Sum over pairs i != j of C_ij G_i G_j' (the own part, C_ii = 1, is above).
  if (ringNoiseShared (nb))
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j)
        if (i != j && use[i] && use[j])
        {
          const S c = ringCorrelation (nb, i, j);
          cov_n[0] += c * g[i][0] * g[j][0];
          cov_n[1] += c * g[i][0] * g[j][1];
          cov_n[2] += c * g[i][1] * g[j][1];
        }
}

/** \brief First-order covariances of the texlet's fit \a method: analyticAveragingCovariance()
  * for normal averaging (ring points \a ring_use), analyticPlaneCovariance() of the inliers
  * (\a mask) for PCA and SVD, with P the texlet's \a centre.
  */
template <typename S> PCL_TEXLET_HD void
analyticCovariance (const Neighbourhood<S> &nb, const unsigned char *mask, const bool ring_use[7],
                    PlaneFitMethod method, const PlaneFit<S> &fit, const TexletCentrePoint<S> &centre,
                    S cov_p[6], S cov_n[3])
{
  if (method == PlaneFitMethod::Averaging)
    analyticAveragingCovariance (nb, ring_use, centre.N0, centre.t1, centre.t2, cov_p, cov_n);
  else
    analyticPlaneCovariance (nb, mask, fit, centre, centre.t1, centre.t2, cov_p, cov_n);
}

/** \brief Accumulates samples of (P - P0) and of the normal's tangent components. A sample
  * comes as its inliers' mean minus the measured one; centre turns that into the step of the
  * texlet's centre (centreShift()).
  */
template <typename S>
struct SampleCovariance
{
  S sp[3], spp[6], sa[2], saa[3];
  int n;
  TexletCentrePoint<S> centre; ///< off after reset (): P is the mean

  PCL_TEXLET_HD void
  reset (const TexletCentrePoint<S> &c = TexletCentrePoint<S> ())
  {
    centre = c;
    for (int i = 0; i < 3; ++i) { sp[i] = S (0); saa[i] = S (0); }
    for (int i = 0; i < 6; ++i) spp[i] = S (0);
    sa[0] = sa[1] = S (0);
    n = 0;
  }

  PCL_TEXLET_HD void
  add (const Vec3<S> &dM, S a1, S a2)
  {
    const Vec3<S> dp = centreShift (centre, dM, a1, a2);
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

/** \brief Adds a Monte Carlo sample's centre \a P and normal \a N to \a acc: P - P0 and N,
  * turned toward the measured N0, along the tangents t1, t2.
  */
template <typename S> PCL_TEXLET_HD void
addMonteCarloSample (const Vec3<S> &P, Vec3<S> N, const Vec3<S> &P0, const Vec3<S> &N0, const Vec3<S> &t1,
                     const Vec3<S> &t2, SampleCovariance<S> &acc)
{
  if (dot (N, N0) < S (0))
    N = -N;
  acc.add (P - P0, dot (N, t1), dot (N, t2));
}

/** \brief Monte Carlo sample \a s of normal averaging: the used ring points (\a ring_use)
  * moved along their rays by depth noise from Philox counters (seed, texlet, s, point block),
  * and Eq. 5 on them. \a correlated: the factor of the points' correlation (ringCorrelation())
  * where ringNoiseShared(); null: independent noise.
  * \return false where the sample has no normal
  */
template <typename S> PCL_TEXLET_HD bool
averagingSample (const Neighbourhood<S> &nb, const bool ring_use[7], const SemidefiniteFactor<S, 7> *correlated,
                 std::uint32_t seed, std::uint32_t texlet, int s, Vec3<S> &P, Vec3<S> &N)
{
  float g[8];
  normalQuad (seed, texlet, static_cast<std::uint32_t> (s), 0u, g);
  normalQuad (seed, texlet, static_cast<std::uint32_t> (s), 1u, g + 4);
  S e[7];
  if (correlated)
  {
    S z[7];
    for (int i = 0; i < 7; ++i)
      z[i] = S (g[i]);
    correlated->apply (z, e);
  }
  else
    for (int i = 0; i < 7; ++i)
      e[i] = S (g[i]);
  Vec3<S> ring[7];
  for (int i = 0; i < 7; ++i)
    ring[i] = ring_use[i] ? (S (1) + e[i] * nb.ring_sigma[i] / nb.ring[i].z) * nb.ring[i] : nb.ring[i];
  P = ring[0];
  return averagingNormal (ring, ring_use, N);
}

/** \brief Monte Carlo sample \a s of a PCA or SVD fit: every inlier (\a mask) moved along its
  * ray by depth noise from Philox counters (seed, texlet, s, point block), and re-fitted.
  * \param lines, box sharedLines() and windowBox() of \a nb, once per texlet
  * \param work scratch of 3 * nb.count values (used by the SVD fit only)
  * \return false where the sample has no plane
  */
template <typename S> PCL_TEXLET_HD bool
inlierSample (const Neighbourhood<S> &nb, const unsigned char *mask, PlaneFitMethod method, const LineSpan &lines,
              const WindowBox &box, std::uint32_t seed, std::uint32_t texlet, int s, const Vec3<S> &P0, S *work,
              Vec3<S> &P, Vec3<S> &N)
{
  float g[4];
  PlaneMoments<S> m;
  m.reset (P0);
  const SharedDraw<S> shared (nb, lines, box.on, seed, texlet, s);
#if !defined(__CUDA_ARCH__) // the device's noise is never shared (gpu/frame_texlet.h)
  const WindowDraw<S> windowed (nb, box, seed, texlet, s);
#endif
  for (int k = 0; k < nb.count; ++k)
  {
    if ((k & 3) == 0)
      normalQuad (seed, texlet, static_cast<std::uint32_t> (s), static_cast<std::uint32_t> (k >> 2), g);
    if (!mask[k])
      continue;
    S e = shared.noise (g[k & 3], nb, k);
#if !defined(__CUDA_ARCH__)
    e += windowed.noise (nb, k);
#endif
    const Vec3<S> p = (S (1) + e * nb.sigma[k] / nb.z[k]) * nb.point (k);
    if (method == PlaneFitMethod::SVD)
    {
      work[3 * m.n + 0] = p.x;
      work[3 * m.n + 1] = p.y;
      work[3 * m.n + 2] = p.z;
    }
    m.add (p);
  }
  PlaneFit<S> fit;
  bool ok;
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
  return ok;
}

/** \brief Monte Carlo covariances: \a samples re-fits (averagingSample() for normal averaging,
  * inlierSample() for PCA and SVD) around the measured P0 (the inliers' mean) and normal
  * centre.N0, of the texlet's \a centre (texletCentre()).
  * \param work scratch of 3 * nb.count values (used by the SVD fit only)
  */
template <typename S> PCL_TEXLET_HD void
monteCarloCovariance (const Neighbourhood<S> &nb, const unsigned char *mask, const bool ring_use[7],
                      PlaneFitMethod method, int samples, std::uint32_t seed, std::uint32_t texlet,
                      const Vec3<S> &P0, const TexletCentrePoint<S> &centre, S *work, S cov_p[6], S cov_n[3])
{
  SampleCovariance<S> acc;
  acc.reset (centre);
  const bool ring = method == PlaneFitMethod::Averaging;
  const LineSpan lines = ring ? LineSpan () : sharedLines (nb);
  const WindowBox box = ring ? WindowBox () : windowBox (nb);
  SemidefiniteFactor<S, 7> ring_factor;
  const bool correlated_ring = ring && ringNoiseShared (nb);
  if (correlated_ring)
  {
    S c[28];
    for (int i = 0; i < 7; ++i)
      for (int j = i; j < 7; ++j)
        c[packedIndex<7> (i, j)] = ringCorrelation (nb, i, j);
    factorSemidefinite<S, 7> (c, ring_factor);
  }
  for (int s = 0; s < samples; ++s)
  {
    Vec3<S> P, N;
    const bool ok = ring ? averagingSample (nb, ring_use, correlated_ring ? &ring_factor : nullptr, seed, texlet, s, P, N)
                         : inlierSample (nb, mask, method, lines, box, seed, texlet, s, P0, work, P, N);
    if (ok)
      addMonteCarloSample (P, N, P0, centre.N0, centre.t1, centre.t2, acc);
  }
  acc.finish (cov_p, cov_n);
}

/** \brief Adds sample \a s of the Gaussian moment model \a md (its normals drawn one at a time,
  * pcaSampleNormals(), and re-fitted, pcaSampleRefit()) to \a acc, unless it has no plane.
  */
template <typename S> PCL_TEXLET_HD void
addPcaSample (const PcaSampleModel<S> &md, std::uint32_t seed, std::uint32_t texlet, int s, SampleCovariance<S> &acc)
{
  S z[kPcaSampleNormals], a1, a2;
  Vec3<S> dP;
  pcaSampleNormals (seed, texlet, static_cast<std::uint32_t> (s), z);
  if (pcaSampleRefit (md, z, dP, a1, a2))
    acc.add (dP, a1, a2);
}

/** \brief Monte Carlo covariances of a PCA fit with the Gaussian moment model of
  * pca_sampler.h: \a samples re-fits whose moments are drawn from 15 normals each (Philox
  * counters (seed, texlet, sample, block 0..3)) instead of one normal per inlier.
  *
  * Statistically equivalent to monteCarloCovariance() with PlaneFitMethod::PCA, which stays the
  * reference definition: the sample moments have the same mean and covariance, their part
  * linear in the depth noise (order sigma * extent) has exactly the same Gaussian law, and
  * only the higher moments of the part quadratic in the noise (order sigma^2) differ (see
  * pca_sampler.h). The random stream differs, so the values differ from the per-point
  * sampler's at the same seed as they would at another seed. The sums over the inliers are
  * made once (in four SIMD lanes on the host), the samples' normals are drawn for up to 32
  * samples at a time (normalSamples()), and the re-fit is a few Newton steps in the measured
  * fit's eigenbasis \a fit (N, e1, e2), falling back to the Jacobi and closed-form eigen
  * solvers when they do not converge. The GPU's warp kernel uses the same pieces and draws.
  * Noise shared over a window (host only) enters the linear part's covariance through the
  * window's form of the points' weights, made once per texlet; the quadratic part's covariance
  * stays that of independent noise (preparePcaSampleModel()).
  */
template <typename S> PCL_TEXLET_HD void
monteCarloPcaCovariance (const Neighbourhood<S> &nb, const unsigned char *mask, const PlaneFit<S> &fit, int samples,
                         std::uint32_t seed, std::uint32_t texlet, const TexletCentrePoint<S> &centre, S cov_p[6],
                         S cov_n[3])
{
  const PcaModelBasis<S> basis = pcaModelBasis (fit);
  const int n = inlierCount (nb, mask);
  if (n < 3)
  {
    fillNaN (cov_p, 6);
    fillNaN (cov_n, 3);
    return;
  }
  PcaModelSums<S> sums;
  S window_ww[45];
  bool windowed = false;
#if !defined(__CUDA_ARCH__) // the device's noise is never shared (gpu/frame_texlet.h)
  // A disc with tables takes its window form from them (window_disc_form.h), its pixels without a
  // reading or an inlier gaps.
  int gap[kMaxWindowDiscGaps];
  const int gaps = windowDiscGaps (nb, mask, gap);
  const bool by_tables = gaps >= 0 && nb.window_fraction > S (0);
  int pu[kMaxWindowPoints], pv[kMaxWindowPoints];
  const WindowBox box = by_tables ? WindowBox () : windowBox (nb, pu, pv);
  if (by_tables)
  {
    S projection[kWindowDiscBasis][9];
    S gathered[(kMaxWindowPoints + 3) / 4][kWindowDiscBasis][4];
    pcaModelSumsOf (nb, mask, basis, sums, static_cast<S (*)[9]> (nullptr), windowDiscBasisOf (nb, gathered),
                    projection);
    windowDiscFormOf<S, 9> (projection, 0, 9, *nb.window_disc, gap, gaps, window_ww);
    windowed = true;
  }
  else
  {
    S W[kMaxWindowPoints][9]; // with a window, every point's linear weights for its form
    pcaModelSumsOf (nb, mask, basis, sums, box.on ? W : nullptr);
    if (box.on)
    {
      windowForm<S, 9> (W, pu, pv, nb.count, box.u0, box.v0, box.nu, box.nv, nb.window_px, window_ww);
      windowed = true;
    }
  }
#else
  pcaModelSumsOf (nb, mask, basis, sums, static_cast<S (*)[9]> (nullptr));
#endif
  PcaSampleModel<S> md;
  preparePcaSampleModel (sums, n, nb.shared_fraction, fit, centre.N0, centre.t1, centre.t2, md, nb.window_fraction,
                         windowed ? window_ww : nullptr, windowInflation (nb));

  SampleCovariance<S> acc;
  acc.reset (centre);
#if !defined(__CUDA_ARCH__) // the device's noise is never shared (gpu/frame_texlet.h)
  // The shared noise by column: each sample's column normals (Philox blocks from
  // kSharedNoiseBlock), an AR(1) series across the columns (lineSeries()).
  const LineSpan columns = sharedLines (nb);
  PcaLineSums<S> cols;
  if (columns.count > 0)
    pcaLineSums (nb, mask, basis, columns, n, cols);
  const int line_blocks = pcaLineNormalBlocks (cols.count);
  const S line_a = nb.line_correlation;
#endif
#if !defined(__CUDACC__)
  Vec3<S> dP;
  S a1, a2;
  constexpr int chunk = 32; // samples whose normals are drawn at once
  std::uint32_t words[4 * chunk];
  S zs[kPcaSampleNormals][chunk];              // normal j of sample first + i at zs[j][i]
  S es[4 * ((kMaxSharedLines + 3) / 4)][chunk]; // column x's normal of sample first + i at es[x][i]
  for (int first = 0; first < samples; first += chunk)
  {
    const int ns = samples - first < chunk ? samples - first : chunk;
    const int ndraw = (ns + 7) / 8 * 8; // whole 8-wide SIMD steps; the spare draws go unused
    for (int b = 0; b < 4; ++b)
      normalSamples (seed, texlet, static_cast<std::uint32_t> (b), first, ndraw, words, zs[4 * b], zs[4 * b + 1],
                     zs[4 * b + 2], zs[4 * b + 3]);
    for (int b = 0; b < line_blocks; ++b)
      normalSamples (seed, texlet, kSharedNoiseBlock + static_cast<std::uint32_t> (b), first, ndraw, words, es[4 * b],
                     es[4 * b + 1], es[4 * b + 2], es[4 * b + 3]);
#if defined(__GNUC__)
    // Moments and re-fits of four samples at a time, one a lane; a lane whose Newton steps fail
    // is re-fitted on its own.
    typedef S Lane __attribute__ ((vector_size (4 * sizeof (S))));
    for (int i = 0; i < ns; i += 4)
    {
      Lane zl[kPcaSampleNormals], ml[3], cl[6];
      PCL_TEXLET_UNROLL_LOOP
      for (int j = 0; j < kPcaSampleNormals; ++j)
        std::memcpy (&zl[j], zs[j] + i, sizeof (Lane));
      Lane el[kMaxSharedLines];
      for (int x = 0; x < cols.count; ++x)
        std::memcpy (&el[x], es[x] + i, sizeof (Lane));
      pcaSharedNoiseSampleMoments (md, cols, line_a, zl, el, ml, cl);
      Lane dPl[3], a1l, a2l;
      int keep;
      const int fast = pcaSampleRefitLanes (md, ml, cl, dPl, a1l, a2l, keep);
      for (int l = 0; l < 4 && i + l < ns; ++l)
      {
        if (fast >> l & 1)
        {
          if (keep >> l & 1)
            acc.add (make3 (dPl[0][l], dPl[1][l], dPl[2][l]), a1l[l], a2l[l]);
          continue;
        }
        const S m[3] = {ml[0][l], ml[1][l], ml[2][l]};
        const S c[6] = {cl[0][l], cl[1][l], cl[2][l], cl[3][l], cl[4][l], cl[5][l]};
        if (pcaSampleRefitMoments (md, m, c, dP, a1, a2))
          acc.add (dP, a1, a2);
      }
    }
#else
    for (int i = 0; i < ns; ++i)
    {
      S z[kPcaSampleNormals], e[kMaxSharedLines], m[3], c[6];
      for (int j = 0; j < kPcaSampleNormals; ++j)
        z[j] = zs[j][i];
      for (int x = 0; x < cols.count; ++x)
        e[x] = es[x][i];
      pcaSharedNoiseSampleMoments (md, cols, line_a, z, e, m, c);
      if (pcaSampleRefitMoments (md, m, c, dP, a1, a2))
        acc.add (dP, a1, a2);
    }
#endif
  }
#else
  for (int s = 0; s < samples; ++s) // the same normals one sample at a time
  {
#if !defined(__CUDA_ARCH__)
    S z[kPcaSampleNormals], e[4 * ((kMaxSharedLines + 3) / 4)], m[3], c[6], a1, a2;
    Vec3<S> dP;
    pcaSampleNormals (seed, texlet, static_cast<std::uint32_t> (s), z);
    sampleNormalBlocks (seed, texlet, static_cast<std::uint32_t> (s), kSharedNoiseBlock, line_blocks, e);
    pcaSharedNoiseSampleMoments (md, cols, line_a, z, e, m, c);
    if (pcaSampleRefitMoments (md, m, c, dP, a1, a2))
      acc.add (dP, a1, a2);
#else
    addPcaSample (md, seed, texlet, s, acc);
#endif
  }
#endif
  acc.finish (cov_p, cov_n);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
