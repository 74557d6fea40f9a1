/*
 * pcl_texlet kernels: depth noise that a texlet's points share, by line (column or row).
 *
 * Column offsets (the stripes' bands) move whole columns of a frame; row offsets (the `rows`
 * term) whole rows: the code below says columns, and the disc's rows serve where
 * Neighbourhood::lines_are_rows (line ()). Two columns du apart share
 * them with correlation a^|du| (Neighbourhood::line_correlation = a; for bands cut at random
 * columns, the probability that no cut falls between them). The shared part of two points'
 * depth noise then has covariance rho sigma_i sigma_j a^|u_i - u_j|, and a propagation through
 * Jacobians J sums the SD-weighted Jacobians of each column, G_x, and takes the quadratic form
 * sum_x sum_x' a^|x - x'| G_x G_x' (lineForm()). With a = 1 that is (sum G)(sum G)': the
 * patch moves as a whole. Patches wider than kMaxSharedLines share it whole.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/philox_rng.h>

#include <cmath>
#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Most lines (columns or rows) over which the shared noise is resolved (a disc of radius 15 px). */
constexpr int kMaxSharedLines = 31;

/** \brief The lines a patch's shared noise is resolved over: \a count from \a first; count 0
  * where the patch shares it whole (adjacent columns correlate by 1, no columns known, or the
  * patch is wider than kMaxSharedLines).
  */
struct LineSpan
{
  int first = 0;
  int count = 0;
};

template <typename S> PCL_TEXLET_HD LineSpan
sharedLines (const Neighbourhood<S> &nb)
{
  LineSpan span;
  if (!(nb.shared_fraction > S (0)) || !(nb.line_correlation < S (1)) || !nb.pixel || nb.width <= 0 ||
      nb.count == 0)
    return span;
  int lo = nb.line (0), hi = lo;
  for (int k = 1; k < nb.count; ++k)
  {
    const int c = nb.line (k);
    lo = c < lo ? c : lo;
    hi = c > hi ? c : hi;
  }
  if (hi - lo + 1 <= kMaxSharedLines)
  {
    span.first = lo;
    span.count = hi - lo + 1;
  }
  return span;
}

/** \brief The quadratic form sum_x sum_x' a^|x - x'| G_x G_x' of \a count column sums \a G
  * (dim values each), packed (upper triangle by rows) into \a out.
  */
template <typename S, int dim> PCL_TEXLET_HD void
lineForm (const S (*G)[dim], int count, S a, S *out)
{
  S power[kMaxSharedLines];
  power[0] = S (1);
  for (int d = 1; d < count; ++d)
    power[d] = power[d - 1] * a;
  for (int k = 0; k < dim * (dim + 1) / 2; ++k)
    out[k] = S (0);
  for (int x = 0; x < count; ++x)
  {
    S h[dim]; // sum_x' a^|x - x'| G_x'
    for (int i = 0; i < dim; ++i)
      h[i] = S (0);
    for (int y = 0; y < count; ++y)
    {
      const S w = power[x > y ? x - y : y - x];
      for (int i = 0; i < dim; ++i)
        h[i] += w * G[y][i];
    }
    for (int i = 0, k = 0; i < dim; ++i)
      for (int j = i; j < dim; ++j, ++k)
        out[k] += G[x][i] * h[j];
  }
}

/** \brief Philox block of the shared normals: beyond any disc's point blocks. */
constexpr std::uint32_t kSharedNoiseBlock = 0x40000000u;

/** \brief The shared part of a Monte Carlo sample's noise: a point's standardised noise is
  * sqrt(1 - rho) g + sqrt(rho) e_x, its own normal g and its column's e_x, an AR(1) series
  * across the columns (e_x = a e_(x-1) + sqrt(1 - a^2) h_x, the h from Philox blocks
  * kSharedNoiseBlock + x / 4), one e for a patch that shares it whole, so that two points'
  * noises correlate by rho a^|du|.
  */
template <typename S>
struct SharedDraw
{
  S own = S (1), root = S (0);
  LineSpan span;
  S e[kMaxSharedLines];

  /** \param whole the points' columns are not known (the ring of normal averaging): one e */
  PCL_TEXLET_HD
  SharedDraw (const Neighbourhood<S> &nb, std::uint32_t seed, std::uint32_t texlet, int s, bool whole = false)
  {
    e[0] = S (0);
    if (!(nb.shared_fraction > S (0)))
      return;
    own = std::sqrt (S (1) - nb.shared_fraction);
    root = std::sqrt (nb.shared_fraction);
    if (!whole)
      span = sharedLines (nb);
    const int n = span.count > 0 ? span.count : 1;
    const S a = span.count > 0 ? nb.line_correlation : S (1), b = std::sqrt (S (1) - a * a);
    float g[4];
    for (int x = 0; x < n; ++x)
    {
      if ((x & 3) == 0)
        normalQuad (seed, texlet, static_cast<std::uint32_t> (s), kSharedNoiseBlock + static_cast<std::uint32_t> (x >> 2),
                    g);
      e[x] = x == 0 ? S (g[0]) : a * e[x - 1] + b * S (g[x & 3]);
    }
  }

  /** \brief Point \a k's standardised noise from its own normal \a g. */
  PCL_TEXLET_HD S
  noise (float g, const Neighbourhood<S> &nb, int k) const
  {
    return own * S (g) + root * e[span.count > 0 ? nb.line (k) - span.first : 0];
  }
};

} // namespace kernels
} // namespace texlet
} // namespace pcl
