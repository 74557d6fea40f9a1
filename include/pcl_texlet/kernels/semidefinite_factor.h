/*
 * pcl_texlet kernels: a square-root factor F (F F' = C) of a small symmetric positive
 * semidefinite matrix, to draw Gaussian vectors with covariance C as F z from standard normals z.
 *
 * Cholesky with diagonal pivoting on C scaled to a unit diagonal: the scaling makes the
 * rank test relative to each component's own variance (the components may carry different
 * units), and the pivoting lets a rank-deficient C (more components than independent
 * sources, or components that are exact combinations of others) stop cleanly, with zero
 * columns for the missing directions instead of a square root of a negative rounding error.
 */
#pragma once

#include <pcl_texlet/kernels/sym_eigen3.h>

// Unrolls small fixed-size loops (SemidefiniteFactor::apply() runs once per Monte Carlo sample,
// addPcaModelTerms() once per point): unrolled, they are one multiply and one add per entry,
// without loop counters, and the operands stay in registers.
#if defined(__CUDACC__)
#define PCL_TEXLET_UNROLL_LOOP _Pragma ("unroll")
#elif defined(__GNUC__) && !defined(__clang__)
#define PCL_TEXLET_UNROLL_LOOP _Pragma ("GCC unroll 16")
#elif defined(__clang__)
#define PCL_TEXLET_UNROLL_LOOP _Pragma ("unroll")
#else
#define PCL_TEXLET_UNROLL_LOOP
#endif

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Index of entry (i, j), i <= j, of a symmetric N x N matrix packed row by row
  * (00 01 .. 0N-1 11 12 ..), the order of the 3x3 packed covariances (xx xy xz yy yz zz).
  */
template <int N> PCL_TEXLET_HD constexpr int
packedIndex (int i, int j)
{
  return i * N - i * (i - 1) / 2 + (j - i);
}

/** \brief F with F F' = C for a symmetric positive semidefinite N x N matrix C, lower
  * triangular up to a permutation of its rows: row i (pivot order) holds i + 1 values and gives
  * component target[i] of F z. Columns rank .. N-1 are zero.
  */
template <typename S, int N>
struct SemidefiniteFactor
{
  S rows[N * (N + 1) / 2]; ///< row i starts at i (i + 1) / 2
  int target[N];
  int rank;

  /** \brief y = F z (N values each); \a V is S or a SIMD lane type (one sample a lane). */
  template <typename V> PCL_TEXLET_HD void
  apply (const V *z, V *y) const
  {
    PCL_TEXLET_UNROLL_LOOP
    for (int i = 0; i < N; ++i)
    {
      const S *r = rows + i * (i + 1) / 2;
      V v = r[0] * z[0];
      PCL_TEXLET_UNROLL_LOOP
      for (int j = 1; j <= i; ++j)
        v += r[j] * z[j];
      y[target[i]] = v;
    }
  }
};

/** \brief Factors the packed (packedIndex()) positive semidefinite matrix \a c. Pivots whose
  * remaining variance is below about N^2 epsilon of the component's own are taken as zero:
  * the factor then reproduces C to that relative accuracy and has fewer than N non-zero
  * columns. A zero, negative or non-finite diagonal entry gives a zero row. Never produces
  * NaN from finite input.
  */
template <typename S, int N> PCL_TEXLET_HD void
factorSemidefinite (const S *c, SemidefiniteFactor<S, N> &f)
{
  S d[N], a[N][N], l[N][N];
  int perm[N];
  for (int i = 0; i < N; ++i)
  {
    const S v = c[packedIndex<N> (i, i)];
    d[i] = v > S (0) && v < S (INFINITY) ? std::sqrt (v) : S (0);
    perm[i] = i;
  }
  for (int i = 0; i < N; ++i)
    for (int j = i; j < N; ++j)
    {
      const S v = d[i] > S (0) && d[j] > S (0) ? c[packedIndex<N> (i, j)] / (d[i] * d[j]) : S (0);
      a[i][j] = a[j][i] = i == j && d[i] > S (0) ? S (1) : v;
      l[i][j] = l[j][i] = S (0);
    }
  const S tol = S (N * N) * machineEpsilon<S> ();
  f.rank = 0;
  PCL_TEXLET_UNROLL_LOOP
  for (int j = 0; j < N; ++j)
  {
    int p = j;
    for (int k = j + 1; k < N; ++k)
      if (a[k][k] > a[p][p])
        p = k;
    if (!(a[p][p] > tol))
      break; // the rest of the (scaled) matrix is zero to rounding
    if (p != j)
    {
      const int t = perm[j];
      perm[j] = perm[p];
      perm[p] = t;
      for (int k = 0; k < N; ++k)
      {
        const S r = a[j][k];
        a[j][k] = a[p][k];
        a[p][k] = r;
      }
      for (int k = 0; k < N; ++k)
      {
        const S r = a[k][j];
        a[k][j] = a[k][p];
        a[k][p] = r;
      }
      for (int k = 0; k < j; ++k)
      {
        const S r = l[j][k];
        l[j][k] = l[p][k];
        l[p][k] = r;
      }
    }
    const S ljj = std::sqrt (a[j][j]);
    l[j][j] = ljj;
    PCL_TEXLET_UNROLL_LOOP
    for (int i = j + 1; i < N; ++i)
      l[i][j] = a[i][j] / ljj;
    PCL_TEXLET_UNROLL_LOOP
    for (int i = j + 1; i < N; ++i)
      PCL_TEXLET_UNROLL_LOOP
      for (int k = j + 1; k <= i; ++k)
        a[i][k] = a[k][i] = a[i][k] - l[i][j] * l[k][j];
    f.rank = j + 1;
  }
  for (int i = 0, r = 0; i < N; ++i)
  {
    f.target[i] = perm[i];
    for (int j = 0; j <= i; ++j, ++r)
      f.rows[r] = d[perm[i]] * l[i][j];
  }
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
