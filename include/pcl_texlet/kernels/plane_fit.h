/*
 * pcl_texlet kernels: the three plane fits compared in the paper (Sect. 3.1, Fig. 8).
 *
 *  - PCA: covariance of the points, smallest eigenvector by the closed-form solve;
 *  - SVD: one-sided Jacobi SVD of the centred point matrix (the reference; iterative);
 *  - normal averaging over the six hexagonal neighbours (Eq. 5).
 */
#pragma once

#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/sym_eigen3.h>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Running sums of points, taken relative to a reference point so that single
  * precision keeps its digits when the patch is far from the origin.
  */
template <typename S>
struct PlaneMoments
{
  Vec3<S> ref;
  S s[3];
  S ss[6]; // xx xy xz yy yz zz
  int n;

  PCL_TEXLET_HD void
  reset (const Vec3<S> &reference)
  {
    ref = reference;
    n = 0;
    for (int i = 0; i < 3; ++i)
      s[i] = S (0);
    for (int i = 0; i < 6; ++i)
      ss[i] = S (0);
  }

  PCL_TEXLET_HD void
  add (const Vec3<S> &p)
  {
    const Vec3<S> d = p - ref;
    s[0] += d.x; s[1] += d.y; s[2] += d.z;
    ss[0] += d.x * d.x; ss[1] += d.x * d.y; ss[2] += d.x * d.z;
    ss[3] += d.y * d.y; ss[4] += d.y * d.z; ss[5] += d.z * d.z;
    ++n;
  }

  PCL_TEXLET_HD Vec3<S>
  mean () const
  {
    const S inv = S (1) / S (n);
    return ref + make3 (s[0] * inv, s[1] * inv, s[2] * inv);
  }

  /** \brief Covariance normalised by 1/n (the population covariance). */
  PCL_TEXLET_HD void
  covariance (S c[6]) const
  {
    const S inv = S (1) / S (n);
    const S m[3] = {s[0] * inv, s[1] * inv, s[2] * inv};
    for (int r = 0, k = 0; r < 3; ++r)
      for (int col = r; col < 3; ++col, ++k)
        c[k] = ss[k] * inv - m[r] * m[col];
  }
};

/** \brief A fitted plane: P on it, unit normal N = smallest principal axis e0, in-plane axes
  * e1, e2 and the eigenvalues l0 <= l1 <= l2 of the points' (1/n) covariance.
  */
template <typename S>
struct PlaneFit
{
  Vec3<S> P, N, e1, e2;
  S lambda[3];
};

/** \brief Points spanning less than this fraction of their extent in a second direction are
  * treated as collinear: no plane is defined.
  */
template <typename S> PCL_TEXLET_HD S
collinearityLimit () { return S (1e-6); }

/** \brief PCA plane of the accumulated points. \return false if fewer than 3 points or collinear. */
template <typename S> PCL_TEXLET_HD bool
fitPlanePca (const PlaneMoments<S> &m, PlaneFit<S> &fit)
{
  if (m.n < 3)
    return false;
  S c[6];
  m.covariance (c);
  SymEigen3<S> eig;
  if (!symmetricEigen3 (c, eig))
    return false;
  if (!(eig.values[1] > collinearityLimit<S> () * eig.values[2]))
    return false;
  fit.P = m.mean ();
  fit.N = eig.vectors[0];
  fit.e1 = eig.vectors[1];
  fit.e2 = eig.vectors[2];
  for (int i = 0; i < 3; ++i)
    fit.lambda[i] = eig.values[i] > S (0) ? eig.values[i] : S (0);
  return true;
}

/** \brief The PCA plane of the points of \a nb marked in \a mask. \return false if they have none */
template <typename S> PCL_TEXLET_HD bool
fitInliersPca (const Neighbourhood<S> &nb, const unsigned char *mask, PlaneFit<S> &fit)
{
  PlaneMoments<S> m;
  m.reset (nb.point (0)); // any point of the patch keeps the sums small
  for (int k = 0; k < nb.count; ++k)
    if (mask[k])
      m.add (nb.point (k));
  return fitPlanePca (m, fit);
}

/** \brief SVD plane of \a n centred points stored row-major in \a a (n x 3, overwritten), by
  * one-sided Jacobi rotations of its columns. \a mean is the points' mean, returned as P.
  */
template <typename S> PCL_TEXLET_HD bool
fitPlaneSvd (S *a, int n, const Vec3<S> &mean, PlaneFit<S> &fit)
{
  if (n < 3)
    return false;
  S v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int sweep = 0; sweep < 40; ++sweep)
  {
    bool rotated = false;
    for (int k = 0; k < 3; ++k)
    {
      const int p = pairs[k][0], q = pairs[k][1];
      S alpha = 0, beta = 0, gamma = 0;
      for (int i = 0; i < n; ++i)
      {
        alpha += a[3 * i + p] * a[3 * i + p];
        beta += a[3 * i + q] * a[3 * i + q];
        gamma += a[3 * i + p] * a[3 * i + q];
      }
      if (gamma == S (0) || std::fabs (gamma) <= machineEpsilon<S> () * std::sqrt (alpha * beta))
        continue;
      rotated = true;
      const S zeta = (beta - alpha) / (S (2) * gamma);
      const S t = (zeta >= S (0) ? S (1) : S (-1)) / (std::fabs (zeta) + std::sqrt (S (1) + zeta * zeta));
      const S c = S (1) / std::sqrt (S (1) + t * t), s = c * t;
      for (int i = 0; i < n; ++i)
      {
        const S ap = a[3 * i + p], aq = a[3 * i + q];
        a[3 * i + p] = c * ap - s * aq;
        a[3 * i + q] = s * ap + c * aq;
      }
      for (int i = 0; i < 3; ++i)
      {
        const S vp = v[i][p], vq = v[i][q];
        v[i][p] = c * vp - s * vq;
        v[i][q] = s * vp + c * vq;
      }
    }
    if (!rotated)
      break;
  }
  S sv2[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j)
      sv2[j] += a[3 * i + j] * a[3 * i + j];
  int order[3] = {0, 1, 2}; // ascending singular values
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2 - i; ++j)
      if (sv2[order[j]] > sv2[order[j + 1]])
      {
        const int t = order[j];
        order[j] = order[j + 1];
        order[j + 1] = t;
      }
  if (!(sv2[order[1]] > collinearityLimit<S> () * sv2[order[2]]))
    return false;
  const auto column = [&v] (int j) { return make3 (v[0][j], v[1][j], v[2][j]); };
  fit.P = mean;
  fit.N = column (order[0]);
  fit.e1 = column (order[1]);
  fit.e2 = column (order[2]);
  for (int i = 0; i < 3; ++i)
    fit.lambda[i] = sv2[order[i]] / S (n);
  return true;
}

/** \brief Normal by averaging over the hexagonal ring (paper Eq. 5):
  * n = mean over adjacent neighbour pairs (i, i+1) of (p_i - p_c) x (p_(i+1) - p_c).
  * \param ring centre (index 0) and the six neighbours in angular order (1..6)
  * \param use  which ring points take part; a pair counts only if both are used
  * \return false if the centre is unused, no adjacent pair is complete, or the sum vanishes.
  */
template <typename S> PCL_TEXLET_HD bool
averagingNormal (const Vec3<S> ring[7], const bool use[7], Vec3<S> &normal)
{
  if (!use[0])
    return false;
  Vec3<S> sum = {0, 0, 0};
  int pairs = 0;
  for (int i = 0; i < 6; ++i)
  {
    const int a = 1 + i, b = 1 + (i + 1) % 6;
    if (!use[a] || !use[b])
      continue;
    sum = sum + cross (ring[a] - ring[0], ring[b] - ring[0]);
    ++pairs;
  }
  const S len = norm (sum);
  if (pairs == 0 || !(len > S (0)))
    return false;
  normal = (S (1) / len) * sum;
  return true;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
