#include "bootstrap.h"
#include "likelihood.h"
#include "recorded_resolution.h"
#include "static_fit.h"

#include <pcl_texlet/kernels/structured_light.h>

#include <Eigen/Core>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

std::unique_ptr<ModelLab::Data>
synthesise (const ModelLab::Data &d, const NoiseModel &model, const std::vector<RecordingMeasurement::ConstPtr> &recs,
            std::mt19937_64 &rng)
{
  auto out = std::make_unique<ModelLab::Data> (d);
  const ModelView mv (model);
  StaticState s;
  staticFit (mv, d, recs, GridFit::none, s);
  std::normal_distribution<double> gauss (0.0, 1.0);
  auto chi2 = [&] (double dof) {
    if (!(dof > 0))
      return 0.0;
    std::gamma_distribution<double> g (0.5 * dof, 2.0);
    return g (rng);
  };
  // Within sums: the bins of both sets get the same draws, pixel by pixel, so they agree.
  const NoiseModel &no_grid = mv.without_grid;
  const std::vector<double> grid_nodes = mv.grid ? mv.grid->parameters () : std::vector<double> ();
  for (Bin &b : out->bins)
    b.ssw = 0;
  for (Bin &b : out->qbins)
    b.ssw = 0;
  // Per-pixel moments (not the bins'), so that the null has the real data's spread within bins.
  const int P = static_cast<int> (out->px.size ());
  // The variance is the whole model's: a rounding sees the disparity the distortion has moved.
  std::vector<double> pvar (P), pcol (P), pmean (P);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < P; ++k)
  {
    const PixelRow &p = out->px[k];
    const RecordingMeasurement &m = *recs[p.rec];
    const PixelContext ctx = pixelContext (m, p.index);
    const NoiseMoments mo = no_grid.moments (ctx);
    // The pixel's mean: the fitted surface with the model's bias, the distortion in disparity.
    double disparity = d.plane[p.rec] ? s.planes[p.rec].dot (Eigen::Vector3d (1.0, p.x, p.y))
                                      : 1000.0 * m.fb () / m.surface_mm[p.index];
    if (mv.grid)
      disparity += linearBiasPx (*mv.grid, grid_nodes, double (p.index % m.width), double (p.index / m.width),
                                 m.surface_mm[p.index], m.fb ());
    disparity -= mo.bias_mm / p.J;
    // Only a rounding's variance depends on the distortion map; otherwise both are no_grid's.
    const double variance = mv.quantised && mv.grid ? model.moments (ctx).variance_mm2 : mo.variance_mm2;
    const RecordedMoments recorded = recordedMoments (model, mv.quantised, variance, 1000.0 * m.fb () / disparity);
    pvar[k] = recorded.variance_mm2;
    pcol[k] = mo.sharedVarianceMm2 ();
    pmean[k] = disparity - recorded.mean_offset_mm / p.J;
  }
  for (int k = 0; k < P; ++k)
  {
    PixelRow &p = out->px[k];
    const double var = pvar[k], col = pcol[k];
    const double ssw = var * chi2 (p.dof);
    p.ss_within = static_cast<float> (ssw);
    out->bins[p.bin].ssw += ssw;
    out->qbins[p.qbin].ssw += ssw;
    // Plus the noise of a mean.
    p.disparity = static_cast<float> (pmean[k] + gauss (rng) * std::sqrt ((var + col) / p.n) / p.J);
  }
  for (const bool row : {false, true})
    for (LineStat &c : row ? out->rows : out->cols)
      c.ss = lineOffsetVariance (mv, c, row, s) * chi2 (c.frames);
  const bool timed = frameDependent (model);
  for (FrameStat &f : out->frames)
  {
    const PixelContext &ctx = d.rep[f.rec];
    const NoiseMoments m = no_grid.moments (ctx);
    const double J = kernels::depthPerDisparityMm (ctx.true_depth_mm, ctx.fb_px_m);
    double pred = 0;
    if (timed)
    {
      double mean = 0;
      for (int t : d.frame_list[f.rec])
        mean += frameBias (no_grid, ctx, t) / J;
      pred = frameBias (no_grid, ctx, f.frame) / J - mean / d.frame_list[f.rec].size ();
    }
    const double v = frameOffsetVariance (mv, f, m, J, s);
    f.D = pred + gauss (rng) * std::sqrt (v);
  }
  return out;
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
