#include <pcl_texlet/lab/model_lab.h>

#include "effect_size.h"
#include "lab_data.h"
#include "likelihood.h"
#include "nll_fit.h"
#include "recorded_resolution.h"
#include "spatial_correlation_fit.h"
#include "split_sd.h"
#include "static_fit.h"

#include <pcl_texlet/kernels/structured_light.h>
#include <pcl_texlet/lab/residual_diagnostics.h>
#include <pcl_texlet/noise/effect_registry.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <pcl/exceptions.h>

#include <Eigen/Core>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace lab
{

using namespace detail;

namespace
{

const int kSpatialRadius = 3; // a 7 x 7 window: a few pixels, far below the scale of a smooth bias (a map's cells)

/** The share of a line offset's variance (column or row offsets whose correlation falls by e
  * over \a length_px lines) that a pixel's difference from the mean of its 48 neighbours in the
  * window keeps, scaled as spatialSd () scales it: 0 where every line shares the offset.
  */
double
windowShare (double length_px)
{
  if (!(length_px > 0) || !std::isfinite (length_px))
    return 0.0;
  const int R = kSpatialRadius, side = 2 * R + 1, others = side * side - 1;
  const auto rho = [&] (int d) { return std::exp (-std::abs (d) / length_px); };
  const auto count = [&] (int d) { return d == 0 ? side - 1 : side; };
  double one = 0, two = 0;
  for (int d = -R; d <= R; ++d)
  {
    one += count (d) * rho (d);
    for (int e = -R; e <= R; ++e)
      two += count (d) * count (e) * rho (d - e);
  }
  one /= others;
  two /= double (others) * others;
  return (1.0 - 2.0 * one + two) * others / (others + 1.0);
}

/** LabMetrics::bias_spatial_sd_mm and its prediction, from the pixels' residuals \a e and the
  * predicted variances of their means' local differences \a mean_var (one per PixelRow of \a d).
  */
void
spatialSd (const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
           const std::vector<float> &e, const std::vector<float> &mean_var, double &measured, double &predicted)
{
  const int R = kSpatialRadius;
  const int min_neighbours = 4;
  std::vector<std::vector<int>> row_at (recs.size ());
  for (std::size_t r = 0; r < recs.size (); ++r)
    row_at[r].assign (static_cast<std::size_t> (recs[r]->width) * recs[r]->height, -1);
  for (std::size_t k = 0; k < d.px.size (); ++k)
    row_at[d.px[k].rec][d.px[k].index] = static_cast<int> (k);
  double s2 = 0, sv = 0, count = 0;
  for (std::size_t k = 0; k < d.px.size (); ++k)
  {
    const PixelRow &p = d.px[k];
    const RecordingMeasurement &m = *recs[p.rec];
    const int u = static_cast<int> (p.index % m.width), v = static_cast<int> (p.index / m.width);
    double sum = 0, n = 0;
    for (int vv = std::max (0, v - R); vv <= std::min (m.height - 1, v + R); ++vv)
      for (int uu = std::max (0, u - R); uu <= std::min (m.width - 1, u + R); ++uu)
      {
        const int j = row_at[p.rec][static_cast<std::size_t> (vv) * m.width + uu];
        if (j < 0 || j == static_cast<int> (k))
          continue;
        sum += e[j];
        n += 1;
      }
    if (n < min_neighbours)
      continue;
    // For white noise Var (e - mean of n others) = sigma^2 (1 + 1 / n).
    const double r = e[k] - sum / n;
    s2 += r * r * n / (n + 1);
    sv += mean_var[k];
    count += 1;
  }
  measured = count > 0 ? std::sqrt (s2 / count) : kNaN;
  predicted = count > 0 ? std::sqrt (sv / count) : kNaN;
}

} // namespace

ModelLab::ModelLab (const LabSettings &settings) : settings_ (settings) {}

ModelLab::~ModelLab () = default;

void
ModelLab::addRecording (const RecordingMeasurement::ConstPtr &recording)
{
  if (!recording)
    throw pcl::BadArgumentException ("ModelLab::addRecording: the recording is null");
  const RecordingMeasurement &r = *recording;
  std::size_t near_edges = 0;
  for (std::size_t i = 0; i < r.used.size (); ++i)
    near_edges += (r.used[i] && r.edge_distance_px[i] < 3.0f) ? 1 : 0;
  const double projectors = r.active_projectors;
  facts_.min_projectors = recordings_.empty () ? projectors : std::min (facts_.min_projectors, projectors);
  facts_.max_projectors = recordings_.empty () ? projectors : std::max (facts_.max_projectors, projectors);
  facts_.any_plane = facts_.any_plane || r.plane_scene;
  facts_.any_edges = facts_.any_edges || near_edges > 100;
  facts_.any_repeated = facts_.any_repeated || r.frames >= 2;
  facts_.any_intensity = facts_.any_intensity || !r.intensity.empty ();
  facts_.all_split = facts_.all_split && r.frames >= 4;
  recordings_.push_back (recording);
  for (auto &d : data_)
    d = CachedData ();
}

bool
ModelLab::splitsFrames () const
{
  return facts_.all_split;
}

TexletConsistency
ModelLab::texlets (const NoiseModel &model, Half half) const
{
  TexletConsistencySettings settings;
  settings.threads = static_cast<unsigned> (std::max (0, settings_.threads));
  if (half != Half::all && splitsFrames ())
    settings.frame_parity = half == Half::fit ? 0 : 1;
  return texletConsistency (recordings_, model, settings);
}

std::shared_ptr<const ModelLab::Data>
ModelLab::data (Half half, const NoiseModel &reference) const
{
  if (recordings_.empty ())
    throw pcl::BadArgumentException ("model lab: no recording was added");
  // The distortion moves each pixel's disparity before the rounding, and so its sub-step phase
  // (docs/model_lab.md section 7): its settings and node values say which phases.
  const ModelView view (reference);
  std::vector<double> distortion;
  if (view.grid)
  {
    for (const auto &kv : view.grid->settings ())
      distortion.push_back (kv.second);
    const std::vector<double> &nodes = view.grid->parameters ();
    distortion.insert (distortion.end (), nodes.begin (), nodes.end ());
  }
  CachedData &slot = data_[static_cast<int> (half)];
  if (!slot.data || slot.distortion != distortion)
  {
    std::shared_ptr<const Data> built = buildData (recordings_, half, splitsFrames (), view.grid.get ());
    if (built->px.empty ())
      throw pcl::BadArgumentException ("model lab: no pixel has enough valid samples in each half of the data "
                                       "(two, or one in recordings of one frame)");
    slot.data = std::move (built);
    slot.distortion = std::move (distortion);
  }
  return slot.data;
}

PixelContext
ModelLab::context (std::size_t r, std::size_t i) const
{
  return pixelContext (*recordings_.at (r), i);
}

LabMetrics
ModelLab::evaluate (const NoiseModel &model, Half half) const
{
  return evaluate (model, *data (half, model), nullptr);
}

LabMetrics
ModelLab::evaluate (const NoiseModel &model, const Data &d, PixelErrors *pixels) const
{
  const ModelView mv (model);
  StaticState s;
  staticFit (mv, d, recordings_, GridFit::none, s);
  LabMetrics out;
  // Column and frame parts of the NLL as in the fit; within and static parts per pixel.
  double L = 0;
  {
    StaticState zero = s;
    const std::vector<Bin> &bins = mv.quantised ? d.qbins : d.bins;
    for (std::size_t b = 0; b < bins.size (); ++b)
    {
      // objective () adds the bins' parts; take them out again, they are done per pixel below.
      const Bin &B = bins[b];
      const double var = s.bin_var[b], V = var + s.bin_shared[b];
      L -= 0.5 * B.dof * std::log (kTwoPi * var) + B.ssw / (2 * var);
      L -= 0.5 * B.npix * std::log (kTwoPi * V) - 0.5 * B.sum_log_n + s.ss_static[b] / (2 * V);
    }
    L += objective (mv, d, zero);
  }
  // Frame-dependent bias per recording, at the central pixel, per frame of the half.
  const bool timed = frameDependent (model);
  std::vector<std::vector<double>> drift (recordings_.size ());
  std::vector<double> drift_var (recordings_.size (), 0.0), rep_J (recordings_.size (), 1.0);
  for (std::size_t r = 0; r < recordings_.size (); ++r)
  {
    const PixelContext &ctx = d.rep[r];
    rep_J[r] = kernels::depthPerDisparityMm (ctx.true_depth_mm, ctx.fb_px_m);
    drift[r].assign (recordings_[r]->frames, 0.0);
    if (!timed)
      continue;
    double s1 = 0, s2 = 0;
    for (int t : d.frame_list[r])
    {
      const double b = frameBias (mv.without_grid, ctx, t) / rep_J[r];
      drift[r][t] = b;
      s1 += b;
      s2 += b * b;
    }
    const double k = static_cast<double> (d.frame_list[r].size ());
    drift_var[r] = k > 1 ? (s2 - s1 * s1 / k) / (k - 1) : 0.0;
    // The surface fit takes up the mean offset over the frames; the samples see the rest.
    for (int t : d.frame_list[r])
      drift[r][t] -= s1 / k;
  }
  const int P = static_cast<int> (d.px.size ());
  if (pixels)
  {
    for (auto *v : {&pixels->sd_pred, &pixels->sd_meas, &pixels->mean_pred, &pixels->mean_meas})
      v->assign (P, 0.0f);
    pixels->line_pred.clear (), pixels->line_meas.clear ();
    for (const bool row : {false, true})
      for (const LineStat &c : row ? d.rows : d.cols)
      {
        const double J = kernels::depthPerDisparityMm (c.ctx.true_depth_mm, c.ctx.fb_px_m);
        pixels->line_pred.push_back (static_cast<float> (J * std::sqrt (lineOffsetVariance (mv, c, row, s))));
        pixels->line_meas.push_back (static_cast<float> (J * std::sqrt (c.ss / c.frames)));
      }
  }
  std::vector<float> residual (P), mean_var (P); // measured minus predicted mean; predicted variance of the mean
  double sd2 = 0, sd_count = 0, floor2 = 0, floor_count = 0, b2 = 0, lp = 0, in1 = 0, in2 = 0, count = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : sd2, sd_count, floor2, floor_count, b2, lp, in1, in2, count) num_threads(settings_.threads > 0 ? settings_.threads : omp_get_max_threads ())
  for (int k = 0; k < P; ++k)
  {
    const PixelRow &p = d.px[k];
    const RecordingMeasurement &m = *recordings_[p.rec];
    const PixelContext ctx = pixelContext (m, p.index);
    const NoiseMoments mo = model.moments (ctx);
    const double surface_disparity = d.plane[p.rec] ? s.planes[p.rec].dot (Eigen::Vector3d (1.0, p.x, p.y))
                                              : 1000.0 * m.fb () / m.surface_mm[p.index];
    const RecordedMoments recorded =
        recordedMoments (model, mv.quantised, mo.variance_mm2,
                         predictedMeanMm (surface_disparity, 1000.0 * m.fb (), mo.bias_mm, p.J));
    const double var = recorded.variance_mm2, col = mo.sharedVarianceMm2 ();
    const double sd_pred = std::sqrt (var + col + p.J * p.J * drift_var[p.rec]);
    // One sample (single frames): no temporal SD to compare.
    const double sd_meas = p.n > 1 ? std::sqrt (p.ss_total / (p.n - 1)) : kNaN;
    if (p.n > 1)
    {
      sd2 += (sd_pred - sd_meas) * (sd_pred - sd_meas);
      sd_count += 1;
    }
    const double mu = predictedMeanMm (surface_disparity, 1000.0 * m.fb (), mo.bias_mm, p.J) + recorded.mean_offset_mm;
    const double e = p.mean_mm - mu;
    b2 += e * e;
    if (pixels)
    {
      pixels->sd_pred[k] = static_cast<float> (sd_pred), pixels->sd_meas[k] = static_cast<float> (sd_meas);
      pixels->mean_pred[k] = static_cast<float> (mu), pixels->mean_meas[k] = p.mean_mm;
    }
    const double V = var + col;
    residual[k] = static_cast<float> (e);
    // Offsets shared over the window cancel in a local difference; a frame's cancel wholly.
    const double local = var + std::max (0.0, mo.columnWithinFrameMm2 ()) * windowShare (mo.column_correlation_px) +
                         std::max (0.0, mo.rowWithinFrameMm2 ()) * windowShare (mo.row_correlation_px);
    mean_var[k] = static_cast<float> (local / p.n);
    lp += 0.5 * p.dof * std::log (kTwoPi * var) + p.ss_within / (2 * var);
    lp += 0.5 * std::log (kTwoPi * V / p.n) + p.n * e * e / (2 * V);
    const double sigma = std::sqrt (V);
    SplitSd split; // the SDs of the pixel's alternate samples
    for (int t : d.frame_list[p.rec])
    {
      const std::uint16_t z = m.at (t, p.index);
      if (!z)
        continue;
      const double dev = std::fabs (z - mu - p.J * drift[p.rec][t]);
      in1 += dev <= sigma ? 1 : 0;
      in2 += dev <= 2 * sigma ? 1 : 0;
      count += 1;
      split.add (z - mu);
    }
    if (split.splittable ())
    {
      floor2 += split.samplingVarianceOfSd ();
      floor_count += 1;
    }
  }
  out.pixels = P;
  out.samples = d.samples;
  out.sd_rmse_mm = sd_count > 0 ? std::sqrt (sd2 / sd_count) : kNaN;
  out.sd_floor_mm = floor_count > 0 ? std::sqrt (floor2 / floor_count) : kNaN;
  spatialSd (d, recordings_, residual, mean_var, out.bias_spatial_sd_mm, out.bias_spatial_sd_pred_mm);
  out.bias_rmse_mm = std::sqrt (b2 / P);
  out.nll = (L + lp) / d.samples;
  out.within_1sigma = count > 0 ? in1 / count : 0;
  out.within_2sigma = count > 0 ? in2 / count : 0;
  return out;
}

NoiseModel
ModelLab::fit (const NoiseModel &model, Half half) const
{
  return fitOn (model, *data (half, model), recordings_, settings_);
}

NoiseModel
ModelLab::addEffect (const NoiseModel &current, const std::string &effect) const
{
  const auto &names = noiseEffectNames ();
  if (std::find (names.begin (), names.end (), effect) == names.end ())
  {
    std::string known;
    for (const auto &n : names)
      known += (known.empty () ? "" : ", ") + n;
    throw pcl::BadArgumentException ("model lab: unknown effect '" + effect + "' (known: " + known + ")");
  }
  if (current.find (effect))
    throw pcl::BadArgumentException ("model lab: the model already has the effect '" + effect + "'");
  if (recordings_.empty ())
    throw pcl::BadArgumentException ("model lab: no recording was added");
  const std::string why = whyNotApplicable (effect);
  if (!why.empty ())
    throw pcl::BadArgumentException ("model lab: cannot add the effect '" + effect + "': the recordings cannot show it (" +
                                     why + ")");
  const std::shared_ptr<const Data> data_all = data (Half::all, current);
  const Data &d = *data_all;
  NoiseModel base = fitOn (current, d, recordings_, settings_);
  if (fittedToNeighbourPairs (effect)) // to every frame's neighbour pairs (spatial_correlation_fit.h)
    return withFittedWindow (*this, base, effect, diagnoseResiduals (*this, base), -1);
  StaticState s;
  const double nested = fitObjective (base, d, recordings_, s);
  return fitWithEffect (base, current, effect, d, recordings_, settings_, nested);
}

} // namespace lab
} // namespace texlet
} // namespace pcl
