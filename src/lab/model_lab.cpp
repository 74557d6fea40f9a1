#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/common/parallel_for.h>
#include <pcl_texlet/kernels/structured_light.h>
#include <pcl_texlet/noise/effect_registry.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <pcl/exceptions.h>

#include <ceres/first_order_function.h>
#include <ceres/gradient_problem.h>
#include <ceres/gradient_problem_solver.h>

#include <Eigen/Dense>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <unordered_map>

namespace pcl
{
namespace texlet
{
namespace lab
{

namespace
{
const double kTwoPi = 6.283185307179586;
const double kNaN = std::numeric_limits<double>::quiet_NaN ();
} // namespace

// ---------------------------------------------------------------------------------------------
// Aggregates of one half.

/** One used pixel of one half. */
struct PixelRow
{
  int rec;
  std::uint32_t index;
  float n;          // valid samples in the half
  float mean_mm;    // their mean
  float disparity;  // f b 1000 / mean, px
  float J;          // depth per disparity at the surface, mm/px
  float x, y;       // normalised image coordinates
  float ss_total;   // sum of squared deviations from the mean
  float ss_within;  // ... after removing the frame and column-frame means
  float log_n;
  int bin, qbin;
  std::uint8_t inlier;
};

/** Pixels with similar covariates: their within sums pooled, one context for the model. */
struct Bin
{
  PixelContext ctx;
  double dof = 0, ssw = 0, npix = 0, sum_log_n = 0;
  double su = 0, sv = 0, sr = 0, sz = 0, scos = 0, sedge = 0, sphase = 0, w = 0;
  int rec = 0;
};

/** How the independent noise of a column's (or a frame's) pixels reaches its mean offset: per
  * covariate bin b, the weight w_b with Var(offset) = sum_b w_b var_b (disparity px^2, var_b the
  * bin's variance in mm^2). w_b sums (1 - 1/n_i) / (J_i^2 N^2) over the offset's N samples i in
  * bin b (n_i: pixel i's samples in the half, whose mean is taken out first). The pixels of a
  * column span every row, so their variances differ (radius and depth change along it): at
  * 640 x 480 the centre pixel's variance over N under-predicted the column offsets' variance by
  * up to 28 %, which the stripes candidate took up (docs/model_lab.md section 7).
  */
struct BinWeights
{
  std::vector<std::pair<int, double>> bins, qbins; // (bin index, weight) in each bin set

  const std::vector<std::pair<int, double>> &
  of (bool quantised) const { return quantised ? qbins : bins; }
};

/** The mean offset of one column in the frames of a half. */
struct ColumnStat
{
  int rec;
  PixelContext ctx;     // the column's pixel nearest the principal point's row (shared variances)
  double frames = 0, ss = 0;
  BinWeights noise;     // the pixels' noise in the offsets, averaged over the frames
};

/** The mean offset of one frame. */
struct FrameStat
{
  int rec;
  int frame;
  double D = 0, count = 0;
  BinWeights noise;     // the pixels' noise in the offset
};

struct ModelLab::Data
{
  Half half = Half::all;
  std::vector<PixelRow> px;
  std::vector<Bin> bins, qbins;
  std::vector<ColumnStat> cols;
  std::vector<FrameStat> frames;
  std::vector<PixelContext> rep;             // per recording: the used pixel nearest the centre
  std::vector<std::vector<int>> frame_list;  // per recording: frames of the half
  std::vector<char> plane;                   // per recording: plane scene
  double samples = 0;
};

namespace
{

bool
inHalfFrame (Half half, bool split_frames, int t)
{
  if (half == Half::all || !split_frames)
    return true;
  return (t % 2 == 0) == (half == Half::fit);
}

bool
inHalfPixel (Half half, bool split_frames, int u, int v)
{
  if (half == Half::all || split_frames)
    return true;
  return (((u / 32) + (v / 32)) % 2 == 0) == (half == Half::fit);
}

PixelContext
pixelContext (const RecordingMeasurement &m, std::size_t i)
{
  PixelContext c = m.noiseContexts ().at (static_cast<double> (i % m.width), static_cast<double> (i / m.width),
                                          m.surface_mm[i]);
  c.true_depth_mm = m.surface_mm[i];
  c.cos_incidence = m.cos_incidence[i];
  c.edge_distance_px = std::min (m.edge_distance_px[i], 1e3f);
  return c;
}

std::unique_ptr<ModelLab::Data>
buildData (const std::vector<RecordingMeasurement::ConstPtr> &recs, Half half, bool split_frames)
{
  auto d = std::make_unique<ModelLab::Data> ();
  d->half = half;
  std::unordered_map<std::uint64_t, int> bin_of, qbin_of;
  for (std::size_t r = 0; r < recs.size (); ++r)
  {
    const RecordingMeasurement &m = *recs[r];
    const std::size_t n = static_cast<std::size_t> (m.width) * m.height;
    const double fb1000 = 1000.0 * m.fb ();
    std::vector<int> frames;
    for (int t = 0; t < m.frames; ++t)
      if (inHalfFrame (half, split_frames, t))
        frames.push_back (t);
    d->frame_list.push_back (frames);
    d->plane.push_back (m.plane_scene ? 1 : 0);

    // Pixels of the half with at least two samples in it: mean and count.
    std::vector<float> mean (n, 0.0f), J (n, 0.0f);
    std::vector<std::uint16_t> count (n, 0);
    std::vector<std::uint8_t> member (n, 0);
#pragma omp parallel for schedule(static)
    for (int v = 0; v < m.height; ++v)
      for (int u = 0; u < m.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * m.width + u;
        if (!m.used[i] || !inHalfPixel (half, split_frames, u, v))
          continue;
        double s = 0;
        int c = 0;
        for (int t : frames)
        {
          const std::uint16_t z = m.at (t, i);
          if (z)
          {
            s += z;
            ++c;
          }
        }
        if (c < 2)
          continue;
        member[i] = 1;
        count[i] = static_cast<std::uint16_t> (c);
        mean[i] = static_cast<float> (s / c);
        J[i] = static_cast<float> (kernels::depthPerDisparityMm (m.surface_mm[i], m.fb ()));
      }

    // Frame and column-frame mean offsets, in disparity.
    const int W = m.width;
    std::vector<double> Dt (frames.size (), 0.0), Dtc (frames.size () * W, 0.0);
    std::vector<double> Nt (frames.size (), 0.0), Ntc (frames.size () * W, 0.0);
#pragma omp parallel for schedule(static)
    for (int k = 0; k < static_cast<int> (frames.size ()); ++k)
    {
      const int t = frames[k];
      double s = 0, c = 0;
      for (std::size_t i = 0; i < n; ++i)
      {
        if (!member[i])
          continue;
        const std::uint16_t z = m.at (t, i);
        if (!z)
          continue;
        s += (z - mean[i]) / J[i];
        c += 1;
      }
      Dt[k] = c > 0 ? s / c : 0.0;
      Nt[k] = c;
      for (std::size_t i = 0; i < n; ++i)
      {
        if (!member[i])
          continue;
        const std::uint16_t z = m.at (t, i);
        if (!z)
          continue;
        const int u = static_cast<int> (i % W);
        Dtc[k * W + u] += (z - mean[i]) / J[i] - Dt[k];
        Ntc[k * W + u] += 1;
      }
      for (int u = 0; u < W; ++u)
        if (Ntc[k * W + u] > 0)
          Dtc[k * W + u] /= Ntc[k * W + u];
    }

    // Covariate bins (recording, radius, depth, incidence angle, edge distance, and sub-step
    // phase for the quantised set) of every pixel of the half: the bins' contexts are their
    // pixels' mean covariates, and the column and frame offsets below average over all pixels.
    double zmin = 1e30, zmax = 0, rmax = 1;
    for (std::size_t i = 0; i < n; ++i)
      if (member[i])
      {
        zmin = std::min<double> (zmin, m.surface_mm[i]);
        zmax = std::max<double> (zmax, m.surface_mm[i]);
      }
    rmax = std::hypot (std::max (m.camera.cx (), m.width - 1 - m.camera.cx ()),
                       std::max (m.camera.cy (), m.height - 1 - m.camera.cy ())) + 1e-6;
    const int bins_first = static_cast<int> (d->bins.size ()), qbins_first = static_cast<int> (d->qbins.size ());
    std::vector<int> bin_at (n, -1), qbin_at (n, -1);
    for (int v = 0; v < m.height; ++v)
      for (int u = 0; u < m.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * m.width + u;
        if (!member[i])
          continue;
        const double rr = m.radius (u, v);
        const int rb = std::min (7, static_cast<int> (8 * rr / rmax));
        const int zb = std::min (7, static_cast<int> (8 * (m.surface_mm[i] - zmin) / (zmax - zmin + 1e-6)));
        const double angle = std::acos (std::min (1.0f, m.cos_incidence[i])) * 57.29577951308232;
        const int ab = std::min (7, static_cast<int> (angle / 11.25));
        const float e = m.edge_distance_px[i];
        const int eb = e < 2.0f ? 0 : (e < 5.0f ? 1 : 2);
        const int qb = std::min (19, static_cast<int> (20 * m.phase[i]));
        const std::uint64_t key = ((((static_cast<std::uint64_t> (r) * 8 + rb) * 8 + zb) * 8 + ab) * 3 + eb);
        const std::uint64_t qkey = key * 20 + qb;
        for (int which = 0; which < 2; ++which)
        {
          auto &map = which ? qbin_of : bin_of;
          auto &bins = which ? d->qbins : d->bins;
          const std::uint64_t kk = which ? qkey : key;
          auto it = map.find (kk);
          int b;
          if (it == map.end ())
          {
            b = static_cast<int> (bins.size ());
            map.emplace (kk, b);
            bins.emplace_back ();
            bins.back ().rec = static_cast<int> (r);
            bins.back ().ctx = pixelContext (m, i);
          }
          else
            b = it->second;
          Bin &B = bins[b];
          B.su += u;
          B.sv += v;
          B.sr += rr;
          B.sz += m.surface_mm[i];
          B.scos += m.cos_incidence[i];
          B.sedge += std::min (e, 1e3f);
          B.sphase += m.phase[i];
          B.w += 1;
          (which ? qbin_at : bin_at)[i] = b;
        }
      }

    // Per pixel: total and within sums of squares. The per-pixel parts use a regular subsample
    // of about 100000 pixels per recording (every pixel up to 320 x 240, every second one in
    // both directions at 640 x 480): plenty for the fits, a quarter of the time. The frame and
    // column offsets use every pixel.
    const int stride = std::max (1, static_cast<int> (std::ceil (std::sqrt (double (n) / 100000.0))));
    for (int v = 0; v < m.height; v += stride)
      for (int u = 0; u < m.width; u += stride)
      {
        const std::size_t i = static_cast<std::size_t> (v) * m.width + u;
        if (!member[i])
          continue;
        PixelRow p;
        p.rec = static_cast<int> (r);
        p.index = static_cast<std::uint32_t> (i);
        p.n = count[i];
        p.mean_mm = mean[i];
        p.disparity = static_cast<float> (fb1000 / mean[i]);
        p.J = J[i];
        p.x = static_cast<float> ((u - m.camera.cx ()) / m.camera.fx ());
        p.y = static_cast<float> ((v - m.camera.cy ()) / m.camera.fy ());
        p.log_n = std::log (p.n);
        p.inlier = m.inlier[i];
        double st = 0, sw = 0;
        for (std::size_t k = 0; k < frames.size (); ++k)
        {
          const std::uint16_t z = m.at (frames[k], i);
          if (!z)
            continue;
          const double dev = z - mean[i];
          st += dev * dev;
          const double w = dev - J[i] * (Dt[k] + Dtc[k * W + u]);
          sw += w * w;
        }
        p.ss_total = static_cast<float> (st);
        p.ss_within = static_cast<float> (sw);
        p.bin = bin_at[i];
        p.qbin = qbin_at[i];
        for (int which = 0; which < 2; ++which)
        {
          Bin &B = (which ? d->qbins : d->bins)[which ? p.qbin : p.bin];
          B.dof += p.n - 1;
          B.ssw += p.ss_within;
          B.npix += 1;
          B.sum_log_n += p.log_n;
        }
        d->samples += p.n;
        d->px.push_back (p);
      }

    // How the pixels' independent noise reaches the column and frame offsets (BinWeights).
    const int F = static_cast<int> (frames.size ());
    const int nb = static_cast<int> (d->bins.size ()) - bins_first, nq = static_cast<int> (d->qbins.size ()) - qbins_first;
    std::vector<double> col_w (static_cast<std::size_t> (W) * nb, 0.0), col_q (static_cast<std::size_t> (W) * nq, 0.0);
    std::vector<double> frame_w (static_cast<std::size_t> (F) * nb, 0.0), frame_q (static_cast<std::size_t> (F) * nq, 0.0);
    std::vector<double> col_frames (W, 0.0);
    for (int u = 0; u < W; ++u)
      for (int k = 0; k < F; ++k)
        col_frames[u] += Ntc[k * W + u] > 1 ? 1.0 : 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!member[i])
        continue;
      const int u = static_cast<int> (i % W);
      const int b = bin_at[i] - bins_first, q = qbin_at[i] - qbins_first;
      const double base = (1.0 - 1.0 / count[i]) / (double (J[i]) * J[i]);
      double in_columns = 0;
      for (int k = 0; k < F; ++k)
      {
        if (!m.at (frames[k], i))
          continue;
        const double nc = Ntc[k * W + u];
        if (nc > 1)
          in_columns += 1.0 / (nc * nc);
        if (Nt[k] >= 2)
        {
          frame_w[static_cast<std::size_t> (k) * nb + b] += base / (Nt[k] * Nt[k]);
          frame_q[static_cast<std::size_t> (k) * nq + q] += base / (Nt[k] * Nt[k]);
        }
      }
      if (col_frames[u] > 0)
      {
        col_w[static_cast<std::size_t> (u) * nb + b] += base * in_columns / col_frames[u];
        col_q[static_cast<std::size_t> (u) * nq + q] += base * in_columns / col_frames[u];
      }
    }
    const auto sparse = [] (const double *w, int count, int first, std::vector<std::pair<int, double>> &out) {
      out.clear ();
      for (int b = 0; b < count; ++b)
        if (w[b] > 0)
          out.emplace_back (first + b, w[b]);
    };

    // Columns and frames.
    std::vector<double> best_dist (W, 1e30);
    std::vector<std::size_t> best_index (W, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (member[i])
      {
        const int u = static_cast<int> (i % W);
        const double dist = std::fabs (double (i / W) - m.camera.cy ());
        if (dist < best_dist[u])
        {
          best_dist[u] = dist;
          best_index[u] = i;
        }
      }
    for (int u = 0; u < W; ++u)
    {
      if (best_dist[u] > 1e29)
        continue;
      ColumnStat c;
      c.rec = static_cast<int> (r);
      c.ctx = pixelContext (m, best_index[u]);
      for (std::size_t k = 0; k < frames.size (); ++k)
        if (Ntc[k * W + u] > 1)
        {
          c.frames += 1;
          c.ss += Dtc[k * W + u] * Dtc[k * W + u];
        }
      if (c.frames < 1)
        continue;
      sparse (&col_w[static_cast<std::size_t> (u) * nb], nb, bins_first, c.noise.bins);
      sparse (&col_q[static_cast<std::size_t> (u) * nq], nq, qbins_first, c.noise.qbins);
      d->cols.push_back (c);
    }
    std::size_t centre = 0;
    double cbest = 1e30;
    for (std::size_t i = 0; i < n; ++i)
      if (member[i])
      {
        const double dd = m.radius (double (i % W), double (i / W));
        if (dd < cbest)
        {
          cbest = dd;
          centre = i;
        }
      }
    d->rep.push_back (pixelContext (m, centre));
    for (std::size_t k = 0; k < frames.size (); ++k)
    {
      if (Nt[k] < 2)
        continue;
      FrameStat f;
      f.rec = static_cast<int> (r);
      f.frame = frames[k];
      f.D = Dt[k];
      f.count = Nt[k];
      sparse (&frame_w[k * nb], nb, bins_first, f.noise.bins);
      sparse (&frame_q[k * nq], nq, qbins_first, f.noise.qbins);
      d->frames.push_back (f);
    }
  }
  // Bin contexts: the pixels' mean covariates; phase bins keep their mean sub-step phase.
  for (int which = 0; which < 2; ++which)
    for (Bin &B : which ? d->qbins : d->bins)
    {
      const RecordingMeasurement &m = *recs[B.rec];
      B.ctx.u = B.su / B.w;
      B.ctx.v = B.sv / B.w;
      B.ctx.radius_px = B.sr / B.w;
      B.ctx.cos_incidence = B.scos / B.w;
      B.ctx.edge_distance_px = B.sedge / B.w;
      double z = B.sz / B.w;
      if (which)
      {
        const double step = m.camera.disparity_subpixel > 0 ? m.camera.disparity_subpixel : CameraInfo ().disparity_subpixel;
        const double fb1000 = 1000.0 * m.fb ();
        const double levels = std::floor (fb1000 / z / step);
        z = fb1000 / ((levels + B.sphase / B.w) * step);
      }
      B.ctx.depth_mm = z;
      B.ctx.true_depth_mm = z;
    }
  return d;
}

/** The most basis functions a linear bias term may have at one pixel. */
constexpr int kMaxBiasBasis = 16;

/** The model as the fits see it: the term whose bias is linear (a distortion grid, fitted by
  * least squares with the surfaces) and the term that rounds apart from the rest.
  */
struct ModelView
{
  const NoiseModel &model;
  bool quantised = false;
  NoiseModel without_grid;   // the model less the linear bias term (its bias is per pixel)
  NoiseModel pre_quantised;  // ... and less the rounding term (its bias is per pixel too)
  NoiseTerm::ConstPtr quantiser;
  NoiseTerm::ConstPtr grid;
  explicit ModelView (const NoiseModel &m) : model (m), without_grid (m), pre_quantised (m)
  {
    for (const auto &t : m.terms ())
    {
      if (!grid && t->linearBiasSupport () > 0)
        grid = t;
      if (!quantiser && t->quantises ())
        quantiser = t;
    }
    quantised = quantiser != nullptr;
    if (grid)
    {
      if (grid->linearBiasSupport () > kMaxBiasBasis)
        throw pcl::BadArgumentException ("model lab: the term '" + grid->name () + "' has more than " +
                                         std::to_string (kMaxBiasBasis) + " bias basis functions at a pixel");
      without_grid.remove (grid->name ());
      pre_quantised.remove (grid->name ());
    }
    if (quantiser)
      pre_quantised.remove (quantiser->name ());
  }
};

/** The disparity offset (px) of linear bias term \a grid with node values \a nodes at (u, v). */
double
linearBiasPx (const NoiseTerm &grid, const std::vector<double> &nodes, double u, double v)
{
  int idx[kMaxBiasBasis];
  double wt[kMaxBiasBasis];
  grid.linearBiasBasis (u, v, idx, wt);
  double offset = 0;
  for (int k = 0; k < grid.linearBiasSupport (); ++k)
    offset += wt[k] * nodes[idx[k]];
  return offset;
}

/** Result of the linear fit of surfaces (and a distortion grid) for one model on one half. */
struct StaticState
{
  std::vector<Eigen::Vector3d> planes;   // per recording (plane scenes)
  std::vector<double> grid;              // fitted grid node offsets, px (empty: the model's own)
  std::vector<double> ss_static;         // per bin of the set in use: sum of n e^2
  std::vector<double> bin_var, bin_col, bin_bias; // per bin of the set in use
  std::vector<float> pixel_bias;         // quantised models: per-pixel bias (mm) of the other terms
};

/** Variance of a recorded sample: the model's (never below its floor) plus that of the
  * recording's resolution, whole millimetres (16-bit PNG depth): 1/12 mm^2.
  */
double
floorVar (const NoiseModel &m, double var)
{
  const double f = m.minSigmaMm () * m.minSigmaMm ();
  return (var > f ? var : f) + 1.0 / 12.0;
}

/** Bin moments of the model (without the distortion grid, whose bias is per pixel). */
void
binMoments (const ModelView &mv, const std::vector<Bin> &bins, StaticState &s)
{
  s.bin_var.resize (bins.size ());
  s.bin_col.resize (bins.size ());
  s.bin_bias.resize (bins.size ());
  for (std::size_t b = 0; b < bins.size (); ++b)
  {
    const NoiseMoments m = mv.without_grid.moments (bins[b].ctx);
    s.bin_var[b] = floorVar (mv.model, m.variance_mm2);
    s.bin_col[b] = m.column_variance_mm2;
    s.bin_bias[b] = mv.quantised ? m.bias_mm : 0.0;
  }
}

/** Linear fit of the surfaces (plane scenes) and, when fit_grid, of the distortion grid, to the
  * pixels' mean disparities with the model's other biases removed; then the static sums.
  */
void
staticFit (const ModelView &mv, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
           bool fit_grid, StaticState &s)
{
  const std::vector<Bin> &bins = mv.quantised ? d.qbins : d.bins;
  binMoments (mv, bins, s);
  const std::size_t R = recs.size ();
  const std::vector<double> fixed_grid = mv.grid ? mv.grid->parameters () : std::vector<double> ();
  const int G = mv.grid && fit_grid ? static_cast<int> (fixed_grid.size ()) : 0;
  const int K = mv.grid ? mv.grid->linearBiasSupport () : 0;
  // Quantised models: the mean offset of the rounding at each pixel's own sub-step phase (it
  // changes by a whole step over a phase, too fast for bins), from the bin's noise before it.
  s.pixel_bias.clear ();
  if (mv.quantised)
  {
    std::vector<double> pre_var (bins.size ()), pre_bias (bins.size ());
    for (std::size_t b = 0; b < bins.size (); ++b)
    {
      const NoiseMoments m = mv.pre_quantised.moments (bins[b].ctx);
      pre_var[b] = m.variance_mm2;
      pre_bias[b] = m.bias_mm;
    }
    s.pixel_bias.resize (d.px.size ());
    const int P = static_cast<int> (d.px.size ());
#pragma omp parallel for schedule(static)
    for (int k = 0; k < P; ++k)
    {
      const PixelRow &p = d.px[k];
      const RecordingMeasurement &m = *recs[p.rec];
      const double d0 = 1000.0 * m.fb () / m.surface_mm[p.index] - pre_bias[p.qbin] / p.J;
      double offset = 0, var = 0;
      mv.quantiser->roundingMoments (d0, std::sqrt (pre_var[p.qbin]) / p.J, offset, var);
      s.pixel_bias[k] = static_cast<float> (pre_bias[p.qbin] - p.J * offset);
    }
  }
  const int N = static_cast<int> (3 * R) + G;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero (N, N);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero (N);
  auto gridAt = [&] (const PixelRow &p, int *idx, double *wt) {
    const RecordingMeasurement &m = *recs[p.rec];
    mv.grid->linearBiasBasis (double (p.index % m.width), double (p.index / m.width), idx, wt);
  };
  auto target = [&] (const PixelRow &p) {
    double t = p.disparity + (mv.quantised ? s.pixel_bias[&p - d.px.data ()] / p.J : 0.0);
    if (mv.grid && !fit_grid)
    {
      int idx[kMaxBiasBasis];
      double wt[kMaxBiasBasis];
      gridAt (p, idx, wt);
      for (int k = 0; k < K; ++k)
        t -= wt[k] * fixed_grid[idx[k]];
    }
    return t;
  };
  for (const PixelRow &p : d.px)
  {
    if (!d.plane[p.rec] || !p.inlier)
      continue;
    const int b = mv.quantised ? p.qbin : p.bin;
    const double w = p.n * p.J * p.J / (s.bin_var[b] + s.bin_col[b]);
    const double t = target (p);
    const double row[3] = {1.0, p.x, p.y};
    const int o = 3 * p.rec;
    for (int a = 0; a < 3; ++a)
    {
      rhs[o + a] += w * row[a] * t;
      for (int c = 0; c < 3; ++c)
        A (o + a, o + c) += w * row[a] * row[c];
    }
    if (G)
    {
      int idx[kMaxBiasBasis];
      double wt[kMaxBiasBasis];
      gridAt (p, idx, wt);
      for (int k = 0; k < K; ++k)
      {
        const int gk = static_cast<int> (3 * R) + idx[k];
        rhs[gk] += w * wt[k] * t;
        for (int a = 0; a < 3; ++a)
        {
          A (gk, o + a) += w * wt[k] * row[a];
          A (o + a, gk) += w * wt[k] * row[a];
        }
        for (int l = 0; l < K; ++l)
          A (gk, static_cast<int> (3 * R) + idx[l]) += w * wt[k] * wt[l];
      }
    }
  }
  // A small ridge keeps nodes without data (and the grid's mean, which the planes share) at zero.
  const double ridge = 1e-9 * (A.diagonal ().cwiseAbs ().maxCoeff () + 1.0);
  for (int k = 0; k < N; ++k)
    A (k, k) += (k >= static_cast<int> (3 * R)) ? 1e3 * ridge : ridge;
  const Eigen::VectorXd sol = A.ldlt ().solve (rhs);
  s.planes.assign (R, Eigen::Vector3d::Zero ());
  for (std::size_t r = 0; r < R; ++r)
    s.planes[r] = sol.segment<3> (3 * r);
  s.grid.clear ();
  if (G)
    s.grid.assign (sol.data () + 3 * R, sol.data () + N);

  s.ss_static.assign (bins.size (), 0.0);
  for (const PixelRow &p : d.px)
  {
    const RecordingMeasurement &m = *recs[p.rec];
    double predicted;
    if (d.plane[p.rec])
      predicted = s.planes[p.rec].dot (Eigen::Vector3d (1.0, p.x, p.y));
    else
      predicted = 1000.0 * m.fb () / m.surface_mm[p.index];
    if (G)
    {
      int idx[kMaxBiasBasis];
      double wt[kMaxBiasBasis];
      gridAt (p, idx, wt);
      for (int k = 0; k < K; ++k)
        predicted += wt[k] * s.grid[idx[k]];
    }
    const double e = p.J * (target (p) - predicted);
    const int b = mv.quantised ? p.qbin : p.bin;
    s.ss_static[b] += p.n * e * e;
  }
}

/** The frame-dependent bias of the model at a context, per frame, relative to the steady state. */
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

/** Variance (disparity px^2) that the pixels' independent noise gives an offset whose noise
  * weights are \a w, from the bins' variances in \a s (the set the model uses).
  */
double
pixelNoiseIn (const BinWeights &w, bool quantised, const StaticState &s)
{
  double v = 0;
  for (const auto &bw : w.of (quantised))
    v += bw.second * s.bin_var[bw.first];
  return v;
}

/** Predicted variance (disparity px^2) of a column's mean offset about its frame's mean: the
  * model's column-shared variance less the part shared by the whole frame (taken out with the
  * frame's mean), plus the noise of the mean of the column's pixels.
  */
double
columnOffsetVariance (const ModelView &mv, const ColumnStat &c, const StaticState &s)
{
  const NoiseMoments m = mv.without_grid.moments (c.ctx);
  const double J = kernels::depthPerDisparityMm (c.ctx.true_depth_mm, c.ctx.fb_px_m);
  return (m.column_variance_mm2 - m.frame_variance_mm2) / (J * J) + pixelNoiseIn (c.noise, mv.quantised, s);
}

/** The NLL (sum, not per sample) of a half under a model, on bins. */
double
objective (const ModelView &mv, const ModelLab::Data &d, const StaticState &s, bool with_static = true)
{
  const std::vector<Bin> &bins = mv.quantised ? d.qbins : d.bins;
  double L = 0;
  for (std::size_t b = 0; b < bins.size (); ++b)
  {
    const Bin &B = bins[b];
    const double var = s.bin_var[b], V = var + s.bin_col[b];
    L += 0.5 * B.dof * std::log (kTwoPi * var) + B.ssw / (2 * var);
    if (with_static)
      L += 0.5 * B.npix * std::log (kTwoPi * V) - 0.5 * B.sum_log_n + s.ss_static[b] / (2 * V);
  }
  for (const ColumnStat &c : d.cols)
  {
    const double v = columnOffsetVariance (mv, c, s);
    const double J = kernels::depthPerDisparityMm (c.ctx.true_depth_mm, c.ctx.fb_px_m);
    L += 0.5 * c.frames * std::log (kTwoPi * v) + c.ss / (2 * v) + c.frames * std::log (J);
  }
  const bool timed = frameDependent (mv.model);
  std::vector<double> pred;
  int current = -1;
  double J = 1, frame_var = 0;
  for (std::size_t k = 0; k < d.frames.size (); ++k)
  {
    const FrameStat &f = d.frames[k];
    if (f.rec != current)
    {
      current = f.rec;
      const PixelContext &ctx = d.rep[f.rec];
      const NoiseMoments m = mv.without_grid.moments (ctx);
      J = kernels::depthPerDisparityMm (ctx.true_depth_mm, ctx.fb_px_m);
      frame_var = m.frame_variance_mm2;
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
    const double v = pixelNoiseIn (f.noise, mv.quantised, s) + frame_var / (J * J);
    const double e = f.D - pred[j];
    L += 0.5 * std::log (kTwoPi * v) + e * e / (2 * v) + std::log (J);
  }
  return L;
}

// ---------------------------------------------------------------------------------------------
// The Ceres fit of the non-linear parameters.

/** Where a model's fitted parameters live: (term index, parameter index), with a scale. */
struct ParameterMap
{
  std::vector<std::pair<std::size_t, std::size_t>> where;
  std::vector<double> scale;
};


ParameterMap
parameterMap (const NoiseModel &m, int only_term = -1)
{
  ParameterMap pm;
  for (std::size_t t = 0; t < m.terms ().size (); ++t)
  {
    const auto &term = m.terms ()[t];
    // A linear bias term is fitted by least squares, not here.
    if (term->linearBiasSupport () > 0 || (only_term >= 0 && static_cast<int> (t) != only_term))
      continue;
    const auto values = term->parameters ();
    for (std::size_t k = 0; k < values.size (); ++k)
    {
      pm.where.emplace_back (t, k);
      pm.scale.push_back (std::max (std::fabs (values[k]), term->typicalScale (k)));
    }
  }
  return pm;
}

void
setScaled (NoiseModel &m, const ParameterMap &pm, const double *x)
{
  std::size_t k = 0;
  while (k < pm.where.size ())
  {
    const std::size_t t = pm.where[k].first;
    auto values = m.terms ()[t]->parameters ();
    for (; k < pm.where.size () && pm.where[k].first == t; ++k)
      values[pm.where[k].second] = x[k] * pm.scale[k];
    m.terms ()[t]->setParameters (values);
  }
}

class NllFunction : public ceres::FirstOrderFunction
{
public:
  NllFunction (const NoiseModel &model, const ParameterMap &pm, const ModelLab::Data &d, const StaticState &s,
               double samples)
    : model_ (model), pm_ (pm), d_ (d), s_ (s), samples_ (samples)
  {
  }

  bool
  Evaluate (const double *x, double *cost, double *gradient) const override
  {
    const int n = NumParameters ();
    if (!value (x, cost))
      return false;
    if (gradient)
    {
      std::vector<double> xx (x, x + n);
      for (int k = 0; k < n; ++k)
      {
        const double h = 1e-5 * std::max (1.0, std::fabs (x[k]));
        double fp = 0, fm = 0;
        xx[k] = x[k] + h;
        const bool okp = value (xx.data (), &fp);
        xx[k] = x[k] - h;
        const bool okm = value (xx.data (), &fm);
        xx[k] = x[k];
        if (!okp || !okm)
          return false;
        gradient[k] = (fp - fm) / (2 * h);
      }
    }
    return true;
  }

  int
  NumParameters () const override { return static_cast<int> (pm_.where.size ()); }

private:
  bool
  value (const double *x, double *cost) const
  {
    setScaled (model_, pm_, x);
    const ModelView mv (model_);
    binMoments (mv, mv.quantised ? d_.qbins : d_.bins, s_);
    // Variance parameters are fitted on the temporal contrasts only (as REML does): the
    // pixels' means are for the surfaces and the bias terms, so that an unmodelled bias is not
    // taken for noise.
    const double L = objective (mv, d_, s_, false) / samples_;
    if (!std::isfinite (L))
      return false;
    *cost = L;
    return true;
  }

  mutable NoiseModel model_;
  const ParameterMap &pm_;
  const ModelLab::Data &d_;
  // The caller's state, copied once: each evaluation only rewrites its per-bin moments (a copy
  // per evaluation moved the per-pixel biases too, a quarter of a proof's time under ASan).
  mutable StaticState s_;
  double samples_;
};

/** Starting values for a term that was just added (its neutral values sit on a saddle): the
  * term's own, some from the recordings.
  */
void
startValues (NoiseTerm &term, const std::vector<RecordingMeasurement::ConstPtr> &recs)
{
  effects::LabStart facts;
  facts.image_width = recs.front ()->width;
  facts.image_height = recs.front ()->height;
  facts.disparity_step_px = recs.front ()->camera.disparity_subpixel;
  term.setLabStart (facts);
}

/** One Ceres run over the parameters of \a pm, from the model's current values. */
void
ceresRun (NoiseModel &model, const ParameterMap &pm, const ModelLab::Data &d, const StaticState &s,
          const LabSettings &settings)
{
  if (pm.where.empty ())
    return;
  std::vector<double> x (pm.where.size ());
  for (std::size_t k = 0; k < x.size (); ++k)
    x[k] = model.terms ()[pm.where[k].first]->parameters ()[pm.where[k].second] / pm.scale[k];
  ceres::GradientProblem problem (new NllFunction (model, pm, d, s, d.samples));
  ceres::GradientProblemSolver::Options options;
  options.line_search_direction_type = ceres::LBFGS;
  options.max_num_iterations = settings.max_lbfgs_iterations;
  options.function_tolerance = 1e-10;
  options.gradient_tolerance = 1e-9;
  options.logging_type = ceres::SILENT;
  ceres::GradientProblemSolver::Summary summary;
  const std::vector<double> x0 = x;
  ceres::Solve (options, problem, x.data (), &summary);
  bool finite = true;
  for (double v : x)
    finite = finite && std::isfinite (v);
  setScaled (model, pm, finite ? x.data () : x0.data ());
}

/** NLL per sample of \a model on \a d with the surfaces (and a grid) fitted to it. */
double
fitObjective (NoiseModel &model, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
              StaticState &s)
{
  const ModelView mv (model);
  staticFit (mv, d, recs, true, s);
  if (mv.grid && !s.grid.empty ())
    model.find (mv.grid->name ())->setParameters (s.grid);
  return objective (ModelView (model), d, s) / d.samples;
}

/** Refits \a start on \a d: alternating linear (surfaces, grid) and Ceres (the rest) fits.
  * \a new_term: index of a term just added to a fitted model, or -1. A new term is first fitted
  * alone (from the best of a few starting scales), then everything together; since the model
  * without it is nested (the term at neutral values), the result is never worse on \a d than
  * that model, whose objective is \a nested_objective.
  */
NoiseModel
fitOn (const NoiseModel &start, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
       const LabSettings &settings, int new_term = -1, double nested_objective = kNaN)
{
  NoiseModel model (start);
  const ParameterMap pm = parameterMap (model);
  bool has_static = false; // a rounding or a linear bias term: the static fit changes with the rest
  for (const auto &t : model.terms ())
    has_static = has_static || t->quantises () || t->linearBiasSupport () > 0;
  const int outer = has_static ? std::max (1, settings.outer_iterations) : std::min (2, std::max (1, settings.outer_iterations));
  if (new_term >= 0)
  {
    const ParameterMap own = parameterMap (model, new_term);
    if (!own.where.empty ())
    {
      // Scan the scale of the term's first parameter, then fit its parameters alone.
      const auto &term = model.terms ()[new_term];
      const std::vector<double> initial = term->parameters ();
      double best = std::numeric_limits<double>::infinity ();
      std::vector<double> best_values = initial;
      for (double f : {0.1, 0.3, 1.0, 3.0})
      {
        std::vector<double> v = initial;
        v[0] *= f;
        term->setParameters (v);
        StaticState s;
        const double L = fitObjective (model, d, recs, s);
        if (L < best)
          best = L, best_values = v;
      }
      term->setParameters (best_values);
      StaticState s;
      fitObjective (model, d, recs, s);
      ceresRun (model, own, d, s, settings);
    }
  }
  for (int it = 0; it < outer; ++it)
  {
    StaticState s;
    fitObjective (model, d, recs, s);
    ceresRun (model, pm, d, s, settings);
  }
  StaticState s;
  const double L = fitObjective (model, d, recs, s);
  if (new_term >= 0 && std::isfinite (nested_objective) && !(L <= nested_objective))
  {
    // Worse than without the term: the fit is stuck; the nested model with the term neutral.
    NoiseModel nested (start);
    const std::string name = nested.terms ()[new_term]->name ();
    const NoiseTerm::Ptr neutral = makeNoiseTerm (name);
    nested.terms ()[new_term]->setParameters (neutral->parameters ());
    return nested;
  }
  return model;
}

/** \a model with the effect \a name added at its starting values. */
NoiseModel
withTerm (const NoiseModel &model, const std::string &name, const std::vector<RecordingMeasurement::ConstPtr> &recs)
{
  NoiseModel m (model);
  NoiseTerm::Ptr term = makeNoiseTerm (name);
  startValues (*term, recs);
  m.add (*term);
  return m;
}

/** Fits the effect \a name on top of \a fitted (\a given refitted on \a d, objective
  * \a nested_objective) with fitOn. For disparity_quantization it also fits from \a given (the
  * model before that refit) plus the term, and keeps the better on \a d: the refit polynomial
  * has already absorbed the phase-averaged step^2/12 variance, and from there adding the step
  * at its camera.yaml value doubles that variance while the joint fit stalls in the valley
  * between them (at 640 x 480, where the noise is 0.2 to 0.5 of a step, it ended at step 0.085
  * with a worse fit and fell back to the nested model; docs/model_lab.md section 7).
  * \a fits: -1 both fits and the better; 0 only the fit from \a fitted; 1 only the one from
  * \a given (so that the two can run in parallel; the caller then keeps the better).
  */
NoiseModel
fitWithEffect (const NoiseModel &fitted, const NoiseModel &given, const std::string &name, const ModelLab::Data &d,
               const std::vector<RecordingMeasurement::ConstPtr> &recs, const LabSettings &settings,
               double nested_objective, int fits = -1)
{
  const int added = static_cast<int> (fitted.terms ().size ());
  const bool two_fits = effectInfo (name).quantises && given.terms ().size () == fitted.terms ().size ();
  if (fits == 1 && two_fits)
    return fitOn (withTerm (given, name, recs), d, recs, settings, added, nested_objective);
  NoiseModel m = fitOn (withTerm (fitted, name, recs), d, recs, settings, added, nested_objective);
  if (fits >= 0 || !two_fits)
    return m;
  NoiseModel alt = fitOn (withTerm (given, name, recs), d, recs, settings, added, nested_objective);
  NoiseModel m_copy (m), alt_copy (alt);
  StaticState sm, sa;
  return fitObjective (alt_copy, d, recs, sa) < fitObjective (m_copy, d, recs, sm) ? alt : m;
}

/** NLL per sample of a fitted model on held-out data (surfaces refitted, nothing else). */
double
scoreOn (const NoiseModel &model, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs)
{
  const ModelView mv (model);
  StaticState s;
  staticFit (mv, d, recs, false, s);
  return objective (mv, d, s) / d.samples;
}

/** Data drawn from \a model in the shape of \a d (parametric bootstrap): no effect beyond it. */
std::unique_ptr<ModelLab::Data>
synthesise (const ModelLab::Data &d, const NoiseModel &model, const std::vector<RecordingMeasurement::ConstPtr> &recs,
            std::mt19937_64 &rng)
{
  auto out = std::make_unique<ModelLab::Data> (d);
  const ModelView mv (model);
  StaticState s;
  staticFit (mv, d, recs, false, s);
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
  std::vector<double> pvar (P), pcol (P), pbias (P);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < P; ++k)
  {
    const PixelRow &p = out->px[k];
    const NoiseMoments mo = no_grid.moments (pixelContext (*recs[p.rec], p.index));
    pvar[k] = floorVar (model, mo.variance_mm2);
    pcol[k] = mo.column_variance_mm2;
    pbias[k] = mo.bias_mm;
  }
  for (int k = 0; k < P; ++k)
  {
    PixelRow &p = out->px[k];
    const double var = pvar[k], col = pcol[k], bias = pbias[k];
    const double ssw = var * chi2 (p.n - 1);
    p.ss_within = static_cast<float> (ssw);
    out->bins[p.bin].ssw += ssw;
    out->qbins[p.qbin].ssw += ssw;
    // The pixel's mean: the fitted surface with the model's bias, plus the noise of a mean.
    const RecordingMeasurement &m = *recs[p.rec];
    double disparity = d.plane[p.rec] ? s.planes[p.rec].dot (Eigen::Vector3d (1.0, p.x, p.y))
                                      : 1000.0 * m.fb () / m.surface_mm[p.index];
    if (mv.grid)
      disparity += linearBiasPx (*mv.grid, grid_nodes, double (p.index % m.width), double (p.index / m.width));
    disparity -= bias / p.J;
    disparity += gauss (rng) * std::sqrt ((var + col) / p.n) / p.J;
    p.disparity = static_cast<float> (disparity);
  }
  for (ColumnStat &c : out->cols)
    c.ss = columnOffsetVariance (mv, c, s) * chi2 (c.frames);
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
    const double v = pixelNoiseIn (f.noise, mv.quantised, s) + m.frame_variance_mm2 / (J * J);
    f.D = pred + gauss (rng) * std::sqrt (v);
  }
  return out;
}

} // namespace

// ---------------------------------------------------------------------------------------------

ModelLab::ModelLab (const LabSettings &settings) : settings_ (settings) {}

ModelLab::~ModelLab () = default;

void
ModelLab::addRecording (const RecordingMeasurement::ConstPtr &recording)
{
  if (!recording)
    throw pcl::BadArgumentException ("ModelLab::addRecording: the recording is null");
  recordings_.push_back (recording);
  for (auto &d : data_)
    d.reset ();
}

bool
ModelLab::splitsFrames () const
{
  for (const auto &r : recordings_)
    if (r->frames < 4)
      return false;
  return true;
}

const ModelLab::Data &
ModelLab::data (Half half) const
{
  if (recordings_.empty ())
    throw pcl::BadArgumentException ("model lab: no recording was added");
  auto &slot = data_[static_cast<int> (half)];
  if (!slot)
    slot = buildData (recordings_, half, splitsFrames ());
  if (slot->px.empty ())
    throw pcl::BadArgumentException ("model lab: no pixel has two valid samples in each half of the data");
  return *slot;
}

PixelContext
ModelLab::context (std::size_t r, std::size_t i) const
{
  return pixelContext (*recordings_.at (r), i);
}

LabMetrics
ModelLab::evaluate (const NoiseModel &model, Half half) const
{
  const Data &d = data (half);
  const ModelView mv (model);
  StaticState s;
  staticFit (mv, d, recordings_, false, s);
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
      const double var = s.bin_var[b], V = var + s.bin_col[b];
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
  double sd2 = 0, b2 = 0, lp = 0, in1 = 0, in2 = 0, count = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : sd2, b2, lp, in1, in2, count) num_threads(settings_.threads > 0 ? settings_.threads : omp_get_max_threads ())
  for (int k = 0; k < P; ++k)
  {
    const PixelRow &p = d.px[k];
    const RecordingMeasurement &m = *recordings_[p.rec];
    const PixelContext ctx = pixelContext (m, p.index);
    const NoiseMoments mo = model.moments (ctx);
    const double var = floorVar (model, mo.variance_mm2), col = mo.column_variance_mm2;
    const double sd_pred = std::sqrt (var + col + p.J * p.J * drift_var[p.rec]);
    const double sd_meas = std::sqrt (p.ss_total / (p.n - 1));
    sd2 += (sd_pred - sd_meas) * (sd_pred - sd_meas);
    double surface_disparity = d.plane[p.rec] ? s.planes[p.rec].dot (Eigen::Vector3d (1.0, p.x, p.y))
                                              : 1000.0 * m.fb () / m.surface_mm[p.index];
    const double mu = 1000.0 * m.fb () / surface_disparity + mo.bias_mm;
    const double e = p.mean_mm - mu;
    b2 += e * e;
    const double V = var + col;
    lp += 0.5 * (p.n - 1) * std::log (kTwoPi * var) + p.ss_within / (2 * var);
    lp += 0.5 * std::log (kTwoPi * V / p.n) + p.n * e * e / (2 * V);
    const double sigma = std::sqrt (V);
    for (int t : d.frame_list[p.rec])
    {
      const std::uint16_t z = m.at (t, p.index);
      if (!z)
        continue;
      const double dev = std::fabs (z - mu - p.J * drift[p.rec][t]);
      in1 += dev <= sigma ? 1 : 0;
      in2 += dev <= 2 * sigma ? 1 : 0;
      count += 1;
    }
  }
  out.pixels = P;
  out.samples = d.samples;
  out.sd_rmse_mm = std::sqrt (sd2 / P);
  out.bias_rmse_mm = std::sqrt (b2 / P);
  out.nll = (L + lp) / d.samples;
  out.within_1sigma = count > 0 ? in1 / count : 0;
  out.within_2sigma = count > 0 ? in2 / count : 0;
  return out;
}

NoiseModel
ModelLab::fit (const NoiseModel &model, Half half) const
{
  return fitOn (model, data (half), recordings_, settings_);
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
  const Data &d = data (Half::all);
  NoiseModel base = fitOn (current, d, recordings_, settings_);
  StaticState s;
  const double nested = fitObjective (base, d, recordings_, s);
  return fitWithEffect (base, current, effect, d, recordings_, settings_, nested);
}

std::vector<Candidate>
ModelLab::rankCandidates (const NoiseModel &current) const
{
  const Data &A = data (Half::fit);
  const Data &B = data (Half::score);
  auto say = [&] (const std::string &line) {
    if (settings_.progress)
      settings_.progress (line);
  };
  const int threads = settings_.threads > 0 ? settings_.threads : omp_get_max_threads ();

  // Which effects the data can show at all.
  std::vector<Candidate> out;
  bool any_plane = false, any_edges = false;
  std::vector<double> projectors;
  for (const auto &r : recordings_)
  {
    any_plane = any_plane || r->plane_scene;
    projectors.push_back (r->active_projectors);
    std::size_t near = 0;
    for (std::size_t i = 0; i < r->used.size (); ++i)
      near += (r->used[i] && r->edge_distance_px[i] < 3.0f) ? 1 : 0;
    any_edges = any_edges || near > 100;
  }
  const bool varied_projectors = *std::max_element (projectors.begin (), projectors.end ()) >
                                 *std::min_element (projectors.begin (), projectors.end ());
  for (const auto &name : noiseEffectNames ())
  {
    if (current.find (name))
      continue;
    Candidate c;
    c.effect = name;
    const EffectInfo &info = effectInfo (name);
    c.physics = info.physics;
    c.signature = info.signature;
    if ((info.lab_needs & effects::kNeedsPlaneScene) && !any_plane)
      c.applicable = false, c.note = "needs a plane scene (meta.yaml scene: plane) to tell a static bias from the surface";
    else if ((info.lab_needs & effects::kNeedsVariedProjectors) && !varied_projectors)
      c.applicable = false, c.note = "every recording has the same number of active projectors";
    else if ((info.lab_needs & effects::kNeedsFrameSplit) && !splitsFrames ())
      c.applicable = false, c.note = "needs recordings of at least 4 frames";
    else if ((info.lab_needs & effects::kNeedsDepthEdges) && !any_edges)
      c.applicable = false, c.note = "no depth edges in the recordings";
    out.push_back (c);
  }

  // Data sets: 0 is the real data; 1 .. null_replicates are drawn from the current model (the
  // null: the same fits where no effect is missing). On each, the current model refitted on the
  // fit half is what every candidate has to beat.
  struct DataSet
  {
    const Data *fit = nullptr, *score = nullptr;
    std::unique_ptr<Data> own_fit, own_score;
    NoiseModel given, fitted; // the model the candidates start from as given, and refitted
    double fitted_score = 0, fitted_objective = 0;
  };
  const int S = 1 + std::max (0, settings_.null_replicates);
  std::vector<DataSet> sets (S);
  auto refit = [&] (DataSet &set) {
    set.fitted = fitOn (set.given, *set.fit, recordings_, settings_);
    set.fitted_score = scoreOn (set.fitted, *set.score, recordings_);
    StaticState state;
    set.fitted_objective = fitObjective (set.fitted, *set.fit, recordings_, state);
  };
  say ("lab: refitting the current model on the fit half");
  sets[0].fit = &A;
  sets[0].score = &B;
  sets[0].given = current;
  refit (sets[0]);
  const NoiseModel &base = sets[0].fitted;
  std::mt19937_64 rng (settings_.seed);
  for (int rep = 1; rep < S; ++rep)
  {
    say ("lab: significance, drawing bootstrap data set " + std::to_string (rep) + " of " + std::to_string (S - 1));
    DataSet &set = sets[rep];
    set.own_fit = synthesise (A, base, recordings_, rng);
    set.own_score = synthesise (B, base, recordings_, rng);
    set.fit = set.own_fit.get ();
    set.score = set.own_score.get ();
    // As for the real data: the model as given (here the one the data were drawn from) and its
    // refit.
    set.given = base;
  }
  say ("lab: refitting the current model on the bootstrap data sets");
  parallelFor (S - 1, threads, true, [&] (int i) { refit (sets[i + 1]); });

  // Every fit of a candidate on every data set is one task, so that the two threads stay busy
  // to the end (disparity_quantization, fitted twice, costs more than the others together).
  struct Fit
  {
    int set, candidate;
    bool from_given; // disparity_quantization's second fit, on top of the model as given
    NoiseModel model;
    double objective = 0;
  };
  std::vector<Fit> fits;
  for (int set = 0; set < S; ++set)
    for (int k = 0; k < static_cast<int> (out.size ()); ++k)
      if (out[k].applicable)
      {
        fits.push_back ({set, k, false, NoiseModel (), 0.0});
        if (effectInfo (out[k].effect).quantises &&
            sets[set].given.terms ().size () == sets[set].fitted.terms ().size ())
          fits.push_back ({set, k, true, NoiseModel (), 0.0});
      }
  say ("lab: fitting " + std::to_string (out.size ()) + " candidates on " + std::to_string (S) + " data sets (" +
       std::to_string (fits.size ()) + " fits)");
  // The longest first: disparity_quantization's fits, then the rest in order.
  std::vector<int> order (fits.size ());
  std::iota (order.begin (), order.end (), 0);
  std::stable_partition (order.begin (), order.end (),
                         [&] (int i) { return effectInfo (out[fits[i].candidate].effect).quantises; });
  parallelFor (static_cast<int> (fits.size ()), threads, true, [&] (int i) {
    Fit &f = fits[order[i]];
    const DataSet &set = sets[f.set];
    f.model = fitWithEffect (set.fitted, set.given, out[f.candidate].effect, *set.fit, recordings_, settings_,
                             set.fitted_objective, f.from_given ? 1 : 0);
    NoiseModel copy (f.model);
    StaticState state;
    f.objective = fitObjective (copy, *set.fit, recordings_, state);
  });

  // Per data set and candidate the better of its fits on the fit half, scored on the other half.
  std::vector<std::vector<double>> null_gains (out.size (), std::vector<double> (S - 1, 0.0));
  std::vector<int> chosen;
  for (int i = 0; i < static_cast<int> (fits.size ()); ++i)
  {
    const bool same = !chosen.empty () && fits[chosen.back ()].set == fits[i].set &&
                      fits[chosen.back ()].candidate == fits[i].candidate;
    if (!same)
      chosen.push_back (i);
    else if (fits[i].objective < fits[chosen.back ()].objective)
      chosen.back () = i;
  }
  parallelFor (static_cast<int> (chosen.size ()), threads, true, [&] (int i) {
    const Fit &f = fits[chosen[i]];
    const DataSet &set = sets[f.set];
    const double gain = set.fitted_score - scoreOn (f.model, *set.score, recordings_);
    if (f.set > 0)
    {
      null_gains[f.candidate][f.set - 1] = gain;
      return;
    }
    Candidate &c = out[f.candidate];
    c.model = f.model;
    c.gain = gain;
    c.metrics = evaluate (c.model, Half::score);
#pragma omp critical(lab_progress)
    say ("lab: candidate " + c.effect + ": held-out gain " + std::to_string (c.gain) + " nats/sample");
  });
  for (std::size_t k = 0; k < out.size (); ++k)
  {
    Candidate &c = out[k];
    const auto &g = null_gains[k];
    if (!c.applicable || g.empty ())
      continue;
    const double mean = std::accumulate (g.begin (), g.end (), 0.0) / g.size ();
    double var = 0;
    for (double x : g)
      var += (x - mean) * (x - mean);
    c.null_mean = mean;
    c.null_sd = g.size () > 1 ? std::sqrt (var / (g.size () - 1)) : 0.0;
    c.threshold = mean + settings_.null_sigmas * c.null_sd;
    c.total_gain = c.gain * B.samples;
    c.significant = c.gain > c.threshold && c.gain > 0 && c.total_gain >= settings_.min_total_gain_nats;
  }
  std::stable_sort (out.begin (), out.end (), [] (const Candidate &a, const Candidate &b) {
    if (a.applicable != b.applicable)
      return a.applicable;
    return a.gain > b.gain;
  });
  return out;
}

void
ModelLab::predict (const NoiseModel &model, std::size_t r, std::vector<float> &sd_mm, std::vector<float> &mean_mm) const
{
  const Data &d = data (Half::all);
  const RecordingMeasurement &m = *recordings_.at (r);
  const ModelView mv (model);
  StaticState s;
  staticFit (mv, d, recordings_, false, s);
  const std::size_t n = static_cast<std::size_t> (m.width) * m.height;
  sd_mm.assign (n, std::numeric_limits<float>::quiet_NaN ());
  mean_mm.assign (n, std::numeric_limits<float>::quiet_NaN ());
  double drift_var = 0;
  const PixelContext &rep = d.rep[r];
  const double Jr = kernels::depthPerDisparityMm (rep.true_depth_mm, rep.fb_px_m);
  if (frameDependent (model))
  {
    double s1 = 0, s2 = 0;
    for (int t : d.frame_list[r])
    {
      const double b = frameBias (mv.without_grid, rep, t) / Jr;
      s1 += b;
      s2 += b * b;
    }
    const double k = static_cast<double> (d.frame_list[r].size ());
    drift_var = k > 1 ? (s2 - s1 * s1 / k) / (k - 1) : 0.0;
  }
  const double fb1000 = 1000.0 * m.fb ();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!m.used[i])
      continue;
    const double J = kernels::depthPerDisparityMm (m.surface_mm[i], m.fb ());
    const NoiseMoments mo = model.moments (pixelContext (m, i));
    const double var = floorVar (model, mo.variance_mm2);
    sd_mm[i] = static_cast<float> (std::sqrt (var + mo.column_variance_mm2 + J * J * drift_var));
    const double x = (double (i % m.width) - m.camera.cx ()) / m.camera.fx ();
    const double y = (double (i / m.width) - m.camera.cy ()) / m.camera.fy ();
    const double disparity = d.plane[r] ? s.planes[r].dot (Eigen::Vector3d (1.0, x, y)) : fb1000 / m.surface_mm[i];
    mean_mm[i] = static_cast<float> (fb1000 / disparity + mo.bias_mm);
  }
}

void
ModelLab::frameCurve (const NoiseModel &model, std::size_t r, std::vector<double> &predicted_mm,
                      std::vector<double> &measured_mm) const
{
  const Data &d = data (Half::all);
  const PixelContext &rep = d.rep.at (r);
  const double J = kernels::depthPerDisparityMm (rep.true_depth_mm, rep.fb_px_m);
  const auto &list = d.frame_list[r];
  predicted_mm.assign (list.size (), 0.0);
  measured_mm.assign (list.size (), std::numeric_limits<double>::quiet_NaN ());
  const ModelView mv (model);
  const NoiseModel &no_grid = mv.without_grid;
  double mean = 0;
  for (std::size_t k = 0; k < list.size (); ++k)
  {
    predicted_mm[k] = frameDependent (model) ? frameBias (no_grid, rep, list[k]) : 0.0;
    mean += predicted_mm[k];
  }
  for (double &p : predicted_mm)
    p -= mean / list.size ();
  for (const FrameStat &f : d.frames)
    if (f.rec == static_cast<int> (r))
    {
      const std::size_t k = std::lower_bound (list.begin (), list.end (), f.frame) - list.begin ();
      measured_mm[k] = f.D * J;
    }
}

} // namespace lab
} // namespace texlet
} // namespace pcl
