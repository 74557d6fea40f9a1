#include "likelihood.h"

#include <pcl_texlet/kernels/shared_noise.h>
#include <pcl_texlet/kernels/structured_light.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

double
frameBias (const NoiseModel &model, PixelContext ctx, int frame)
{
  const double steady = model.moments (ctx).bias_mm;
  ctx.frame = frame;
  return model.moments (ctx).bias_mm - steady;
}

bool
frameDependent (const NoiseModel &model)
{
  for (const auto &t : model.terms ())
    if (t->frameDependent ())
      return true;
  return false;
}

double
pixelNoiseIn (const BinWeights &w, bool quantised, const StaticState &s)
{
  double v = 0;
  for (const auto &bw : w.of (quantised))
    v += bw.second * s.bin_var[bw.first];
  return v;
}

double
lineOffsetVariance (const ModelView &mv, const LineStat &c, bool row, const StaticState &s)
{
  const NoiseMoments m = mv.without_grid.moments (c.ctx);
  const double J = kernels::depthPerDisparityMm (c.ctx.true_depth_mm, c.ctx.fb_px_m);
  const double shared = row ? m.rowWithinFrameMm2 () : m.columnWithinFrameMm2 ();
  return shared / (J * J) + pixelNoiseIn (c.noise, mv.quantised, s) * windowedNoiseFactor (m, 1);
}

double
windowedNoiseFactor (const NoiseMoments &m, int dims)
{
  if (!(m.window_share > 0.0))
    return 1.0;
  const double w = kernels::resolvedWindowPx (m.window_px);
  return 1.0 + m.window_share * (std::pow (w, dims) - 1.0);
}

double
frameOffsetVariance (const ModelView &mv, const FrameStat &f, const NoiseMoments &m, double J, const StaticState &s)
{
  return pixelNoiseIn (f.noise, mv.quantised, s) * windowedNoiseFactor (m, 2) + m.frame_variance_mm2 / (J * J);
}

double
objective (const ModelView &mv, const ModelLab::Data &d, const StaticState &s, bool with_static)
{
  const std::vector<Bin> &bins = mv.quantised ? d.qbins : d.bins;
  double L = 0;
  for (std::size_t b = 0; b < bins.size (); ++b)
  {
    const Bin &B = bins[b];
    const double var = s.bin_var[b], V = var + s.bin_shared[b];
    L += 0.5 * B.dof * std::log (kTwoPi * var) + B.ssw / (2 * var);
    if (with_static)
      L += 0.5 * B.npix * std::log (kTwoPi * V) - 0.5 * B.sum_log_n + s.ss_static[b] / (2 * V);
  }
  for (const bool row : {false, true})
    for (const LineStat &c : row ? d.rows : d.cols)
    {
      const double v = lineOffsetVariance (mv, c, row, s);
      const double J = kernels::depthPerDisparityMm (c.ctx.true_depth_mm, c.ctx.fb_px_m);
      L += 0.5 * c.frames * std::log (kTwoPi * v) + c.ss / (2 * v) + c.frames * std::log (J);
    }
  const bool timed = frameDependent (mv.model);
  std::vector<double> pred;
  int current = -1;
  double J = 1;
  NoiseMoments m;
  for (std::size_t k = 0; k < d.frames.size (); ++k)
  {
    const FrameStat &f = d.frames[k];
    if (f.rec != current)
    {
      current = f.rec;
      const PixelContext &ctx = d.rep[f.rec];
      m = mv.without_grid.moments (ctx);
      J = kernels::depthPerDisparityMm (ctx.true_depth_mm, ctx.fb_px_m);
      pred.assign (d.frame_list[f.rec].size (), 0.0);
      if (timed)
      {
        double mean = 0;
        for (std::size_t j = 0; j < pred.size (); ++j)
        {
          pred[j] = frameBias (mv.without_grid, ctx, d.frame_list[f.rec][j]) / J;
          mean += pred[j];
        }
        for (double &p : pred)
          p -= mean / pred.size ();
      }
    }
    const auto &list = d.frame_list[f.rec];
    const std::size_t j = std::lower_bound (list.begin (), list.end (), f.frame) - list.begin ();
    const double v = frameOffsetVariance (mv, f, m, J, s);
    const double e = f.D - pred[j];
    L += 0.5 * std::log (kTwoPi * v) + e * e / (2 * v) + std::log (J);
  }
  return L;
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
