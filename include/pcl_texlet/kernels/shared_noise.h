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
 *
 * Noise shared over a window (Neighbourhood::window_fraction, window_px = w): each point's part
 * is the mean of white noise over the w x w window around its pixel, so points du, dv apart
 * correlate by the windows' overlap, tri(du) tri(dv) with tri(d) = max(0, 1 - |d| / w), and the
 * propagation takes the quadratic form sum_i sum_j tri tri G_i G_j' (windowForm(), by the
 * windows' sums). Monte Carlo draws the white noise on the cells and box-filters it (WindowDraw).
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/philox_rng.h>
#include <pcl_texlet/kernels/semidefinite_factor.h>

#include <cmath>
#include <cstdint>
#include <cstring>

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

/** \brief Widest window of shared noise resolved, pixels: wider ones count as this wide. */
constexpr int kMaxWindowPx = 15;

/** \brief Most points whose window-shared noise is resolved pair by pair: a bounding box of
  * kMaxSharedLines x kMaxSharedLines pixels (a disc of radius 15 px). Larger discs count the
  * window's part as independent noise whose variance the window multiplies by windowInflation()
  * (exact far from the disc's rim).
  */
constexpr int kMaxWindowPoints = kMaxSharedLines * kMaxSharedLines;

/** \brief A window's width \a window_px as the kernels resolve it: whole pixels, 1 .. kMaxWindowPx. */
PCL_TEXLET_HD int
resolvedWindowPx (double window_px)
{
  const double w = window_px < double (kMaxWindowPx) ? std::round (window_px) : double (kMaxWindowPx);
  return w > 1.0 ? static_cast<int> (w) : 1;
}

/** \brief The bounding box of a disc's pixels, over which its window-shared noise is resolved. */
struct WindowBox
{
  bool on = false; ///< the disc has window-shared noise and its box fits kMaxSharedLines x kMaxSharedLines
  int u0 = 0, v0 = 0, nu = 0, nv = 0;
};

/** \brief Whether the window-shared noise of \a nb is resolved (it has some, and the points'
  * bounding box fits kMaxSharedLines x kMaxSharedLines); the box's corner and size. Where \a u
  * and \a v are given (kMaxWindowPoints each) and the disc has such noise, the points' pixels go
  * there too, the first kMaxWindowPoints of them: all of them where the box is on (at most one
  * point per pixel).
  */
template <typename S> PCL_TEXLET_HD WindowBox
windowBox (const Neighbourhood<S> &nb, int *u = nullptr, int *v = nullptr)
{
  WindowBox box;
  if (!(nb.window_fraction > S (0)) || !nb.pixel || nb.width <= 0 || nb.count == 0)
    return box;
  int ulo = nb.width, uhi = -1, vlo = nb.pixel[0] / nb.width, vhi = vlo;
  for (int k = 0; k < nb.count; ++k)
  {
    const int y = nb.pixel[k] / nb.width, x = nb.pixel[k] - y * nb.width;
    if (u && k < kMaxWindowPoints)
    {
      u[k] = x;
      v[k] = y;
    }
    ulo = x < ulo ? x : ulo;
    uhi = x > uhi ? x : uhi;
    vlo = y < vlo ? y : vlo;
    vhi = y > vhi ? y : vhi;
  }
  box.u0 = ulo;
  box.v0 = vlo;
  box.nu = uhi - ulo + 1;
  box.nv = vhi - vlo + 1;
  box.on = box.nu <= kMaxSharedLines && box.nv <= kMaxSharedLines;
  return box;
}

/** \brief The means over each pixel's \a w x \a w window of values on cells: pixel (x, y) of an
  * \a nu x \a nv box averages cells x .. x + w - 1, y .. y + w - 1 of \a cell ((nu + w - 1) x
  * (nv + w - 1), by rows), times \a w (unit variance for unit normals), into \a out (nu x nv).
  * Sliding sums along the rows into \a across ((nv + w - 1) x nu), then along the columns.
  */
template <typename S> PCL_TEXLET_HD void
windowMeans (const float *cell, int nu, int nv, int w, S *across, S *out)
{
  const int cu = nu + w - 1, cv = nv + w - 1;
  for (int y = 0; y < cv; ++y)
  {
    const float *line = cell + static_cast<long> (y) * cu;
    S sum = S (0);
    for (int d = 0; d + 1 < w; ++d)
      sum += S (line[d]);
    for (int x = 0; x < nu; ++x)
    {
      sum += S (line[x + w - 1]);
      across[static_cast<long> (y) * nu + x] = sum;
      sum -= S (line[x]);
    }
  }
  const S inv_w = S (1) / S (w);
  for (int x = 0; x < nu; ++x)
  {
    S sum = S (0);
    for (int d = 0; d + 1 < w; ++d)
      sum += across[static_cast<long> (d) * nu + x];
    for (int y = 0; y < nv; ++y)
    {
      sum += across[static_cast<long> (y + w - 1) * nu + x];
      out[static_cast<long> (y) * nu + x] = sum * inv_w;
      sum -= across[static_cast<long> (y) * nu + x];
    }
  }
}

/** \brief The correlation of window-shared noise at pixel lag \a d along a row or a column: the
  * overlap of two w x w windows, tri(d) = max(0, 1 - |d| / \a w).
  */
template <typename S> PCL_TEXLET_HD S
windowOverlap (int d, int w)
{
  const int a = d < 0 ? -d : d;
  return a < w ? S (1) - S (a) / S (w) : S (0);
}

/** \brief Sum of tri(du) tri(dv) over every pixel offset: (sum over |d| < w of 1 - |d| / w)^2 = w^2. */
template <typename S> PCL_TEXLET_HD S
windowInflation (const Neighbourhood<S> &nb)
{
  return S (nb.window_px) * S (nb.window_px);
}

/** \brief Four values of S side by side, with the operations windowForm() takes on them: its
  * SIMD lane type where GNU vector types are not available (nvcc).
  */
template <typename S>
struct FourLanes
{
  S v[4];

  PCL_TEXLET_HD S &operator[] (int i) { return v[i]; }
  PCL_TEXLET_HD S operator[] (int i) const { return v[i]; }

  PCL_TEXLET_HD FourLanes &
  operator+= (const FourLanes &o)
  {
    for (int i = 0; i < 4; ++i)
      v[i] += o.v[i];
    return *this;
  }

  PCL_TEXLET_HD FourLanes
  operator- (const FourLanes &o) const
  {
    FourLanes r;
    for (int i = 0; i < 4; ++i)
      r.v[i] = v[i] - o.v[i];
    return r;
  }

  PCL_TEXLET_HD friend FourLanes
  operator* (S s, const FourLanes &o)
  {
    FourLanes r;
    for (int i = 0; i < 4; ++i)
      r.v[i] = s * o.v[i];
    return r;
  }
};

/** \brief The quadratic form sum_i sum_j tri(u_i - u_j) tri(v_i - v_j) G_i G_j' of the points'
  * \a G (\a D values each: the analytic propagation's 6 SD-weighted Jacobians, the moment
  * sampler's 9 linear weights), packed (upper triangle by rows) into \a out. \a u, \a v: the
  * points' pixels, inside the box of corner (\a u0, \a v0) and size \a nu x \a nv
  * (windowBox()), at most one point per pixel. Since tri tri is the two pixels' windows' overlap
  * over w^2, the form is (1 / w^2) sum over the windows c touching the box of H_c H_c', H_c the
  * sum of G over window c: sliding sums along the rows, then the columns. Only the block of
  * values \a lo .. \a hi - 1 is formed (the rest of \a out is 0): a texlet's analytic
  * propagation needs 3 of the 6 when P is on the centre ray. A window's values travel
  * together, four to a SIMD lane, so that each sliding step and each row of H_c H_c' is a
  * few vector operations (docs/benchmarks.md).
  */
template <typename S, int D, int lo = 0, int hi = D> PCL_TEXLET_HD void
windowForm (const S (*G)[D], const int *u, const int *v, int count, int u0, int v0, int nu, int nv, int w,
            S out[D * (D + 1) / 2])
{
  for (int k = 0; k < D * (D + 1) / 2; ++k)
    out[k] = S (0);
#if defined(__GNUC__) && !defined(__CUDACC__)
  typedef S Lane __attribute__ ((vector_size (4 * sizeof (S))));
#else
  typedef FourLanes<S> Lane;
#endif
  constexpr int dims = hi - lo, lanes = (dims + 3) / 4;
  // The points' G, four values to a lane, after a zero row (point k in row k + 1); slot names the
  // row on each cell of the box padded with w empty columns on either side, so that the sliding
  // sums need no tests: slot column p is box column p - w, and window x (box columns
  // x - w + 1 .. x) sums slot columns x + 1 .. x + w; the same for the rows. Slots, not the
  // values, fill the box: far less memory to clear per disc.
  const int pw = nu + 2 * w;
  Lane packed[kMaxWindowPoints + 1][lanes];
  std::uint16_t slot[kMaxSharedLines * (kMaxSharedLines + 2 * kMaxWindowPx)];
  for (int c = 0; c < nv * pw; ++c)
    slot[c] = 0;
  for (int l = 0; l < lanes; ++l)
    packed[0][l] = Lane{};
  for (int k = 0; k < count; ++k)
  {
    for (int l = 0; l < lanes; ++l)
      packed[k + 1][l] = Lane{};
    for (int d = 0; d < dims; ++d)
      packed[k + 1][d / 4][d % 4] = G[k][lo + d];
    slot[(v[k] - v0) * pw + (u[k] - u0 + w)] = static_cast<std::uint16_t> (k + 1);
  }
  Lane row[kMaxSharedLines + 2 * kMaxWindowPx][lanes]; // row y + w: box row y's sum over window x's columns
  for (int y = 0; y < nv + 2 * w; ++y)
    for (int l = 0; l < lanes; ++l)
      row[y][l] = Lane{};
  Lane sum[dims][lanes]; // row a of sum H_c H_c', lanes a / 4 on
  for (int a = 0; a < dims; ++a)
    for (int l = 0; l < lanes; ++l)
      sum[a][l] = Lane{};
  const int ny = nv + w - 1;
  for (int x = 0; x < nu + w - 1; ++x)
  {
    for (int y = 0; y < nv; ++y)
      for (int l = 0; l < lanes; ++l)
        row[y + w][l] += packed[slot[y * pw + x + w]][l] - packed[slot[y * pw + x]][l];
    Lane H[lanes]; // window (x, y): rows y - w + 1 .. y
    for (int l = 0; l < lanes; ++l)
      H[l] = Lane{};
    for (int y = 0; y < ny; ++y)
    {
      for (int l = 0; l < lanes; ++l)
        H[l] += row[y + w][l] - row[y][l];
      PCL_TEXLET_UNROLL_LOOP
      for (int a = 0; a < dims; ++a)
        PCL_TEXLET_UNROLL_LOOP
        for (int l = a / 4; l < lanes; ++l)
          sum[a][l] += H[a / 4][a % 4] * H[l];
    }
  }
  const S inv_w2 = S (1) / (S (w) * S (w));
  for (int a = 0; a < dims; ++a)
    for (int b = a; b < dims; ++b)
      out[packedIndex<D> (lo + a, lo + b)] = sum[a][b / 4][b % 4] * inv_w2;
}

/** \brief The windowed part of a Monte Carlo sample's noise (host only): normals on the cells of
  * the disc's bounding box widened by w - 1 (Philox blocks kWindowNoiseBlock + cell / 4), their
  * mean over each pixel's w x w window times w (windowMeans(): unit variance). Off where windowBox()
  * is off (the part then stays in SharedDraw's own noise, independent).
  */
template <typename S>
struct WindowDraw
{
  bool on = false;
  S root = S (0);
  int u0 = 0, v0 = 0, nu = 0, nv = 0;
  S b[kMaxSharedLines * kMaxSharedLines];

  /** \param box windowBox() of \a nb */
  WindowDraw (const Neighbourhood<S> &nb, const WindowBox &box, std::uint32_t seed, std::uint32_t texlet, int s);

  /** \brief Point \a k's windowed standardised noise, times sqrt(window_fraction). */
  S
  noise (const Neighbourhood<S> &nb, int k) const
  {
    if (!on)
      return S (0);
    const int p = nb.pixel[k];
    return root * b[(p / nb.width - v0) * nu + (p % nb.width - u0)];
  }
};

/** \brief Turns \a count independent normals \a e, one a line, into the AR(1) series of the
  * shared noise across the lines, e_x = a e_(x-1) + sqrt(1 - a^2) h_x: lines du apart correlate
  * by a^|du|. \a V is S or a SIMD lane type (several samples' series, one a lane).
  */
template <typename S, typename V> PCL_TEXLET_HD void
lineSeries (int count, S a, V *e)
{
  const S b = std::sqrt (S (1) - a * a);
  for (int x = 1; x < count; ++x)
    e[x] = a * e[x - 1] + b * e[x];
}

/** \brief Philox block of the shared normals: beyond any disc's point blocks. */
constexpr std::uint32_t kSharedNoiseBlock = 0x40000000u;

/** \brief The shared part of a Monte Carlo sample's noise: a point's standardised noise is
  * sqrt(1 - rho - window) g + sqrt(rho) e_x (+ the window's part, WindowDraw), its own normal g and its column's e_x, an AR(1) series
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

  /** \param lines sharedLines() of \a nb, or none where the points' columns are not known (the
    * ring of normal averaging): one e for all
    * \param window_drawn the window's part is drawn apart (WindowDraw, windowBox() on), else it stays
    * in the own part with its variance multiplied by windowInflation(), as the analytic
    * propagation takes it (addSharedNoise())
    */
  PCL_TEXLET_HD
  SharedDraw (const Neighbourhood<S> &nb, const LineSpan &lines, bool window_drawn, std::uint32_t seed,
              std::uint32_t texlet, int s)
    : span (lines)
  {
    e[0] = S (0);
    own = std::sqrt (S (1) - nb.shared_fraction +
                     (window_drawn ? -nb.window_fraction : nb.window_fraction * (windowInflation (nb) - S (1))));
    if (!(nb.shared_fraction > S (0)))
      return;
    root = std::sqrt (nb.shared_fraction);
    const int n = span.count > 0 ? span.count : 1;
    float g[4];
    for (int x = 0; x < n; ++x)
    {
      if ((x & 3) == 0)
        normalQuad (seed, texlet, static_cast<std::uint32_t> (s), kSharedNoiseBlock + static_cast<std::uint32_t> (x >> 2),
                    g);
      e[x] = S (g[x & 3]);
    }
    lineSeries (n, span.count > 0 ? nb.line_correlation : S (1), e);
  }

  /** \brief Point \a k's standardised noise from its own normal \a g. */
  PCL_TEXLET_HD S
  noise (float g, const Neighbourhood<S> &nb, int k) const
  {
    return own * S (g) + root * e[span.count > 0 ? nb.line (k) - span.first : 0];
  }
};

/** \brief Philox block of the window's normals: beyond the shared ones. */
constexpr std::uint32_t kWindowNoiseBlock = 0x50000000u;

template <typename S>
WindowDraw<S>::WindowDraw (const Neighbourhood<S> &nb, const WindowBox &box, std::uint32_t seed, std::uint32_t texlet,
                           int s)
{
  if (!box.on)
    return;
  u0 = box.u0;
  v0 = box.v0;
  nu = box.nu;
  nv = box.nv;
  const int w = nb.window_px, cells = (nu + w - 1) * (nv + w - 1);
  float cell[(kMaxSharedLines + kMaxWindowPx - 1) * (kMaxSharedLines + kMaxWindowPx - 1)];
  float g[4];
  for (int c = 0; c < cells; ++c)
  {
    if ((c & 3) == 0)
      normalQuad (seed, texlet, static_cast<std::uint32_t> (s), kWindowNoiseBlock + static_cast<std::uint32_t> (c >> 2), g);
    cell[c] = g[c & 3];
  }
  S across[(kMaxSharedLines + kMaxWindowPx - 1) * kMaxSharedLines];
  windowMeans (cell, nu, nv, w, across, b);
  root = std::sqrt (nb.window_fraction);
  on = true;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
