/*
 * pcl_texlet kernels: closed-form eigen decomposition of a symmetric 3x3 matrix.
 *
 * The paper (Sect. 3.1) prefers this to SVD on a GPU because it is not iterative: the
 * eigenvalues are the roots of the characteristic cubic (trigonometric form), the smallest
 * eigenvector is the null vector of A - l0 I (a cross product of two of its rows), and the
 * other two are the eigenvectors of the 2x2 problem in the plane orthogonal to it, which stays
 * well defined when the two in-plane eigenvalues are (nearly) equal, as on a round planar patch.
 */
#pragma once

#include <pcl_texlet/kernels/vec3.h>

namespace pcl
{
namespace texlet
{
namespace kernels
{

template <typename S> PCL_TEXLET_HD S
machineEpsilon () { return sizeof (S) == sizeof (float) ? S (1.1920929e-07) : S (2.220446049250313e-16); }

/** \brief Eigen decomposition, eigenvalues ascending, vectors orthonormal. */
template <typename S>
struct SymEigen3
{
  S values[3];
  Vec3<S> vectors[3];
};

/** \brief A v for a packed symmetric matrix (xx xy xz yy yz zz). */
template <typename S> PCL_TEXLET_HD Vec3<S>
symMul (const S a[6], const Vec3<S> &v)
{
  return {a[0] * v.x + a[1] * v.y + a[2] * v.z, a[1] * v.x + a[3] * v.y + a[4] * v.z,
          a[2] * v.x + a[4] * v.y + a[5] * v.z};
}

/** \brief Any unit vector orthogonal to unit vector \a n. */
template <typename S> PCL_TEXLET_HD Vec3<S>
anyOrthogonal (const Vec3<S> &n)
{
  const S ax = std::fabs (n.x), ay = std::fabs (n.y), az = std::fabs (n.z);
  const Vec3<S> axis = (ax <= ay && ax <= az) ? make3<S> (1, 0, 0) : (ay <= az ? make3<S> (0, 1, 0) : make3<S> (0, 0, 1));
  return normalized (cross (n, axis));
}

/** \brief Eigenvalues (ascending) of a packed symmetric 3x3 matrix, trigonometric form. */
template <typename S> PCL_TEXLET_HD void
symEigenvalues3 (const S a[6], S out[3])
{
  const S m = (a[0] + a[3] + a[5]) / S (3);
  const S b00 = a[0] - m, b11 = a[3] - m, b22 = a[5] - m;
  const S off = a[1] * a[1] + a[2] * a[2] + a[4] * a[4];
  const S p = (b00 * b00 + b11 * b11 + b22 * b22 + S (2) * off) / S (6);
  if (p <= S (0))
  {
    out[0] = out[1] = out[2] = m;
    return;
  }
  const S q = (b00 * (b11 * b22 - a[4] * a[4]) - a[1] * (a[1] * b22 - a[4] * a[2]) +
               a[2] * (a[1] * a[4] - b11 * a[2])) / S (2);
  const S disc = p * p * p - q * q;
  const S phi = std::atan2 (std::sqrt (disc > S (0) ? disc : S (0)), q) / S (3);
  const S sp = std::sqrt (p), c = std::cos (phi), s = std::sin (phi);
  const S sqrt3 = S (1.7320508075688772935);
  out[0] = m - sp * (c + sqrt3 * s);
  out[1] = m - sp * (c - sqrt3 * s);
  out[2] = m + S (2) * sp * c;
}

/** \brief Null vector of (A - l I) from the best-conditioned cross product of its rows.
  * \return false when (A - l I) has rank < 2, i.e. l is (nearly) a repeated eigenvalue.
  */
template <typename S> PCL_TEXLET_HD bool
symNullVector (const S a[6], S l, Vec3<S> &v)
{
  const Vec3<S> r0 = {a[0] - l, a[1], a[2]}, r1 = {a[1], a[3] - l, a[4]}, r2 = {a[2], a[4], a[5] - l};
  const Vec3<S> c01 = cross (r0, r1), c02 = cross (r0, r2), c12 = cross (r1, r2);
  const S n01 = squaredNorm (c01), n02 = squaredNorm (c02), n12 = squaredNorm (c12);
  Vec3<S> best = c01;
  S best_n = n01;
  if (n02 > best_n) { best = c02; best_n = n02; }
  if (n12 > best_n) { best = c12; best_n = n12; }
  // a is scaled to max |entry| = 1: a relative gap of ~sqrt(eps) is what can be resolved.
  if (!(best_n > S (64) * machineEpsilon<S> ()))
    return false;
  v = (S (1) / std::sqrt (best_n)) * best;
  return true;
}

/** \brief Eigen decomposition of a packed symmetric 3x3 matrix (xx xy xz yy yz zz).
  * \return false for a zero or non-finite matrix.
  */
template <typename S> PCL_TEXLET_HD bool
symmetricEigen3 (const S cov[6], SymEigen3<S> &out)
{
  S scale = S (0);
  for (int i = 0; i < 6; ++i)
    scale = std::fabs (cov[i]) > scale ? std::fabs (cov[i]) : scale;
  if (!(scale > S (0)) || !std::isfinite (scale))
    return false;
  S a[6];
  for (int i = 0; i < 6; ++i)
    a[i] = cov[i] / scale;

  S l[3];
  symEigenvalues3 (a, l);
  Vec3<S> e0;
  if (!symNullVector (a, l[0], e0))
  {
    // l0 ~ l1: the smallest eigenvector is any vector orthogonal to the largest one.
    Vec3<S> e2;
    e0 = symNullVector (a, l[2], e2) ? anyOrthogonal (e2) : make3<S> (0, 0, 1);
  }
  const Vec3<S> u = anyOrthogonal (e0), w = cross (e0, u);
  const Vec3<S> au = symMul (a, u), aw = symMul (a, w);
  const S a11 = dot (u, au), a12 = dot (u, aw), a22 = dot (w, aw);
  const S theta = S (0.5) * std::atan2 (S (2) * a12, a11 - a22);
  const S ct = std::cos (theta), st = std::sin (theta);
  const Vec3<S> e2 = ct * u + st * w;
  const Vec3<S> e1 = (-st) * u + ct * w;

  out.vectors[0] = e0;
  out.vectors[1] = e1;
  out.vectors[2] = e2;
  // Rayleigh quotients: more accurate than the cubic's roots for the small eigenvalue.
  out.values[0] = dot (e0, symMul (a, e0)) * scale;
  out.values[1] = dot (e1, symMul (a, e1)) * scale;
  out.values[2] = dot (e2, symMul (a, e2)) * scale;
  return true;
}

/** \brief Eigen decomposition of a packed symmetric 3x3 matrix that is nearly diagonal in the
  * orthonormal basis \a basis (e.g. a slightly perturbed covariance whose unperturbed
  * eigenvectors are known), by cyclic Jacobi rotations in that basis. It converges
  * quadratically from a good basis and needs no trigonometric function, which makes it much
  * cheaper than symmetricEigen3() for the re-fits of Monte Carlo sampling; it agrees with it
  * to rounding. \return false for a zero or non-finite matrix or if 8 sweeps did not converge
  * (then use symmetricEigen3()).
  */
template <typename S> PCL_TEXLET_HD bool
symmetricEigen3Near (const S cov[6], const Vec3<S> basis[3], SymEigen3<S> &out)
{
  // b = E' A E, packed 00 01 02 11 12 22.
  const Vec3<S> a0 = symMul (cov, basis[0]), a1 = symMul (cov, basis[1]), a2 = symMul (cov, basis[2]);
  S b[3][3];
  b[0][0] = dot (basis[0], a0); b[0][1] = dot (basis[0], a1); b[0][2] = dot (basis[0], a2);
  b[1][1] = dot (basis[1], a1); b[1][2] = dot (basis[1], a2); b[2][2] = dot (basis[2], a2);
  b[1][0] = b[0][1]; b[2][0] = b[0][2]; b[2][1] = b[1][2];
  const S norm2 = b[0][0] * b[0][0] + b[1][1] * b[1][1] + b[2][2] * b[2][2] +
                  S (2) * (b[0][1] * b[0][1] + b[0][2] * b[0][2] + b[1][2] * b[1][2]);
  if (!(norm2 > S (0)) || !(norm2 < S (1e300)))
    return false;
  S v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const S tol2 = machineEpsilon<S> () * machineEpsilon<S> () * norm2;
  bool converged = false;
  for (int sweep = 0; sweep < 8 && !converged; ++sweep)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int p = k == 2 ? 1 : 0, q = k == 0 ? 1 : 2, r = 3 - p - q;
      const S apq = b[p][q];
      if (apq * apq <= tol2 * S (1e-4))
        continue;
      const S theta = (b[q][q] - b[p][p]) / (S (2) * apq);
      const S t = (theta >= S (0) ? S (1) : S (-1)) / (std::fabs (theta) + std::sqrt (S (1) + theta * theta));
      const S c = S (1) / std::sqrt (S (1) + t * t), s = t * c;
      b[p][p] -= t * apq;
      b[q][q] += t * apq;
      b[p][q] = b[q][p] = S (0);
      const S brp = b[r][p], brq = b[r][q];
      b[r][p] = b[p][r] = c * brp - s * brq;
      b[r][q] = b[q][r] = s * brp + c * brq;
      for (int i = 0; i < 3; ++i)
      {
        const S vp = v[i][p], vq = v[i][q];
        v[i][p] = c * vp - s * vq;
        v[i][q] = s * vp + c * vq;
      }
    }
    converged = b[0][1] * b[0][1] + b[0][2] * b[0][2] + b[1][2] * b[1][2] <= tol2;
  }
  if (!converged)
    return false;
  int order[3] = {0, 1, 2}; // ascending eigenvalues
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2 - i; ++j)
      if (b[order[j]][order[j]] > b[order[j + 1]][order[j + 1]])
      {
        const int t = order[j];
        order[j] = order[j + 1];
        order[j + 1] = t;
      }
  for (int i = 0; i < 3; ++i)
  {
    const int j = order[i];
    out.values[i] = b[j][j];
    out.vectors[i] = v[0][j] * basis[0] + v[1][j] * basis[1] + v[2][j] * basis[2];
  }
  return true;
}

/** \brief The smallest eigenvalue, its eigenvector and the other two eigenvalues of a
  * symmetric 3x3 matrix. */
template <typename S>
struct SmallestEigen3
{
  S values[3]; ///< ascending
  Vec3<S> vector;
};

/** \brief One Newton step of smallestEigen3NearFirstAxis() at the trial eigenvalue \a l: the
  * eigenvector's (x, y) for l, the step \a dl, and a11, det, both positive where l is below the
  * trailing 2x2 block's eigenvalues. \a V is the scalar \a S or a SIMD lane of them (four samples'
  * re-fits at once, pca_sampler.h), so both take the same arithmetic.
  */
template <typename S, typename V> PCL_TEXLET_HD void
nearFirstAxisNewtonStep (const V b[6], const V &l, V &a11, V &det, V &x, V &y, V &dl)
{
  a11 = b[3] - l;
  const V a22 = b[5] - l, a12 = b[4];
  det = a11 * a22 - a12 * a12;
  const V inv = S (1) / det;
  x = (a12 * b[2] - a22 * b[1]) * inv;
  y = (a12 * b[1] - a11 * b[2]) * inv;
  const V g = b[0] + b[1] * x + b[2] * y;
  dl = (g - l) / (S (1) + x * x + y * y);
}

/** \brief std::sqrt in place, as a function object (otherEigenvaluesOf() of a scalar). */
template <typename S>
struct ScalarSqrt
{
  PCL_TEXLET_HD void operator() (S &v) const { v = std::sqrt (v); }
};

/** \brief The two larger eigenvalues of \a b (ascending, \a l1 <= \a l2) from its smallest \a l:
  * l1 + l2 = trace - l, l1 l2 = (sum of the principal 2x2 minors) - l (l1 + l2). \a sqrt_of
  * takes the square root of a V in place. */
template <typename S, typename V, typename Sqrt> PCL_TEXLET_HD void
otherEigenvaluesOf (const V b[6], const V &l, Sqrt sqrt_of, V &l1, V &l2)
{
  const V sum = b[0] + b[3] + b[5] - l;
  const V minors = b[0] * b[3] - b[1] * b[1] + b[0] * b[5] - b[2] * b[2] + b[3] * b[5] - b[4] * b[4];
  const V prod = minors - l * sum;
  const V disc = sum * sum - S (4) * prod;
  V root = disc > S (0) ? disc : V {};
  sqrt_of (root);
  l2 = S (0.5) * (sum + root);
  l1 = l2 > S (0) ? prod / l2 : sum - l2; // no cancellation when l1 << l2
}

/** \brief Smallest eigenpair of a packed symmetric 3x3 matrix \a b (00 01 02 11 12 22) that is
  * nearly diagonal with its smallest eigenvalue near b00, e.g. a perturbed covariance written
  * in the eigenbasis of the unperturbed one, smallest axis first. The eigenvector is taken as
  * v = (1, x, y): for a trial eigenvalue l, rows 1 and 2 of (B - l I) v = 0 give (x, y) by a
  * 2x2 solve, row 0 gives g(l) = b00 + b01 x + b02 y, and Newton's method on l - g(l) = 0
  * (derivative 1 + x^2 + y^2) converges quadratically from l = b00: a few steps of about 20
  * flops where a Jacobi sweep costs over a hundred, with no trigonometric function. The other
  * two eigenvalues follow from the trace and the sum of the principal 2x2 minors.
  * \return false if 8 steps did not converge, or the matrix is non-finite, or the eigenvalue
  * found is not below both eigenvalues of the trailing 2x2 block (then, by interlacing, it
  * need not be the smallest): then use symmetricEigen3Near() or symmetricEigen3().
  */
template <typename S> PCL_TEXLET_HD bool
smallestEigen3NearFirstAxis (const S b[6], SmallestEigen3<S> &out)
{
  const S scale = std::fabs (b[3]) + std::fabs (b[5]);
  if (!(scale > S (0)) || !(scale < S (INFINITY)))
    return false;
  const S tol = S (4) * machineEpsilon<S> () * scale;
  S l = b[0], x = S (0), y = S (0);
  bool converged = false;
  for (int step = 0; step < 8 && !converged; ++step)
  {
    S a11, det, dl;
    nearFirstAxisNewtonStep<S> (b, l, a11, det, x, y, dl);
    if (!(a11 > S (0)) || !(det > S (0)))
      return false; // l is not below the trailing block's eigenvalues
    l += dl;
    converged = std::fabs (dl) <= tol;
  }
  if (!converged)
    return false;
  // (x, y) are those of the last step's l, within tol of the converged one: they differ from
  // the converged l's by about tol |(x, y)| / gap, far below rounding.
  const S inv_norm = S (1) / std::sqrt (S (1) + x * x + y * y);
  out.vector = make3 (inv_norm, x * inv_norm, y * inv_norm);
  out.values[0] = l;
  otherEigenvaluesOf<S> (b, l, ScalarSqrt<S> (), out.values[1], out.values[2]);
  return true;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
