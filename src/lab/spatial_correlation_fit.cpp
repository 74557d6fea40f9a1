/*
 * pcl_texlet model lab: the term spatial_correlation fitted to the neighbour pairs
 * (spatial_correlation_fit.h).
 */
#include "spatial_correlation_fit.h"

#include <pcl_texlet/kernels/shared_noise.h>
#include <pcl_texlet/noise/effect_registry.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <algorithm>
#include <cmath>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

namespace
{

/** Sums of half \a half (-1: both) at direction d, lag index k. */
void
sums (const NeighbourPairs &p, int half, int d, int k, double &xy, double &xx, double &n)
{
  xy = xx = n = 0;
  for (int h = 0; h < 2; ++h)
    if (half < 0 || h == half)
    {
      xy += p.products[h][d][k];
      xx += p.squares[h][d][k];
      n += p.count[h][d][k];
    }
  xy /= p.variance;
  xx /= p.variance;
}

/** Measured correlation less the model's at direction d, lag index k. */
double
excess (const NeighbourPairs &p, const ModelCorrelation &model, int half, int d, int k)
{
  double xy, xx, n;
  sums (p, half, d, k, xy, xx, n);
  return n > 0 ? xy / n - model.r[d][k] : 0.0;
}

/** Negative log-likelihood (less constants) of pairs of unit-variance Gaussians correlated r. */
double
pairNll (double r, double xy, double xx, double n)
{
  r = std::max (-0.99, std::min (0.99, r));
  const double q = 1.0 - r * r;
  return 0.5 * n * std::log (q) + (xx - 2.0 * r * xy) / (2.0 * q);
}

int
lagCount (const NeighbourPairs &p)
{
  return static_cast<int> (p.products[0][0].size ());
}

} // namespace

bool
fittedToNeighbourPairs (const std::string &name)
{
  const EffectRegistry &r = EffectRegistry::vocabulary ();
  return r.find (name) >= 0 && (effectInfo (name).lab_needs & effects::kNeedsNeighbourCorrelation);
}

ModelCorrelation
modelCorrelation (const ResidualDiagnostics &d, std::size_t leave_out)
{
  ModelCorrelation m;
  const int lags = d.neighbour_pairs.empty () ? 0 : lagCount (d.neighbour_pairs[0]);
  for (int dir = 0; dir < 2; ++dir)
  {
    m.r[dir].assign (lags, 0.0);
    for (int k = 0; k < lags; ++k)
    {
      double sum = 0;
      int count = 0;
      for (std::size_t j = 1; j < d.neighbour_pairs.size (); ++j)
      {
        if (j == leave_out)
          continue;
        double xy, xx, n;
        sums (d.neighbour_pairs[j], -1, dir, k, xy, xx, n);
        if (n > 0)
        {
          sum += xy / n;
          ++count;
        }
      }
      m.r[dir][k] = count > 0 ? sum / count : 0.0;
    }
  }
  return m;
}

WindowFit
fitWindow (const NeighbourPairs &p, const ModelCorrelation &model, int half)
{
  WindowFit best;
  double best_sse = 0;
  const int lags = lagCount (p);
  for (int d = 0; d < 2; ++d)
    for (int k = 0; k < lags; ++k)
      best_sse += excess (p, model, half, d, k) * excess (p, model, half, d, k);
  for (int w = 2; w <= kernels::kMaxWindowPx; ++w)
  {
    double xb = 0, bb = 0;
    for (int d = 0; d < 2; ++d)
      for (int k = 0; k < lags; ++k)
      {
        const double b = kernels::windowOverlap<double> (k + 1, w);
        xb += excess (p, model, half, d, k) * b;
        bb += b * b;
      }
    const double share = bb > 0 ? std::max (0.0, std::min (1.0, xb / bb)) : 0.0;
    double sse = 0;
    for (int d = 0; d < 2; ++d)
      for (int k = 0; k < lags; ++k)
      {
        const double e = excess (p, model, half, d, k) - share * kernels::windowOverlap<double> (k + 1, w);
        sse += e * e;
      }
    if (sse < best_sse)
    {
      best_sse = sse;
      best.share = share;
      best.window_px = w;
    }
  }
  return best;
}

WindowFit
calibrateWindow (const NeighbourPairs &data, const ModelCorrelation &without, const ModelCorrelation &with,
                 WindowFit fit)
{
  double xy = 0, yy = 0;
  const int lags = lagCount (data);
  for (int d = 0; d < 2; ++d)
    for (int k = 0; k < lags; ++k)
    {
      const double x = excess (data, without, -1, d, k), y = with.r[d][k] - without.r[d][k];
      xy += x * y;
      yy += y * y;
    }
  if (yy > 0 && xy > 0)
    fit.share = std::min (1.0, fit.share * xy / yy);
  return fit;
}

double
windowGain (const NeighbourPairs &p, const ModelCorrelation &model, const WindowFit &fit, int half)
{
  const int lags = lagCount (p);
  double gain = 0;
  for (int d = 0; d < 2; ++d)
    for (int k = 0; k < lags; ++k)
    {
      double xy, xx, n;
      sums (p, half, d, k, xy, xx, n);
      if (n <= 0)
        continue;
      const double r0 = model.r[d][k], r1 = r0 + fit.share * kernels::windowOverlap<double> (k + 1, fit.window_px);
      gain += pairNll (r0, xy, xx, n) - pairNll (r1, xy, xx, n);
    }
  double samples = 0;
  for (int h = 0; h < 2; ++h)
    if (half < 0 || h == half)
      samples += p.samples[h];
  return lags > 0 && samples > 0 ? gain / lags / samples : 0.0;
}

double
windowEffect (const NeighbourPairs &p, const ModelCorrelation &model, const WindowFit &fit, int half,
              double &rms_before, double &rms_after)
{
  const int lags = lagCount (p);
  double before = 0, after = 0;
  int count = 0;
  for (int d = 0; d < 2; ++d)
    for (int k = 0; k < lags; ++k)
    {
      const double e = excess (p, model, half, d, k);
      const double a = e - fit.share * kernels::windowOverlap<double> (k + 1, fit.window_px);
      before += e * e;
      after += a * a;
      ++count;
    }
  rms_before = count > 0 ? std::sqrt (before / count) : 0.0;
  rms_after = count > 0 ? std::sqrt (after / count) : 0.0;
  return before > 0 ? 1.0 - after / before : 0.0;
}

NoiseModel
withWindow (const NoiseModel &model, const std::string &effect, const WindowFit &fit)
{
  NoiseTerm::Ptr term = makeNoiseTerm (effect);
  term->setParameters ({fit.share, static_cast<double> (fit.window_px)});
  NoiseModel out (model);
  out.remove (effect);
  out.add (*term);
  return out;
}

NoiseModel
withFittedWindow (const ModelLab &lab, const NoiseModel &base, const std::string &effect,
                  const ResidualDiagnostics &pairs, int half)
{
  const ModelCorrelation without = modelCorrelation (pairs);
  const WindowFit first = fitWindow (pairs.neighbour_pairs[0], without, half);
  const ModelCorrelation with = modelCorrelation (diagnoseResiduals (lab, withWindow (base, effect, first)));
  return withWindow (base, effect, calibrateWindow (pairs.neighbour_pairs[0], without, with, first));
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
