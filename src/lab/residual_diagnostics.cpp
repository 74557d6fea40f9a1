/*
 * pcl_texlet model lab: residual diagnostics (residual_diagnostics.h). The data and each replica
 * of the model's noise go through the same statistics, so what the model itself implies
 * (its column and frame offsets, the samples' own noise in a bin's mean, the correlation the
 * temporal mean removal leaves) cancels in the difference.
 */
#include <pcl_texlet/lab/residual_diagnostics.h>

#include "lab_data.h"
#include "likelihood.h"

#include <pcl_texlet/kernels/normal_blocks.h>
#include <pcl_texlet/kernels/shared_noise.h>
#include <pcl_texlet/kernels/structured_light.h>

#include <pcl/exceptions.h>

#include <Eigen/Core>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace pcl
{
namespace texlet
{
namespace lab
{

using namespace detail;

const UnexplainedStructure *
ResidualDiagnostics::firstSignificant () const
{
  for (const auto &s : structures)
    if (s.significant)
      return &s;
  return nullptr;
}

namespace
{

const float kNaNf = std::numeric_limits<float>::quiet_NaN ();

/** What the model says of one recording's pixels, and its frames' drift. */
struct RecordingModel
{
  const RecordingMeasurement *m = nullptr;
  std::vector<float> mean, sd;          // predicted mean and SD, mm (NaN: not used)
  std::vector<float> own, column, row, frame; // SDs of the independent, column and row (less frame) and frame parts, mm
  std::vector<float> drift;             // per frame: disparity offset (px) of the model's drift, mean 0
  std::vector<float> J;                 // depth per disparity, mm/px
  double a = 1, a_row = 1;              // correlation of adjacent columns' (rows') offsets
  std::vector<float> window;            // share of the independent part shared over a window (spatial_correlation)
  int window_px = 1;                    // that window's width, whole pixels
};

/** The statistics, summed over recordings. */
struct Stats
{
  double frames = 0, frames_n = 0, rows = 0, rows_n = 0, columns = 0, columns_n = 0;
  double frame_lag1 = 0, frame_lag0 = 0; // the frame offsets' products one frame apart, and squares
  std::vector<double> time_num, time_pairs;     // products of residuals k frames apart, and their count; per lag
  double var = 0, var_n = 0;                    // of the residuals after the offsets
  NeighbourPairs pairs;                         // pairs along rows and columns, by half: their autocorrelation too
  std::vector<std::vector<double>> bin_v, bin_b, bin_n; // per covariate, per bin

  void
  init (int lags, const std::vector<int> &bins)
  {
    time_num.assign (lags, 0.0);
    time_pairs.assign (lags, 0.0);
    for (int h = 0; h < 2; ++h)
      for (int d = 0; d < 2; ++d)
      {
        pairs.products[h][d].assign (lags, 0.0);
        pairs.squares[h][d].assign (lags, 0.0);
        pairs.count[h][d].assign (lags, 0.0);
      }
    bin_v.clear ();
    bin_b.clear ();
    bin_n.clear ();
    for (int b : bins)
    {
      bin_v.emplace_back (b, 0.0);
      bin_b.emplace_back (b, 0.0);
      bin_n.emplace_back (b, 0.0);
    }
  }

  double
  acf (int d, int lag) const
  {
    const double v = var / std::max (var_n, 1.0);
    double num = 0, count = 0;
    if (d == 2)
    {
      num = time_num[lag];
      count = time_pairs[lag];
    }
    else
      for (int h = 0; h < 2; ++h)
      {
        num += pairs.products[h][d][lag];
        count += pairs.count[h][d][lag];
      }
    return count > 0 && v > 0 ? num / count / v : 0.0;
  }

  /** Mean square, over pixels, of the deviation of their bin's mean from the overall mean:
    * of the variance ratio (sd) or of the standardised bias. */
  double
  spread (std::size_t c, bool bias) const
  {
    const auto &x = bias ? bin_b[c] : bin_v[c];
    double s = 0, n = 0;
    for (std::size_t b = 0; b < x.size (); ++b)
    {
      s += x[b];
      n += bin_n[c][b];
    }
    if (n <= 0)
      return 0.0;
    const double mean = s / n;
    double ss = 0;
    for (std::size_t b = 0; b < x.size (); ++b)
      if (bin_n[c][b] > 0)
      {
        const double d = x[b] / bin_n[c][b] - mean;
        ss += bin_n[c][b] * d * d;
      }
    return ss / n;
  }
};

/** One covariate: its name and each pixel's bin per recording (-1: none). */
struct Covariate
{
  std::string name, words;
  std::vector<std::vector<int>> bin;
  int bins = 0;
};

/** Quantile bins of per-pixel values \a value (NaN: none) over the used pixels. */
Covariate
makeCovariate (const std::string &name, const std::string &words, const std::vector<RecordingModel> &recs,
               int bins, const std::vector<std::vector<float>> &value)
{
  Covariate c;
  c.name = name;
  c.words = words;
  std::vector<float> all;
  for (const auto &v : value)
    for (float x : v)
      if (std::isfinite (x))
        all.push_back (x);
  c.bin.resize (recs.size ());
  if (all.size () < static_cast<std::size_t> (bins) * 20)
    return c;
  std::sort (all.begin (), all.end ());
  std::vector<float> edges;
  for (int b = 1; b < bins; ++b)
  {
    const float e = all[all.size () * b / bins];
    if (edges.empty () || e > edges.back ())
      edges.push_back (e);
  }
  c.bins = static_cast<int> (edges.size ()) + 1;
  if (c.bins < 2)
  {
    c.bins = 0;
    return c;
  }
  for (std::size_t r = 0; r < recs.size (); ++r)
  {
    c.bin[r].assign (value[r].size (), -1);
    for (std::size_t i = 0; i < value[r].size (); ++i)
      if (std::isfinite (value[r][i]))
        c.bin[r][i] = static_cast<int> (std::upper_bound (edges.begin (), edges.end (), value[r][i]) - edges.begin ());
  }
  return c;
}

/** Turns the weighted sums \a offset of each line (row or column) into its offset, fitted by
  * weights \a weight2 (sums of squared weights) over \a count samples, and adds each offset's
  * share of its samples' variance to \a share (lines of fewer than 2 samples: offset 0). */
void
finishOffsets (std::vector<double> &offset, const std::vector<double> &weight2, const std::vector<int> &count,
               double &share, double &lines)
{
  for (std::size_t k = 0; k < offset.size (); ++k)
    if (count[k] > 1 && weight2[k] > 0)
    {
      offset[k] /= weight2[k];
      share += offset[k] * offset[k] * weight2[k] / count[k];
      lines += 1;
    }
    else
      offset[k] = 0;
}

/** Sum of a[i] b[i], i < n, vectorised (Eigen reassociates the float sum). */
double
dot (const float *a, const float *b, int n)
{
  return static_cast<double> ((Eigen::Map<const Eigen::ArrayXf> (a, n) * Eigen::Map<const Eigen::ArrayXf> (b, n)).sum ());
}

/** Adds the pairs (x[i], y[i]), i < n, of lag \a k in direction \a d of half \a h to \a pairs:
  * x, y are 0 where invalid, xx, yy their squares and vx, vy 1 where valid, 0 where not. */
void
addPairs (const float *x, const float *y, const float *xx, const float *yy, const float *vx, const float *vy, int n,
          NeighbourPairs &pairs, int h, int d, int k)
{
  pairs.products[h][d][k - 1] += dot (x, y, n);
  pairs.squares[h][d][k - 1] += dot (xx, vy, n) + dot (yy, vx, n);
  pairs.count[h][d][k - 1] += dot (vx, vy, n);
}

/** Adds the statistics of one recording's depths \a y (frames x pixels, mm, NaN: none; the
  * model's drift taken out) to \a s. \a e is scratch of the same size.
  * Offsets are fitted in the shape of a disparity offset (a pattern shift moves a pixel's depth
  * by J, its depth per disparity): in standardised units, weight J / sd per pixel.
  */
void
accumulate (const RecordingModel &rm, std::size_t r, const std::vector<float> &y, const std::vector<Covariate> &cov,
            int lags, std::vector<float> &e, Stats &s)
{
  const RecordingMeasurement &m = *rm.m;
  const int W = m.width, H = m.height, T = m.frames;
  const std::size_t n = static_cast<std::size_t> (W) * H;
  e.assign (y.size (), kNaNf);
  std::vector<double> bias (n, kNaNf), vsum (n, 0.0), w (n, 0.0);
  std::vector<int> count (n, 0);
  // Frame by frame, in memory order: a pixel's samples lie a frame apart.
  std::vector<double> sum (n, 0.0), scale (n, 0.0);
  for (int t = 0; t < T; ++t)
  {
    const float *yt = y.data () + static_cast<std::size_t> (t) * n;
    for (std::size_t i = 0; i < n; ++i)
      if (std::isfinite (yt[i]) && std::isfinite (rm.sd[i]))
      {
        sum[i] += yt[i];
        ++count[i];
      }
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    const int c = count[i];
    if (c < 2)
    {
      count[i] = 0;
      continue;
    }
    sum[i] /= c; // the pixel's temporal mean
    bias[i] = (sum[i] - rm.mean[i]) / rm.sd[i];
    w[i] = rm.J[i] / rm.sd[i];
    // a sample less its pixel's temporal mean has variance sd^2 (1 - 1/c) under the model
    scale[i] = 1.0 / (rm.sd[i] * std::sqrt (1.0 - 1.0 / c));
  }
  for (int t = 0; t < T; ++t)
  {
    const std::size_t o = static_cast<std::size_t> (t) * n;
    for (std::size_t i = 0; i < n; ++i)
      if (count[i] && std::isfinite (y[o + i]))
        e[o + i] = static_cast<float> ((y[o + i] - sum[i]) * scale[i]);
  }
  // The recording's overall scale out: what is left are shares of its residual variance.
  double ss = 0, cnt = 0, w2 = 0;
  for (float v : e)
    if (std::isfinite (v))
    {
      ss += double (v) * v;
      cnt += 1;
    }
  if (cnt < 2 || !(ss > 0))
    return;
  const double norm = 1.0 / std::sqrt (ss / cnt);
  for (float &v : e)
    v = static_cast<float> (v * norm); // NaN stays NaN
  for (std::size_t i = 0; i < n; ++i)
    if (count[i])
    {
      bias[i] *= norm;
      w2 += w[i] * w[i];
    }
  const double w_unit = std::sqrt (w2 / std::count_if (count.begin (), count.end (), [] (int c) { return c > 0; }));
  for (double &x : w)
    x /= w_unit; // mean square 1 over the pixels

  std::vector<double> row (H), col (W), row_w (H), col_w (W);
  std::vector<int> row_n (H), col_n (W);
  std::vector<float> mask (y.size (), 0.0f), square (n);
  double previous_F = std::numeric_limits<double>::quiet_NaN ();
  for (int t = 0; t < T; ++t)
  {
    float *f = e.data () + static_cast<std::size_t> (t) * n;
    double F = 0, Fw = 0;
    int Fn = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (std::isfinite (f[i]))
      {
        F += w[i] * f[i];
        Fw += w[i] * w[i];
        ++Fn;
      }
    if (Fn < 2 || !(Fw > 0))
    {
      previous_F = std::numeric_limits<double>::quiet_NaN ();
      std::fill (f, f + n, 0.0f); // masked out: no pairs over time
      continue;
    }
    F /= Fw;
    if (std::isfinite (previous_F))
    {
      s.frame_lag1 += F * previous_F;
      s.frame_lag0 += 0.5 * (F * F + previous_F * previous_F);
    }
    previous_F = F;
    s.frames += F * F * Fw / Fn; // the offset's share of the samples' variance
    s.frames_n += 1;
    std::fill (row.begin (), row.end (), 0.0);
    std::fill (col.begin (), col.end (), 0.0);
    std::fill (row_w.begin (), row_w.end (), 0.0);
    std::fill (col_w.begin (), col_w.end (), 0.0);
    std::fill (row_n.begin (), row_n.end (), 0);
    std::fill (col_n.begin (), col_n.end (), 0);
    for (int v = 0; v < H; ++v)
      for (int u = 0; u < W; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * W + u;
        float &x = f[i];
        if (!std::isfinite (x))
          continue;
        x -= static_cast<float> (F * w[i]);
        row[v] += w[i] * x;
        row_w[v] += w[i] * w[i];
        ++row_n[v];
        col[u] += w[i] * x;
        col_w[u] += w[i] * w[i];
        ++col_n[u];
      }
    finishOffsets (row, row_w, row_n, s.rows, s.rows_n);
    finishOffsets (col, col_w, col_n, s.columns, s.columns_n);
    for (int v = 0; v < H; ++v)
      for (int u = 0; u < W; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * W + u;
        float &x = f[i];
        if (!std::isfinite (x))
          continue;
        x -= static_cast<float> ((row[v] + col[u]) * w[i]);
        s.var += double (x) * x;
        s.var_n += 1;
        s.pairs.samples[t & 1] += 1;
        vsum[i] += double (x) * x;
      }
    // Invalid samples become 0 with a mask of 0: a lag's sums are then dot products of whole
    // lines (products, squares where the partner is valid, valid pairs).
    float *valid = mask.data () + static_cast<std::size_t> (t) * n;
    for (std::size_t i = 0; i < n; ++i)
    {
      valid[i] = std::isfinite (f[i]) ? 1.0f : 0.0f;
      if (!valid[i])
        f[i] = 0.0f;
      square[i] = f[i] * f[i];
    }
    const int half = t & 1;
    for (int v = 0; v < H; ++v)
    {
      const std::size_t o = static_cast<std::size_t> (v) * W;
      for (int k = 1; k <= lags && k < W; ++k)
        addPairs (f + o, f + o + k, square.data () + o, square.data () + o + k, valid + o, valid + o + k, W - k,
                  s.pairs, half, 0, k);
      for (int k = 1; k <= lags && v + k < H; ++k)
      {
        const std::size_t b = o + static_cast<std::size_t> (k) * W;
        addPairs (f + o, f + b, square.data () + o, square.data () + b, valid + o, valid + b, W, s.pairs, half, 1, k);
      }
    }
  }
  // Covariates: each pixel's variance after the offsets, and its bias.
  for (std::size_t c = 0; c < cov.size (); ++c)
    for (std::size_t i = 0; i < n; ++i)
    {
      const int b = cov[c].bins ? cov[c].bin[r][i] : -1;
      if (b < 0 || !count[i])
        continue;
      s.bin_v[c][b] += vsum[i] / count[i];
      s.bin_b[c][b] += bias[i];
      s.bin_n[c][b] += 1;
    }
  // Over time: frame t against frame t + k, line by line (each line's sum in float, exact enough
  // for its W products, the lines' in double).
  for (int t = 0; t < T; ++t)
    for (int k = 1; k <= lags && t + k < T; ++k)
      for (int v = 0; v < H; ++v)
      {
        const std::size_t a = static_cast<std::size_t> (t) * n + static_cast<std::size_t> (v) * W,
                          b = a + static_cast<std::size_t> (k) * n;
        s.time_num[k - 1] += dot (e.data () + a, e.data () + b, W);
        s.time_pairs[k - 1] += dot (mask.data () + a, mask.data () + b, W);
      }
}

/** The recording's depths, the model's drift taken out: frames x pixels, NaN where none. */
void
measuredDepths (const RecordingModel &rm, std::vector<float> &y)
{
  const RecordingMeasurement &m = *rm.m;
  const std::size_t n = static_cast<std::size_t> (m.width) * m.height;
  y.assign (n * m.frames, kNaNf);
  for (int t = 0; t < m.frames; ++t)
    for (std::size_t i = 0; i < n; ++i)
    {
      const std::uint16_t z = m.at (t, i);
      if (z > 0 && std::isfinite (rm.sd[i]))
        y[t * n + i] = static_cast<float> (z - (rm.drift.empty () ? 0.0 : rm.drift[t] * rm.J[i]));
    }
}

/** The expected variance about their mean of \a n terms of a unit-variance AR(1) sequence whose
  * neighbours correlate \a a: 1 minus the variance of the mean.
  */
double
ar1VarianceAboutMean (double a, std::size_t n)
{
  if (n < 2 || a >= 1.0)
    return 0.0;
  const double N = static_cast<double> (n);
  const double var_mean = ((1 + a) / (1 - a) - 2 * a * (1 - std::pow (a, N)) / (N * (1 - a) * (1 - a))) / N;
  return 1.0 - var_mean;
}

/** A replica: the model's mean plus its noise (independent, column, row, frame parts) on the
  * recording's valid samples, rounded to whole millimetres as the recording is. Frame \a t of
  * replica \a replica of recording \a r draws its normals from Philox blocks (seed, r,
  * replica x frames + t), so that a replica does not depend on the threads. */
void
replicaDepths (const RecordingModel &rm, std::uint32_t seed, std::uint32_t r, int replica, std::vector<float> &y)
{
  const RecordingMeasurement &m = *rm.m;
  const int W = m.width, H = m.height;
  const std::size_t n = static_cast<std::size_t> (W) * H;
  y.assign (n * m.frames, kNaNf);
  std::vector<float> col (W), row (H);
  // Offsets along a line whose neighbours correlate a, about the frame's offset (drawn apart):
  // an AR(1) sequence less its mean, scaled to unit expected variance about that mean.
  const auto drawLine = [] (double a, const float *normal, std::vector<float> &line) {
    const double within = ar1VarianceAboutMean (a, line.size ());
    if (!(within > 1e-9))
    {
      std::fill (line.begin (), line.end (), 0.0f);
      return;
    }
    const float b = static_cast<float> (std::sqrt (std::max (0.0, 1.0 - a * a)));
    double sum = 0;
    for (std::size_t k = 0; k < line.size (); ++k)
    {
      line[k] = k == 0 ? normal[0] : static_cast<float> (a) * line[k - 1] + b * normal[k];
      sum += line[k];
    }
    const float centre = static_cast<float> (sum / line.size ()), scale = static_cast<float> (1.0 / std::sqrt (within));
    for (float &x : line)
      x = (x - centre) * scale;
  };
  // Noise shared over a window: white noise on the cells, its mean over each pixel's window
  // times the window's width (unit variance), as kernels::WindowDraw draws it.
  const int w = rm.window_px;
  const std::size_t cells = w > 1 ? static_cast<std::size_t> (W + w - 1) * (H + w - 1) : 0;
  std::vector<float> across, window;
  if (w > 1)
  {
    across.resize (static_cast<std::size_t> (W) * (H + w - 1));
    window.resize (n);
  }
  // A frame's normals: the frame's offset, the columns', the rows', the cells', the pixels'.
  const std::size_t draws = 1 + W + H + cells + n;
  const int blocks = static_cast<int> ((draws + 3) / 4);
  std::vector<float> normal (4 * static_cast<std::size_t> (blocks));
  std::vector<std::uint32_t> words (4 * static_cast<std::size_t> (blocks));
  for (int t = 0; t < m.frames; ++t)
  {
    kernels::normalBlocks (seed, r, static_cast<std::uint32_t> (replica * m.frames + t), 0, blocks, words.data (),
                           normal.data ());
    const float F = normal[0];
    drawLine (rm.a, normal.data () + 1, col);
    drawLine (rm.a_row, normal.data () + 1 + W, row);
    const float *cell = normal.data () + 1 + W + H, *own = cell + cells;
    if (w > 1)
      kernels::windowMeans (cell, W, H, w, across.data (), window.data ());
    for (std::size_t i = 0; i < n; ++i)
      if (m.at (t, i) > 0 && std::isfinite (rm.sd[i]))
      {
        float e = own[i];
        if (w > 1 && rm.window[i] > 0)
          e = std::sqrt (1.0f - rm.window[i]) * e + std::sqrt (rm.window[i]) * window[i];
        y[t * n + i] = std::round (rm.mean[i] + rm.own[i] * e + rm.column[i] * col[i % W] + rm.row[i] * row[i / W] +
                                   rm.frame[i] * F);
      }
  }
}

double
mean (const std::vector<double> &x)
{
  double s = 0;
  for (double v : x)
    s += v;
  return x.empty () ? 0.0 : s / x.size ();
}

double
sd (const std::vector<double> &x)
{
  const double m = mean (x);
  double s = 0;
  for (double v : x)
    s += (v - m) * (v - m);
  return x.size () > 1 ? std::sqrt (s / (x.size () - 1)) : 0.0;
}

std::string
percent (double x)
{
  char buf[32];
  std::snprintf (buf, sizeof buf, "%.1f %%", 100.0 * x);
  return buf;
}

std::string
fixed (double x, int digits)
{
  char buf[32];
  std::snprintf (buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

} // namespace

ResidualDiagnostics
diagnoseResiduals (const ModelLab &lab, const NoiseModel &model, const ResidualDiagnosticsSettings &settings)
{
  if (settings.replicas < 2 || settings.max_lag < 1 || settings.covariate_bins < 2 || !(settings.min_z >= 0) ||
      !(settings.min_strength >= 0))
  {
    std::ostringstream msg;
    msg << "pcl::texlet::lab::diagnoseResiduals: settings out of range (replicas " << settings.replicas
        << " must be >= 2, max_lag " << settings.max_lag << " >= 1, covariate_bins " << settings.covariate_bins
        << " >= 2, min_z " << settings.min_z << " and min_strength " << settings.min_strength << " >= 0)";
    throw pcl::BadArgumentException (msg.str ());
  }
  const auto start = std::chrono::steady_clock::now ();
  const auto &recordings = lab.recordings ();
  std::vector<RecordingModel> recs (recordings.size ());
  const bool drifts = frameDependent (model);
  {
    std::vector<std::vector<float>> sd, mean;
    lab.predict (model, sd, mean);
    for (std::size_t r = 0; r < recordings.size (); ++r)
    {
      recs[r].sd = std::move (sd[r]);
      recs[r].mean = std::move (mean[r]);
    }
  }
  for (std::size_t r = 0; r < recordings.size (); ++r)
  {
    RecordingModel &rm = recs[r];
    const RecordingMeasurement &m = *recordings[r];
    rm.m = &m;
    const std::size_t n = static_cast<std::size_t> (m.width) * m.height;
    rm.own.assign (n, 0.0f);
    rm.column.assign (n, 0.0f);
    rm.row.assign (n, 0.0f);
    rm.frame.assign (n, 0.0f);
    rm.J.assign (n, 0.0f);
    rm.window.assign (n, 0.0f);
    double rate = 0, weight = 0, row_rate = 0, row_weight = 0;
    std::size_t centre = 0;
    double best = std::numeric_limits<double>::infinity ();
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!std::isfinite (rm.sd[i]))
        continue;
      const PixelContext ctx = lab.context (r, i);
      const NoiseMoments mo = model.moments (ctx);
      const double sd2 = double (rm.sd[i]) * rm.sd[i];
      const double shared2 = mo.sharedVarianceMm2 ();
      const double frame2 = std::min (mo.frame_variance_mm2, shared2);
      const double column2 = std::max (0.0, mo.columnWithinFrameMm2 ()), row2 = std::max (0.0, mo.rowWithinFrameMm2 ());
      rm.frame[i] = static_cast<float> (std::sqrt (std::max (0.0, frame2)));
      rm.column[i] = static_cast<float> (std::sqrt (column2));
      rm.row[i] = static_cast<float> (std::sqrt (row2));
      // The independent part before the recording's rounding: the replicas round as it does.
      rm.own[i] = static_cast<float> (std::sqrt (std::max (0.0, std::min (sd2 - shared2, mo.variance_mm2))));
      if (mo.window_share > 0 && rm.own[i] > 0)
      {
        rm.window[i] = static_cast<float> (std::min (1.0, mo.window_share));
        rm.window_px = std::max (rm.window_px, kernels::resolvedWindowPx (mo.window_px));
      }
      if (row2 > 0 && std::isfinite (mo.row_correlation_px) && mo.row_correlation_px > 0)
        row_rate += row2 / mo.row_correlation_px;
      row_weight += row2;
      rm.J[i] = static_cast<float> (kernels::depthPerDisparityMm (m.surface_mm[i], m.fb ()));
      if (column2 > 0 && std::isfinite (mo.column_correlation_px) && mo.column_correlation_px > 0)
      {
        rate += column2 / mo.column_correlation_px;
        weight += column2;
      }
      else if (column2 > 0)
        weight += column2;
      if (ctx.radius_px < best)
      {
        best = ctx.radius_px;
        centre = i;
      }
    }
    rm.a = weight > 0 ? std::exp (-rate / weight) : 1.0;
    rm.a_row = row_weight > 0 ? std::exp (-row_rate / row_weight) : 1.0;
    if (drifts && std::isfinite (rm.sd[centre]))
    {
      // The drift the model predicts, as a disparity offset of the central pixel: each frame's
      // samples are moved back by it, scaled by their depth per disparity.
      const PixelContext ctx = lab.context (r, centre);
      const double Jc = rm.J[centre];
      rm.drift.resize (m.frames);
      double s = 0;
      for (int t = 0; t < m.frames; ++t)
        s += rm.drift[t] = static_cast<float> (frameBias (model, ctx, t) / Jc);
      for (float &d : rm.drift)
        d -= static_cast<float> (s / m.frames);
    }
  }

  // Covariates, binned by their quantiles over every used pixel.
  const int nb = settings.covariate_bins;
  std::vector<Covariate> cov;
  {
    const std::size_t R = recs.size ();
    std::vector<std::vector<float>> radius (R), depth (R), incidence (R), column (R), row (R), phase (R), edge (R),
        intensity (R);
    bool has_intensity = false;
    for (std::size_t r = 0; r < R; ++r)
    {
      const RecordingMeasurement &m = *recs[r].m;
      const std::size_t n = static_cast<std::size_t> (m.width) * m.height;
      for (auto *v : {&radius[r], &depth[r], &incidence[r], &column[r], &row[r], &phase[r], &edge[r], &intensity[r]})
        v->assign (n, kNaNf);
      for (std::size_t i = 0; i < n; ++i)
      {
        if (!std::isfinite (recs[r].sd[i]))
          continue;
        radius[r][i] = static_cast<float> (m.radius (double (i % m.width), double (i / m.width)));
        depth[r][i] = m.surface_mm[i];
        incidence[r][i] = static_cast<float> (std::acos (std::min (1.0f, std::max (0.0f, m.cos_incidence[i]))) * 57.29578);
        column[r][i] = static_cast<float> (i % m.width);
        row[r][i] = static_cast<float> (i / m.width);
        phase[r][i] = m.phase[i];
        edge[r][i] = std::min (m.edge_distance_px[i], 50.0f);
        if (!m.intensity.empty ())
        {
          intensity[r][i] = m.intensity[i];
          has_intensity = true;
        }
      }
    }
    cov.push_back (makeCovariate ("radius", "distance from the image centre", recs, nb, radius));
    cov.push_back (makeCovariate ("depth", "depth", recs, nb, depth));
    cov.push_back (makeCovariate ("incidence_angle", "incidence angle", recs, nb, incidence));
    cov.push_back (makeCovariate ("column", "image column", recs, nb, column));
    cov.push_back (makeCovariate ("row", "image row", recs, nb, row));
    cov.push_back (makeCovariate ("disparity_phase", "sub-step disparity phase", recs, nb, phase));
    cov.push_back (makeCovariate ("edge_distance", "distance to a depth edge", recs, nb, edge));
    if (has_intensity)
      cov.push_back (makeCovariate ("intensity", "image intensity (the colour frames' grey level)", recs, nb, intensity));
    cov.erase (std::remove_if (cov.begin (), cov.end (), [] (const Covariate &c) { return c.bins == 0; }), cov.end ());
  }
  std::vector<int> bins;
  for (const auto &c : cov)
    bins.push_back (c.bins);

  const int lags = settings.max_lag;
  const int runs = settings.replicas + 1; // run 0: the data
  std::vector<Stats> stats (runs);
  const auto seed = static_cast<std::uint32_t> (settings.seed ^ (settings.seed >> 32));
  const int threads = lab.settings ().threads > 0 ? lab.settings ().threads : omp_get_max_threads ();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (int k = 0; k < runs; ++k)
  {
    Stats &s = stats[k];
    s.init (lags, bins);
    std::vector<float> y, e;
    for (std::size_t r = 0; r < recs.size (); ++r)
    {
      if (k == 0)
        measuredDepths (recs[r], y);
      else
        replicaDepths (recs[r], seed, static_cast<std::uint32_t> (r), k - 1, y);
      accumulate (recs[r], r, y, cov, lags, e, s);
    }
  }

  // Each statistic on the data against its replicas.
  ResidualDiagnostics out;
  auto judge = [&] (const std::string &name, auto statistic) {
    std::vector<double> null;
    for (int k = 1; k < runs; ++k)
      null.push_back (statistic (stats[k]));
    UnexplainedStructure u;
    u.structure = name;
    u.strength = statistic (stats[0]) - mean (null);
    u.z = u.strength / std::max (sd (null), 1e-12);
    u.significant = u.z >= settings.min_z && u.strength >= settings.min_strength;
    return u;
  };
  auto ratio = [] (double s, double n) { return n > 0 ? s / n : 0.0; };
  // A row's (a column's) offsets hold the frame's: where they hold significantly more, their
  // strength is both together, so that bands outrank the frame offsets they imply.
  const UnexplainedStructure frames = judge ("frames", [&] (const Stats &s) { return ratio (s.frames, s.frames_n); });
  for (const bool rows : {true, false})
  {
    UnexplainedStructure u = judge (rows ? "rows" : "columns", [&] (const Stats &s) {
      return rows ? ratio (s.rows, s.rows_n) : ratio (s.columns, s.columns_n);
    });
    const double beyond = u.strength;
    if (u.significant)
      u.strength += frames.strength;
    u.words = std::string ("the pixels of a ") + (rows ? "row" : "column") +
              " share an offset that changes from frame to frame: " + percent (u.strength) +
              " of the residual variance beyond what the model expects, " + percent (beyond) +
              " beyond the whole frame's offset (" + (rows ? "horizontal bands" : "vertical stripes") + ")";
    out.structures.push_back (u);
  }
  {
    // A drift is a trend, its offsets alike from one frame to the next; random offsets are not.
    UnexplainedStructure u = frames;
    const double r1 = stats[0].frame_lag0 > 0 ? stats[0].frame_lag1 / stats[0].frame_lag0 : 0.0;
    u.words = "whole frames move together: " + percent (u.strength) +
              " of the residual variance beyond what the model expects; the offsets correlate " + fixed (r1, 2) +
              " from one frame to the next (" +
              (r1 > 0.5 ? "a trend over frames: a drift" : "random per-frame offsets more than a trend") + ")";
    out.structures.push_back (u);
  }
  {
    const UnexplainedStructure along_rows = judge ("spatial_correlation", [] (const Stats &s) { return s.acf (0, 0); });
    const UnexplainedStructure along_cols = judge ("spatial_correlation", [] (const Stats &s) { return s.acf (1, 0); });
    UnexplainedStructure u = along_rows.strength >= along_cols.strength ? along_rows : along_cols;
    u.significant = along_rows.significant || along_cols.significant;
    u.words = "neighbouring pixels' noise is correlated (after the row, column and frame offsets): at 1 px, " +
              fixed (along_rows.strength, 2) + " along rows and " + fixed (along_cols.strength, 2) +
              " along columns beyond the model (a correlation window)";
    out.structures.push_back (u);
  }
  {
    UnexplainedStructure u = judge ("temporal_correlation", [] (const Stats &s) { return s.acf (2, 0); });
    u.words = "a pixel's noise is correlated from one frame to the next: " + fixed (u.strength, 2) +
              " beyond the model at a lag of 1 frame";
    out.structures.push_back (u);
  }
  for (std::size_t c = 0; c < cov.size (); ++c)
  {
    const UnexplainedStructure v = judge ("covariate:" + cov[c].name, [c] (const Stats &s) { return s.spread (c, false); });
    const UnexplainedStructure b = judge ("covariate:" + cov[c].name, [c] (const Stats &s) { return s.spread (c, true); });
    UnexplainedStructure u = v.strength >= b.strength ? v : b;
    u.significant = v.significant || b.significant;
    u.words = "the residual " + std::string (v.strength >= b.strength ? "variance" : "bias") + " changes with the " +
              cov[c].words + ": mean square over its bins " + fixed (u.strength, 3) + " beyond the model (variance " +
              fixed (v.strength, 3) + ", bias " + fixed (b.strength, 3) + ")";
    out.structures.push_back (u);
  }
  for (const Stats &st : stats)
  {
    out.neighbour_pairs.push_back (st.pairs);
    out.neighbour_pairs.back ().variance = st.var / std::max (st.var_n, 1.0);
  }
  std::stable_sort (out.structures.begin (), out.structures.end (),
                    [] (const UnexplainedStructure &a, const UnexplainedStructure &b) { return a.strength > b.strength; });

  const char *along[3] = {"rows", "columns", "time"};
  for (int d = 0; d < 3; ++d)
  {
    ResidualCorrelation c;
    c.along = along[d];
    for (int k = 0; k < lags; ++k)
    {
      c.measured.push_back (stats[0].acf (d, k));
      std::vector<double> null;
      for (int j = 1; j < runs; ++j)
        null.push_back (stats[j].acf (d, k));
      c.model.push_back (mean (null));
    }
    out.correlations.push_back (c);
  }
  out.seconds = std::chrono::duration<double> (std::chrono::steady_clock::now () - start).count ();
  return out;
}

} // namespace lab
} // namespace texlet
} // namespace pcl
