#include "static_fit.h"
#include "recorded_resolution.h"
#include "setting_combinations.h"

#include <pcl/exceptions.h>

#include <Eigen/Dense>

#include <omp.h>

#include <cmath>
#include <limits>
#include <utility>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

double
linearBiasPx (const NoiseTerm &grid, const std::vector<double> &nodes, double u, double v, double depth_mm,
              double fb_px_m)
{
  int idx[kMaxBiasBasis];
  double wt[kMaxBiasBasis];
  grid.linearBiasBasis (u, v, idx, wt);
  double offset = 0;
  for (int k = 0; k < grid.linearBiasSupport (); ++k)
    offset += wt[k] * nodes[idx[k]];
  return offset * grid.linearBiasShape (depth_mm, fb_px_m);
}

void
binMoments (const ModelView &mv, const std::vector<Bin> &bins, StaticState &s)
{
  s.bin_var.resize (bins.size ());
  s.bin_shared.resize (bins.size ());
  s.bin_bias.resize (bins.size ());
  for (std::size_t b = 0; b < bins.size (); ++b)
  {
    const NoiseMoments m = mv.without_grid.moments (bins[b].ctx);
    s.bin_var[b] = recordedVarianceOverPhases (mv.model, mv.quantised, m.variance_mm2);
    s.bin_shared[b] = m.sharedVarianceMm2 ();
    s.bin_bias[b] = m.bias_mm;
  }
}

namespace
{

/** staticFit with the grid term \a grid (mv.grid, or a copy of it with other shape settings). */
void
solveStatic (const ModelView &mv, const NoiseTerm *grid, const ModelLab::Data &d,
             const std::vector<RecordingMeasurement::ConstPtr> &recs, bool fit_grid, StaticState &s)
{
  const std::vector<Bin> &bins = mv.quantised ? d.qbins : d.bins;
  binMoments (mv, bins, s);
  const std::size_t R = recs.size ();
  const std::vector<double> fixed_grid = grid ? grid->parameters () : std::vector<double> ();
  const int G = grid && fit_grid ? static_cast<int> (fixed_grid.size ()) : 0;
  const int K = grid ? grid->linearBiasSupport () : 0;
  // Quantised models: the mean offset of the rounding at each pixel's own sub-step phase (it
  // changes by a whole step over a phase, too fast for bins), from the bin's noise before it.
  s.pixel_bias.clear ();
  // The steady bias per bin of the terms besides the grid and the rounding.
  std::vector<double> pre_bias = s.bin_bias;
  if (mv.quantised)
  {
    std::vector<double> pre_var (bins.size ());
    for (std::size_t b = 0; b < bins.size (); ++b)
    {
      const NoiseMoments m = mv.pre_quantised.moments (bins[b].ctx);
      pre_var[b] = m.variance_mm2;
      pre_bias[b] = m.bias_mm;
    }
    s.pixel_bias.resize (d.px.size ());
    const std::vector<double> moved_nodes = mv.grid ? mv.grid->parameters () : std::vector<double> ();
    const int P = static_cast<int> (d.px.size ());
#pragma omp parallel for schedule(static)
    for (int k = 0; k < P; ++k)
    {
      const PixelRow &p = d.px[k];
      const RecordingMeasurement &m = *recs[p.rec];
      // The rounding sees the disparity that the distortion (as the model has it now) has moved.
      const double moved_px = mv.grid ? linearBiasPx (*mv.grid, moved_nodes, double (p.index % m.width),
                                                      double (p.index / m.width), m.surface_mm[p.index], m.fb ())
                                      : 0.0;
      const double d0 = 1000.0 * m.fb () / m.surface_mm[p.index] + moved_px - pre_bias[p.qbin] / p.J;
      double offset = 0, var = 0;
      mv.quantiser->roundingMoments (d0, std::sqrt (pre_var[p.qbin]) / p.J, offset, var);
      s.pixel_bias[k] = static_cast<float> (pre_bias[p.qbin] - p.J * offset);
    }
  }
  // The steady mean's parameters (fitted with the grid): the bias each moves per bin, linear in
  // it, taken off as a disparity offset as every other bias is.
  const int M = fit_grid ? static_cast<int> (mv.means.size ()) : 0;
  std::vector<double> phi (bins.size () * M), theta (M);
  if (M)
  {
    NoiseModel probe (mv.quantised ? mv.pre_quantised : mv.without_grid);
    for (int j = 0; j < M; ++j)
    {
      const NoiseTerm::Ptr term = probe.find (mv.means[j].first);
      std::vector<double> values = term->parameters ();
      const std::size_t k = mv.means[j].second;
      theta[j] = values[k];
      values[k] += 1.0;
      term->setParameters (values);
      for (std::size_t b = 0; b < bins.size (); ++b)
        phi[b * M + j] = probe.moments (bins[b].ctx).bias_mm - pre_bias[b];
      values[k] = theta[j];
      term->setParameters (values);
    }
  }
  const int X = G + M; // unknowns besides the surfaces
  const int N = static_cast<int> (3 * R) + X;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero (N, N);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero (N);
  auto gridAt = [&] (const PixelRow &p, int *idx, double *wt) {
    const RecordingMeasurement &m = *recs[p.rec];
    grid->linearBiasBasis (double (p.index % m.width), double (p.index / m.width), idx, wt);
    const double shape = grid->linearBiasShape (m.surface_mm[p.index], m.fb ());
    for (int k = 0; k < K; ++k)
      wt[k] *= shape;
  };
  // The unknowns besides the surfaces at pixel p: the grid's basis, then the steady mean's
  // parameters; their indices into the solution and their weights, \return how many.
  auto extrasAt = [&] (const PixelRow &p, int *idx, double *wt) {
    int n = 0;
    if (G)
    {
      gridAt (p, idx, wt);
      for (int k = 0; k < K; ++k)
        idx[k] += static_cast<int> (3 * R);
      n = K;
    }
    const int b = mv.quantised ? p.qbin : p.bin;
    for (int j = 0; j < M; ++j, ++n)
    {
      idx[n] = static_cast<int> (3 * R) + G + j;
      wt[n] = -phi[b * M + j] / p.J;
    }
    return n;
  };
  auto target = [&] (const PixelRow &p) {
    double t = p.disparity + (mv.quantised ? s.pixel_bias[&p - d.px.data ()] : s.bin_bias[p.bin]) / p.J;
    if (grid && !fit_grid)
    {
      int idx[kMaxBiasBasis];
      double wt[kMaxBiasBasis];
      gridAt (p, idx, wt);
      for (int k = 0; k < K; ++k)
        t -= wt[k] * fixed_grid[idx[k]];
    }
    return t;
  };
  const int P = static_cast<int> (d.px.size ());
  // The normal equations summed in parallel, one set per thread; with a grid term this loop
  // is most of a solve, and the lab solves hundreds of times (docs/model_lab.md section 9).
  // Summed in thread order, so that a run repeats to the last bit.
  std::vector<Eigen::MatrixXd> A_parts (omp_get_max_threads ());
  std::vector<Eigen::VectorXd> rhs_parts (A_parts.size ());
#pragma omp parallel
  {
    Eigen::MatrixXd &A_part = A_parts[omp_get_thread_num ()];
    Eigen::VectorXd &rhs_part = rhs_parts[omp_get_thread_num ()];
    A_part = Eigen::MatrixXd::Zero (N, N);
    rhs_part = Eigen::VectorXd::Zero (N);
#pragma omp for schedule(static)
    for (int i = 0; i < P; ++i)
    {
      const PixelRow &p = d.px[i];
      if (!d.plane[p.rec] || !p.inlier)
        continue;
      const int b = mv.quantised ? p.qbin : p.bin;
      const double w = p.n * p.J * p.J / (s.bin_var[b] + s.bin_shared[b]);
      const double t = target (p);
      const double row[3] = {1.0, p.x, p.y};
      const int o = 3 * p.rec;
      for (int a = 0; a < 3; ++a)
      {
        rhs_part[o + a] += w * row[a] * t;
        for (int c = 0; c < 3; ++c)
          A_part (o + a, o + c) += w * row[a] * row[c];
      }
      if (X)
      {
        int idx[kMaxBiasBasis + kMaxMeanParameters];
        double wt[kMaxBiasBasis + kMaxMeanParameters];
        const int n = extrasAt (p, idx, wt);
        for (int k = 0; k < n; ++k)
        {
          const int gk = idx[k];
          rhs_part[gk] += w * wt[k] * t;
          for (int a = 0; a < 3; ++a)
            A_part (gk, o + a) += w * wt[k] * row[a];
          for (int l = 0; l < n; ++l)
            A_part (gk, idx[l]) += w * wt[k] * wt[l];
        }
      }
    }
  }
  for (std::size_t t = 0; t < A_parts.size (); ++t)
    if (A_parts[t].size ())
    {
      A += A_parts[t];
      rhs += rhs_parts[t];
    }
  // The block of the surfaces and the other unknowns was summed on one side only.
  if (X)
    A.topRightCorner (3 * R, X) = A.bottomLeftCorner (X, 3 * R).transpose ();
  // A small ridge keeps nodes without data at zero.
  const double scale = A.diagonal ().cwiseAbs ().maxCoeff () + 1.0, ridge = 1e-9 * scale;
  for (int k = 0; k < N; ++k)
    A (k, k) += (k >= static_cast<int> (3 * R)) ? 1e3 * ridge : ridge;
  // The planes carry the affine part (1, u, v) of the map: it is held at zero over the image.
  // Where the map's shape changes with depth within a recording the two are no longer exactly
  // interchangeable, only nearly, and the fit would trade large opposite tilts between them.
  if (G)
  {
    const RecordingMeasurement &m = *recs.front ();
    std::vector<Eigen::VectorXd> affine (3, Eigen::VectorXd::Zero (G));
    int idx[kMaxBiasBasis];
    double wt[kMaxBiasBasis];
    for (int v = 0; v < m.height; v += 4)
      for (int u = 0; u < m.width; u += 4)
      {
        grid->linearBiasBasis (u, v, idx, wt);
        const double phi[3] = {1.0, (u - 0.5 * m.width) / m.width, (v - 0.5 * m.height) / m.width};
        for (int a = 0; a < 3; ++a)
          for (int k = 0; k < K; ++k)
            affine[a][idx[k]] += phi[a] * wt[k];
      }
    for (auto &c : affine)
      if (c.norm () > 0)
      {
        c.normalize ();
        A.block (3 * R, 3 * R, G, G) += 1e3 * scale * c * c.transpose ();
      }
  }
  const Eigen::VectorXd sol = A.ldlt ().solve (rhs);
  s.planes.assign (R, Eigen::Vector3d::Zero ());
  for (std::size_t r = 0; r < R; ++r)
    s.planes[r] = sol.segment<3> (3 * r);
  s.grid.clear ();
  if (G)
    s.grid.assign (sol.data () + 3 * R, sol.data () + 3 * R + G);
  s.means.clear ();
  for (int j = 0; j < M; ++j)
    s.means.push_back (theta[j] + sol[3 * R + G + j]);

  s.ss_static.assign (bins.size (), 0.0);
  std::vector<std::vector<double>> ss_parts (omp_get_max_threads ());
#pragma omp parallel
  {
    std::vector<double> &ss_part = ss_parts[omp_get_thread_num ()];
    ss_part.assign (bins.size (), 0.0);
#pragma omp for schedule(static)
    for (int i = 0; i < P; ++i)
    {
      const PixelRow &p = d.px[i];
      const RecordingMeasurement &m = *recs[p.rec];
      double predicted;
      if (d.plane[p.rec])
        predicted = s.planes[p.rec].dot (Eigen::Vector3d (1.0, p.x, p.y));
      else
        predicted = 1000.0 * m.fb () / m.surface_mm[p.index];
      if (X)
      {
        int idx[kMaxBiasBasis + kMaxMeanParameters];
        double wt[kMaxBiasBasis + kMaxMeanParameters];
        const int n = extrasAt (p, idx, wt);
        for (int k = 0; k < n; ++k)
          predicted += wt[k] * sol[idx[k]];
      }
      const double e = p.J * (target (p) - predicted);
      const int b = mv.quantised ? p.qbin : p.bin;
      ss_part[b] += p.n * e * e;
    }
  }
  for (const std::vector<double> &part : ss_parts)
    for (std::size_t b = 0; b < part.size (); ++b)
      s.ss_static[b] += part[b];
}

} // namespace

void
staticFit (const ModelView &mv, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
           GridFit grid_fit, StaticState &s)
{
  s.grid_settings.clear ();
  const bool fit_grid = grid_fit != GridFit::none;
  const auto search = mv.grid && grid_fit == GridFit::nodes_and_shape
                          ? mv.grid->linearBiasShapeSearch ()
                          : std::vector<std::pair<std::string, std::vector<double>>> ();
  if (search.empty ())
  {
    solveStatic (mv, mv.grid.get (), d, recs, fit_grid, s);
    return;
  }
  // Every combination of the shape settings; the static part of the NLL (the variances do not
  // depend on the shape) picks one.
  double best = std::numeric_limits<double>::infinity ();
  forEachSettingCombination (search, [&] (const SettingCombination &settings) {
    const NoiseTerm::Ptr grid = mv.grid->clone ();
    for (const auto &kv : settings)
      grid->setSetting (kv.first, kv.second);
    StaticState trial;
    solveStatic (mv, grid.get (), d, recs, true, trial);
    double score = 0;
    for (std::size_t b = 0; b < trial.ss_static.size (); ++b)
      score += trial.ss_static[b] / (trial.bin_var[b] + trial.bin_shared[b]);
    if (score < best)
    {
      best = score;
      s = std::move (trial);
      s.grid_settings = settings;
    }
  });
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
