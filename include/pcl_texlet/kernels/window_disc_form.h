/*
 * pcl_texlet kernels: the window's form of a texlet whose disc is whole, from tables made once.
 *
 * windowForm() sums a disc's SD-weighted Jacobians G over every window touching its box, which
 * costs (nu + w - 1)(nv + w - 1) windows per texlet. Where every pixel of the disc has a point
 * and every point is an inlier, the points are the disc's own offsets in disc order, so the
 * kernel K (o, o') = tri (du - du') tri (dv - dv') over them is the same for every such texlet.
 * G is smooth over a disc (a plane's Jacobians times the model's SD), so the form is taken on
 * the quadratics phi (o) = (1, du, dv, du^2, du dv, dv^2): with Psi = K Phi and
 * Phi' K Phi = L L', the form G' K G is P' P + R, P = L^-1 Psi' G (6 values per G's value, one
 * pass over the points), and R = r' K r >= 0 for the part r of G that no quadratic holds
 * (K-orthogonal to them), second order in it and left out (docs/benchmarks.md).
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/semidefinite_factor.h>
#include <pcl_texlet/kernels/shared_noise.h>

#include <cmath>
#include <memory>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Basis functions of a whole disc's window form: the quadratics in the pixel offset. */
constexpr int kWindowDiscBasis = 6;

/** \brief The tables of the window's form on a whole disc for one window width: each disc
  * offset's row of L^-1 Psi' (kWindowDiscBasis values), in disc order, four offsets side by side
  * (offset o's value a at lanes[o / 4][a][o % 4], zero beyond the disc) so that a propagation
  * summing four points at a time in SIMD lanes projects them as it goes.
  */
template <typename S>
struct WindowDiscForm
{
  int window_px = 0;
  int size = 0; ///< the disc's offsets (at most kMaxWindowPoints)
  S lanes[(kMaxWindowPoints + 3) / 4][kWindowDiscBasis][4];

  /** \brief Offset \a o's basis value \a a. */
  PCL_TEXLET_HD S
  at (int o, int a) const { return lanes[o >> 2][a][o & 3]; }
};

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
    double row[m];
    for (int a = 0; a < m; ++a)
    {
      double s = psi[o][a];
      for (int k = 0; k < a; ++k)
        s -= L[a][k] * row[k];
      row[a] = s / L[a][a];
      form.lanes[o >> 2][a][o & 3] = static_cast<S> (row[a]);
    }
  }
  return true;
}

/** \brief The form P' P of the projections \a P (P[a][d]: value d's sum over the points of
  * basis value a times it) of values \a lo .. \a hi - 1, packed D x D into \a out (the rest 0).
  */
template <typename S, int D> PCL_TEXLET_HD void
windowFormOfProjection (const S (*P)[D], int lo, int hi, S out[D * (D + 1) / 2])
{
  for (int k = 0; k < D * (D + 1) / 2; ++k)
    out[k] = S (0);
  for (int i = lo; i < hi; ++i)
    for (int j = i; j < hi; ++j)
    {
      S s = S (0);
      for (int a = 0; a < kWindowDiscBasis; ++a)
        s += P[a][i] * P[a][j];
      out[packedIndex<D> (i, j)] = s;
    }
}

/** \brief windowForm() of a disc whose every offset holds a point (in disc order) of values \a G,
  * by \a form's tables: the same block \a lo .. \a hi - 1 of \a out, less R (above).
  */
template <typename S, int D, int lo = 0, int hi = D> PCL_TEXLET_HD void
windowDiscForm (const S (*G)[D], const WindowDiscForm<S> &form, S out[D * (D + 1) / 2])
{
  S P[kWindowDiscBasis][D] = {};
  for (int o = 0; o < form.size; ++o)
    PCL_TEXLET_UNROLL_LOOP
    for (int a = 0; a < kWindowDiscBasis; ++a)
    {
      const S b = form.at (o, a);
      PCL_TEXLET_UNROLL_LOOP
      for (int d = lo; d < hi; ++d)
        P[a][d] += b * G[o][d];
    }
  windowFormOfProjection<S, D> (P, lo, hi, out);
}

/** \brief The whole-disc window forms of one disc, one per window width, made when first asked
  * for (host only; one per worker thread, so never shared).
  */
template <typename S>
class WindowDiscForms
{
public:
  /** \param du, dv the disc's offsets in disc order, kept by reference */
  WindowDiscForms (const int *du, const int *dv, int size) : du_ (du), dv_ (dv), size_ (size) {}

  /** \brief The form for a window of \a w pixels (1 .. kMaxWindowPx), or null where none can be made. */
  const WindowDiscForm<S> *
  of (int w)
  {
    if (w < 2 || w > kMaxWindowPx)
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
  bool tried_[kMaxWindowPx + 1] = {};
  std::unique_ptr<WindowDiscForm<S>> forms_[kMaxWindowPx + 1];
};

} // namespace kernels
} // namespace texlet
} // namespace pcl
