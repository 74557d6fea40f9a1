/*
 * pcl_texlet kernels: the window's form of a texlet whose disc is whole, from tables made once.
 *
 * windowForm() sums a disc's SD-weighted Jacobians G over every window touching its box, which
 * costs (nu + w - 1)(nv + w - 1) windows per texlet. Where every pixel of the disc has a point,
 * the points are the disc's own offsets in disc order, so the kernel
 * K (o, o') = tri (du - du') tri (dv - dv') over them is the same for every such texlet. G is
 * smooth over a disc (a plane's Jacobians times the model's SD), so the form is taken on the
 * quadratics phi (o) = (1, du, dv, du^2, du dv, dv^2): with Psi = K Phi and Phi' K Phi = L L',
 * the form G' K G is P' P + R, P = L^-1 Psi' G (6 values per G's value, one pass over the
 * points), and R = r' K r >= 0 for the part r of G that no quadratic holds (K-orthogonal to
 * them), second order in it and left out: an under-estimate, largest where the window is narrow
 * against the noise in the Jacobians, so the tables serve windows of kMinWindowDiscPx and more.
 * Outliers and pixels without a reading, up to kMaxWindowDiscGaps, are gaps that the quadratics'
 * fit fills (windowDiscFormOf()). Its error: docs/benchmarks.md, "Discs from tables".
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/semidefinite_factor.h>
#include <pcl_texlet/kernels/shared_noise.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Basis functions of a whole disc's window form: the quadratics in the pixel offset. */
constexpr int kWindowDiscBasis = 6;

/** \brief The narrowest window the tables serve, pixels: below it the part of the Jacobians no
  * quadratic holds weighs too much in the form (docs/benchmarks.md), and the windows' sums are cheap.
  */
constexpr int kMinWindowDiscPx = 6;

/** \brief The tables of the window's form on a whole disc for one window width: each disc
  * offset's row of L^-1 Psi' (the basis, kWindowDiscBasis values), in disc order, four offsets
  * side by side (offset o's value a at lanes[o / 4][a][o % 4], zero beyond the disc) so that a
  * propagation summing four points at a time in SIMD lanes projects them as it goes; and its
  * row of L^-1 Phi' (the fit of the quadratics, for the gaps).
  */
template <typename S>
struct WindowDiscForm
{
  int window_px = 0;
  int size = 0; ///< the disc's offsets (at most kMaxWindowPoints)
  S lanes[(kMaxWindowPoints + 3) / 4][kWindowDiscBasis][4];
  S fit[kMaxWindowPoints][kWindowDiscBasis];
  int du[kMaxWindowPoints], dv[kMaxWindowPoints]; ///< the offsets

  /** \brief Offset \a o's basis value \a a (row a of L^-1 Psi'). */
  PCL_TEXLET_HD S
  at (int o, int a) const { return lanes[o >> 2][a][o & 3]; }
};

/** \brief Most disc offsets without an inlier (no reading, or an outlier) that windowDiscGapForm() fills. */
constexpr int kMaxWindowDiscGaps = 8;

/** \brief Makes \a form for the disc of \a size offsets \a du, \a dv and a window of \a w
  * pixels. \return false (and \a form unusable) where the disc is too small or too large for the
  * quadratics, or they are not independent under the window's kernel.
  */
template <typename S> bool
makeWindowDiscForm (const int *du, const int *dv, int size, int w, WindowDiscForm<S> &form)
{
  constexpr int m = kWindowDiscBasis;
  form.window_px = w;
  form.size = size;
  if (size < 2 * m || size > kMaxWindowPoints || w < 2)
    return false;
  int reach = 1;
  for (int o = 0; o < size; ++o)
    reach = std::max (reach, std::max (std::abs (du[o]), std::abs (dv[o])));
  const auto phi = [&] (int o, double f[m]) {
    const double x = double (du[o]) / reach, y = double (dv[o]) / reach;
    f[0] = 1.0; f[1] = x; f[2] = y; f[3] = x * x; f[4] = x * y; f[5] = y * y;
  };
  std::unique_ptr<double[][m]> psi (new double[size][m]);
  double gram[m][m] = {};
  for (int o = 0; o < size; ++o)
  {
    for (int a = 0; a < m; ++a)
      psi[o][a] = 0.0;
    for (int p = 0; p < size; ++p)
    {
      const double k = windowOverlap<double> (du[o] - du[p], w) * windowOverlap<double> (dv[o] - dv[p], w);
      if (k == 0.0)
        continue;
      double f[m];
      phi (p, f);
      for (int a = 0; a < m; ++a)
        psi[o][a] += k * f[a];
    }
    double f[m];
    phi (o, f);
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b)
        gram[a][b] += f[a] * psi[o][b];
  }
  // gram = L L' (Cholesky); each offset's row L^-1 psi (o) by forward substitution.
  double L[m][m] = {};
  for (int j = 0; j < m; ++j)
  {
    double d = gram[j][j];
    for (int k = 0; k < j; ++k)
      d -= L[j][k] * L[j][k];
    if (!(d > 1e-12 * gram[j][j]))
      return false;
    L[j][j] = std::sqrt (d);
    for (int i = j + 1; i < m; ++i)
    {
      double s = gram[i][j];
      for (int k = 0; k < j; ++k)
        s -= L[i][k] * L[j][k];
      L[i][j] = s / L[j][j];
    }
  }
  for (int g = 0; g < (size + 3) / 4; ++g)
    for (int a = 0; a < m; ++a)
      for (int l = 0; l < 4; ++l)
        form.lanes[g][a][l] = S (0);
  for (int o = 0; o < size; ++o)
  {
    double row[m], f[m], fit[m];
    phi (o, f);
    for (int a = 0; a < m; ++a)
    {
      double s = psi[o][a], t = f[a];
      for (int k = 0; k < a; ++k)
      {
        s -= L[a][k] * row[k];
        t -= L[a][k] * fit[k];
      }
      row[a] = s / L[a][a];
      fit[a] = t / L[a][a];
      form.lanes[o >> 2][a][o & 3] = static_cast<S> (row[a]);
      form.fit[o][a] = static_cast<S> (fit[a]);
    }
    form.du[o] = du[o];
    form.dv[o] = dv[o];
  }
  return true;
}

/** \brief The gaps of a disc in its window tables (Neighbourhood::window_disc): the offsets
  * without a reading (Neighbourhood::disc_offset) or with an outlier (mask 0) into \a gap.
  * \return how many, or -1 where the disc has no tables or more than kMaxWindowDiscGaps gaps.
  */
template <typename S> PCL_TEXLET_HD int
windowDiscGaps (const Neighbourhood<S> &nb, const unsigned char *mask, int gap[kMaxWindowDiscGaps])
{
  if (!nb.window_disc)
    return -1;
  const int size = nb.window_disc->size;
  if (!nb.disc_offset && nb.count != size)
    return -1;
  int gaps = 0;
  if (!nb.disc_offset)
  {
    // A whole disc: its gaps are its outliers; eight inliers (mask bytes of 1) skipped at once.
    for (int k = 0; k < size;)
    {
      std::uint64_t word = 0;
      if (k + 8 <= size)
        std::memcpy (&word, mask + k, sizeof word);
      if (word == 0x0101010101010101ull)
      {
        k += 8;
        continue;
      }
      if (!mask[k])
      {
        if (gaps == kMaxWindowDiscGaps)
          return -1;
        gap[gaps++] = k;
      }
      ++k;
    }
    return gaps;
  }
  if (size - nb.count > kMaxWindowDiscGaps)
    return -1;
  // The offsets before each point's that no point has (no reading), and the points' own where
  // they are outliers, in the disc's order.
  int o = 0;
  for (int k = 0; k <= nb.count; ++k)
  {
    const int next = k < nb.count ? nb.disc_offset[k] : size;
    for (; o < next; ++o)
    {
      if (gaps == kMaxWindowDiscGaps)
        return -1;
      gap[gaps++] = o;
    }
    if (k < nb.count && !mask[k])
    {
      if (gaps == kMaxWindowDiscGaps)
        return -1;
      gap[gaps++] = next;
    }
    o = next + 1;
  }
  return gaps;
}

/** \brief The points' rows of the basis of \a nb's window tables, four points to a lane group:
  * the tables' own where the disc is whole, else gathered into \a gathered by
  * Neighbourhood::disc_offset (zero beyond the points).
  */
template <typename S> PCL_TEXLET_HD const S (*windowDiscBasisOf (const Neighbourhood<S> &nb,
                                                                 S (*gathered)[kWindowDiscBasis][4]))[kWindowDiscBasis][4]
{
  if (!nb.disc_offset)
    return nb.window_disc->lanes;
  const int groups = (nb.count + 3) / 4;
  for (int g = 0; g < groups; ++g)
    for (int a = 0; a < kWindowDiscBasis; ++a)
      for (int l = 0; l < 4; ++l)
      {
        const int k = 4 * g + l;
        gathered[g][a][l] = k < nb.count ? nb.window_disc->at (nb.disc_offset[k], a) : S (0);
      }
  return gathered;
}

/** \brief windowForm()'s block \a lo .. \a hi - 1 of \a out for a whole disc, from its points'
  * projections \a R on the tables' basis (R[a][d]: value d's sum over the points of basis value
  * a times it; an outlier's values are 0), with the offsets \a gap (\a gaps of them, at most
  * kMaxWindowDiscGaps: the outliers) filled by the quadratics' fit S, solved with it. Then
  * G = Gf - S on the gaps, and G' K G = Gf' K Gf - 2 S' (K Gf) + S' K S: Gf' K Gf = P' P, K Gf at a
  * gap from the tables (basis . P), S' K S exact.
  */
template <typename S, int D> PCL_TEXLET_HD void
windowDiscFormOf (const S (*R)[D], int lo, int hi, const WindowDiscForm<S> &form, const int *gap,
                  int gaps, S out[D * (D + 1) / 2])
{
  constexpr int m = kWindowDiscBasis;
  S fill[kMaxWindowDiscGaps][D], kg[kMaxWindowDiscGaps][kMaxWindowDiscGaps];
  if (gaps > 0)
  {
    // The fill S = F (R + B S) at the gaps (F: their fit rows, B: their basis rows): solve
    // (I - F B) S = F R by elimination with partial pivoting; I - F B is near I for a few gaps.
    S a[kMaxWindowDiscGaps][kMaxWindowDiscGaps];
    for (int g = 0; g < gaps; ++g)
    {
      for (int h = 0; h < gaps; ++h)
      {
        S fb = S (0);
        for (int c = 0; c < m; ++c)
          fb += form.fit[gap[g]][c] * form.at (gap[h], c);
        a[g][h] = (g == h ? S (1) : S (0)) - fb;
        kg[g][h] = windowOverlap<S> (form.du[gap[g]] - form.du[gap[h]], form.window_px) *
                   windowOverlap<S> (form.dv[gap[g]] - form.dv[gap[h]], form.window_px);
      }
      for (int d = lo; d < hi; ++d)
      {
        S v = S (0);
        for (int c = 0; c < m; ++c)
          v += form.fit[gap[g]][c] * R[c][d];
        fill[g][d] = v;
      }
    }
    for (int j = 0; j < gaps; ++j)
    {
      int p = j;
      for (int i = j + 1; i < gaps; ++i)
        p = std::fabs (a[i][j]) > std::fabs (a[p][j]) ? i : p;
      if (p != j)
      {
        for (int k = 0; k < gaps; ++k)
        {
          const S t = a[j][k]; a[j][k] = a[p][k]; a[p][k] = t;
        }
        for (int d = lo; d < hi; ++d)
        {
          const S t = fill[j][d]; fill[j][d] = fill[p][d]; fill[p][d] = t;
        }
      }
      const S inv = S (1) / a[j][j];
      for (int i = j + 1; i < gaps; ++i)
      {
        const S f = a[i][j] * inv;
        for (int k = j; k < gaps; ++k)
          a[i][k] -= f * a[j][k];
        for (int d = lo; d < hi; ++d)
          fill[i][d] -= f * fill[j][d];
      }
    }
    for (int j = gaps - 1; j >= 0; --j)
      for (int d = lo; d < hi; ++d)
      {
        S v = fill[j][d];
        for (int k = j + 1; k < gaps; ++k)
          v -= a[j][k] * fill[k][d];
        fill[j][d] = v / a[j][j];
      }
  }
  // The filled disc's projection.
  S P[m][D];
  for (int c = 0; c < m; ++c)
    for (int d = lo; d < hi; ++d)
    {
      S p = R[c][d];
      for (int g = 0; g < gaps; ++g)
        p += form.at (gap[g], c) * fill[g][d];
      P[c][d] = p;
    }
  // K Gf at each gap from the tables, less half of K S there (so that -2 S' K Gf + S' K S is
  // the sum over the gaps of -(S kf' + kf S')).
  S kf[kMaxWindowDiscGaps][D];
  for (int g = 0; g < gaps; ++g)
    for (int d = lo; d < hi; ++d)
    {
      S v = S (0);
      for (int c = 0; c < m; ++c)
        v += form.at (gap[g], c) * P[c][d];
      for (int h = 0; h < gaps; ++h)
        v -= S (0.5) * kg[g][h] * fill[h][d];
      kf[g][d] = v;
    }
  for (int k = 0; k < D * (D + 1) / 2; ++k)
    out[k] = S (0);
  for (int i = lo; i < hi; ++i)
    for (int j = i; j < hi; ++j)
    {
      S v = S (0);
      for (int c = 0; c < m; ++c)
        v += P[c][i] * P[c][j];
      for (int g = 0; g < gaps; ++g)
        v -= fill[g][i] * kf[g][j] + kf[g][i] * fill[g][j];
      out[packedIndex<D> (i, j)] = v;
    }
}

/** \brief windowForm() of a disc whose every offset holds a point (in disc order) of values \a G
  * (an outlier's 0), by \a form's tables (windowDiscFormOf(), no gaps): the same block
  * \a lo .. \a hi - 1 of \a out.
  */
template <typename S, int D, int lo = 0, int hi = D> PCL_TEXLET_HD void
windowDiscForm (const S (*G)[D], const WindowDiscForm<S> &form, S out[D * (D + 1) / 2])
{
  S R[kWindowDiscBasis][D] = {};
  for (int o = 0; o < form.size; ++o)
    PCL_TEXLET_UNROLL_LOOP
    for (int a = 0; a < kWindowDiscBasis; ++a)
    {
      const S b = form.at (o, a);
      PCL_TEXLET_UNROLL_LOOP
      for (int d = lo; d < hi; ++d)
        R[a][d] += b * G[o][d];
    }
  windowDiscFormOf<S, D> (R, lo, hi, form, nullptr, 0, out);
}

/** \brief The whole-disc window forms of one disc, one per window width, made when first asked
  * for, and each texlet's map of its points to the disc's offsets (host only; one per worker
  * thread, so never shared).
  */
template <typename S>
class WindowDiscForms
{
public:
  /** \param du, dv the disc's offsets in disc order, kept by reference */
  WindowDiscForms (const int *du, const int *dv, int size) : du_ (du), dv_ (dv), size_ (size), offset_ (size) {}

  /** \brief The disc offset of each of \a count points of pixels \a pixel (v * width + u, in
    * disc order) of the disc around (cu, cv) in a frame of \a width x \a height, kept until the
    * next call; null where they are not the disc's pixels in disc order.
    */
  const int *
  offsetsOf (const int *pixel, int count, int cu, int cv, int width, int height)
  {
    int k = 0;
    for (int o = 0; o < size_ && k < count; ++o)
    {
      const int u = cu + du_[o], v = cv + dv_[o];
      if (u < 0 || v < 0 || u >= width || v >= height || pixel[k] != v * width + u)
        continue;
      offset_[k++] = o;
    }
    return k == count ? offset_.data () : nullptr;
  }

  /** \brief The form for a window of \a w pixels (1 .. kMaxWindowPx), or null where none is made
    * (below kMinWindowDiscPx, or a disc too small for the quadratics). */
  const WindowDiscForm<S> *
  of (int w)
  {
    if (w < kMinWindowDiscPx || w > kMaxWindowPx)
      return nullptr;
    if (!tried_[w])
    {
      tried_[w] = true;
      std::unique_ptr<WindowDiscForm<S>> form (new WindowDiscForm<S>);
      if (makeWindowDiscForm (du_, dv_, size_, w, *form))
        forms_[w] = std::move (form);
    }
    return forms_[w].get ();
  }

private:
  const int *du_, *dv_;
  int size_;
  std::vector<int> offset_;
  bool tried_[kMaxWindowPx + 1] = {};
  std::unique_ptr<WindowDiscForm<S>> forms_[kMaxWindowPx + 1];
};

} // namespace kernels
} // namespace texlet
} // namespace pcl
