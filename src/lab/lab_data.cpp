#include "lab_data.h"
#include "quantisation_lattice.h"
#include "static_fit.h"

#include <pcl_texlet/kernels/structured_light.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace pcl
{
namespace texlet
{
namespace lab
{

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

} // namespace

namespace detail
{

PixelContext
pixelContext (const RecordingMeasurement &m, std::size_t i)
{
  PixelContext c = m.noiseContexts ().at (static_cast<double> (i % m.width), static_cast<double> (i / m.width),
                                          m.surface_mm[i]);
  c.true_depth_mm = m.surface_mm[i];
  c.cos_incidence = m.cos_incidence[i];
  c.edge_distance_px = std::min (m.edge_distance_px[i], 1e3f);
  if (!m.intensity.empty ())
    c.intensity = m.intensity[i];
  return c;
}

std::unique_ptr<ModelLab::Data>
buildData (const std::vector<RecordingMeasurement::ConstPtr> &recs, Half half, bool split_frames,
           const NoiseTerm *distortion)
{
  auto d = std::make_unique<ModelLab::Data> ();
  d->half = half;
  std::unordered_map<std::uint64_t, int> bin_of, qbin_of;
  // Phase bins on the lattice the quantisation term starts from (quantisation_lattice.h).
  d->lattice = quantisationLattice (recs);
  const QuantisationLattice &lattice = d->lattice;
  const std::vector<double> distortion_nodes = distortion ? distortion->parameters () : std::vector<double> ();
  auto stepOf = [&] (const RecordingMeasurement &m) {
    return lattice.stepPx (m.fb (), m.camera.disparity_subpixel > 0 ? m.camera.disparity_subpixel
                                                                   : CameraInfo ().disparity_subpixel);
  };
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

    // Pixels of the half with at least two samples in it (one where the half has one frame, a
    // single-frame set: only the pixels' means, the static part, carry information): mean and count.
    const int min_samples = frames.size () >= 2 ? 2 : 1;
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
        if (c < min_samples)
          continue;
        member[i] = 1;
        count[i] = static_cast<std::uint16_t> (c);
        mean[i] = static_cast<float> (s / c);
        J[i] = static_cast<float> (kernels::depthPerDisparityMm (m.surface_mm[i], m.fb ()));
      }

    // Frame, column-frame and row-frame mean offsets, in disparity (the rows' after the columns').
    const int W = m.width, H = m.height;
    std::vector<double> Dt (frames.size (), 0.0), Dtc (frames.size () * W, 0.0), Dtr (frames.size () * H, 0.0);
    std::vector<double> Nt (frames.size (), 0.0), Ntc (frames.size () * W, 0.0), Ntr (frames.size () * H, 0.0);
    // Calls f (i, z) for every pixel i of the half with a reading z in frame t, in pixel order.
    const auto forReadings = [&] (int t, const auto &f) {
      for (std::size_t i = 0; i < n; ++i)
      {
        if (!member[i])
          continue;
        const std::uint16_t z = m.at (t, i);
        if (z)
          f (i, z);
      }
    };
#pragma omp parallel for schedule(static)
    for (int k = 0; k < static_cast<int> (frames.size ()); ++k)
    {
      const int t = frames[k];
      double s = 0, c = 0;
      forReadings (t, [&] (std::size_t i, std::uint16_t z) {
        s += (z - mean[i]) / J[i];
        c += 1;
      });
      Dt[k] = c > 0 ? s / c : 0.0;
      Nt[k] = c;
      forReadings (t, [&] (std::size_t i, std::uint16_t z) {
        const int u = static_cast<int> (i % W);
        Dtc[k * W + u] += (z - mean[i]) / J[i] - Dt[k];
        Ntc[k * W + u] += 1;
      });
      for (int u = 0; u < W; ++u)
        if (Ntc[k * W + u] > 0)
          Dtc[k * W + u] /= Ntc[k * W + u];
      forReadings (t, [&] (std::size_t i, std::uint16_t z) {
        const int u = static_cast<int> (i % W), v = static_cast<int> (i / W);
        Dtr[k * H + v] += (z - mean[i]) / J[i] - Dt[k] - Dtc[k * W + u];
        Ntr[k * H + v] += 1;
      });
      for (int v = 0; v < H; ++v)
        if (Ntr[k * H + v] > 0)
          Dtr[k * H + v] /= Ntr[k * H + v];
    }

    // Covariate bins (recording, radius, depth, incidence angle, edge distance, grey level, and
    // sub-step phase for the quantised set) of every pixel of the half: the bins' contexts are their
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
        // Grey level in 8 bins where the recording has colour frames (terms of the intensity).
        const int ib = m.intensity.empty () ? 0 : std::min (7, static_cast<int> (m.intensity[i] * 8.0f));
        const double moved_px = distortion ? linearBiasPx (*distortion, distortion_nodes, u, v,
                                                           m.surface_mm[i], m.fb ())
                                           : 0.0;
        const double phase = subStepPhase (fb1000 / m.surface_mm[i] + moved_px, stepOf (m), lattice.phase);
        const int qb = std::min (19, static_cast<int> (20 * phase));
        const std::uint64_t key = ((((static_cast<std::uint64_t> (r) * 8 + rb) * 8 + zb) * 8 + ab) * 3 + eb) * 8 + ib;
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
          B.sintensity += m.intensity.empty () ? 0.0 : m.intensity[i];
          B.sphase += phase;
          B.sdistortion += moved_px;
          B.w += 1;
          (which ? qbin_at : bin_at)[i] = b;
        }
      }

    // Per pixel: total and within sums of squares. The per-pixel parts use a regular subsample
    // of about 100000 pixels per recording (every pixel up to 320 x 240, every second one in
    // both directions at 640 x 480), plenty for the fits; the frame and column offsets use every
    // pixel.
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
        // The frame's, column's and row's means hold 1 / N of each sample: that share of its
        // degrees of freedom goes with them.
        double st = 0, sw = 0, in_means = 0;
        for (std::size_t k = 0; k < frames.size (); ++k)
        {
          const std::uint16_t z = m.at (frames[k], i);
          if (!z)
            continue;
          const double dev = z - mean[i];
          st += dev * dev;
          const double w = dev - J[i] * (Dt[k] + Dtc[k * W + u] + Dtr[k * H + v]);
          sw += w * w;
          in_means += 1.0 / Nt[k] + 1.0 / Ntc[k * W + u] + 1.0 / Ntr[k * H + v];
        }
        p.dof = static_cast<float> (std::max (0.0, (count[i] - 1.0) - (1.0 - 1.0 / count[i]) * in_means));
        p.ss_total = static_cast<float> (st);
        p.ss_within = static_cast<float> (sw);
        p.bin = bin_at[i];
        p.qbin = qbin_at[i];
        for (int which = 0; which < 2; ++which)
        {
          Bin &B = (which ? d->qbins : d->bins)[which ? p.qbin : p.bin];
          B.dof += p.dof;
          B.ssw += p.ss_within;
          B.npix += 1;
          B.sum_log_n += p.log_n;
        }
        d->samples += p.n;
        d->px.push_back (p);
      }

    // How the pixels' independent noise reaches the column, row and frame offsets (BinWeights).
    const int F = static_cast<int> (frames.size ());
    const int nb = static_cast<int> (d->bins.size ()) - bins_first, nq = static_cast<int> (d->qbins.size ()) - qbins_first;
    std::vector<double> col_w (static_cast<std::size_t> (W) * nb, 0.0), col_q (static_cast<std::size_t> (W) * nq, 0.0);
    std::vector<double> row_w (static_cast<std::size_t> (H) * nb, 0.0), row_q (static_cast<std::size_t> (H) * nq, 0.0);
    std::vector<double> frame_w (static_cast<std::size_t> (F) * nb, 0.0), frame_q (static_cast<std::size_t> (F) * nq, 0.0);
    std::vector<double> col_frames (W, 0.0), row_frames (H, 0.0);
    for (int k = 0; k < F; ++k)
    {
      for (int u = 0; u < W; ++u)
        col_frames[u] += Ntc[k * W + u] > 1 ? 1.0 : 0.0;
      for (int v = 0; v < H; ++v)
        row_frames[v] += Ntr[k * H + v] > 1 ? 1.0 : 0.0;
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!member[i])
        continue;
      const int u = static_cast<int> (i % W), v = static_cast<int> (i / W);
      const int b = bin_at[i] - bins_first, q = qbin_at[i] - qbins_first;
      const double base = (1.0 - 1.0 / count[i]) / (double (J[i]) * J[i]);
      double in_columns = 0, in_rows = 0;
      for (int k = 0; k < F; ++k)
      {
        if (!m.at (frames[k], i))
          continue;
        const double nc = Ntc[k * W + u], nr = Ntr[k * H + v];
        if (nc > 1)
          in_columns += 1.0 / (nc * nc);
        if (nr > 1)
          in_rows += 1.0 / (nr * nr);
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
      if (row_frames[v] > 0)
      {
        row_w[static_cast<std::size_t> (v) * nb + b] += base * in_rows / row_frames[v];
        row_q[static_cast<std::size_t> (v) * nq + q] += base * in_rows / row_frames[v];
      }
    }
    const auto sparse = [] (const double *w, int count, int first, std::vector<std::pair<int, double>> &out) {
      out.clear ();
      for (int b = 0; b < count; ++b)
        if (w[b] > 0)
          out.emplace_back (first + b, w[b]);
    };

    // Columns, rows and frames. A line's context is its pixel nearest the principal point's row
    // (a row's: nearest its column).
    const auto addLines = [&] (bool rows, std::vector<LineStat> &out) {
      const int L = rows ? H : W;
      const std::vector<double> &Dl = rows ? Dtr : Dtc, &Nl = rows ? Ntr : Ntc;
      const std::vector<double> &lw = rows ? row_w : col_w, &lq = rows ? row_q : col_q;
      const double centre_line = rows ? m.camera.cx () : m.camera.cy ();
      std::vector<double> best_dist (L, 1e30);
      std::vector<std::size_t> best_index (L, 0);
      for (std::size_t i = 0; i < n; ++i)
        if (member[i])
        {
          const int line = static_cast<int> (rows ? i / W : i % W);
          const double dist = std::fabs (double (rows ? i % W : i / W) - centre_line);
          if (dist < best_dist[line])
          {
            best_dist[line] = dist;
            best_index[line] = i;
          }
        }
      for (int l = 0; l < L; ++l)
      {
        if (best_dist[l] > 1e29)
          continue;
        LineStat c;
        c.rec = static_cast<int> (r);
        c.ctx = pixelContext (m, best_index[l]);
        for (std::size_t k = 0; k < frames.size (); ++k)
          if (Nl[k * L + l] > 1)
          {
            c.frames += 1;
            c.ss += Dl[k * L + l] * Dl[k * L + l];
          }
        if (c.frames < 1)
          continue;
        sparse (&lw[static_cast<std::size_t> (l) * nb], nb, bins_first, c.noise.bins);
        sparse (&lq[static_cast<std::size_t> (l) * nq], nq, qbins_first, c.noise.qbins);
        // Pixels of one sample are their own mean: an offset of only such pixels is 0, no datum.
        if (c.noise.bins.empty ())
          continue;
        out.push_back (c);
      }
    };
    addLines (false, d->cols);
    addLines (true, d->rows);
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
      if (f.noise.bins.empty ())
        continue;
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
      if (!m.intensity.empty ())
        B.ctx.intensity = B.sintensity / B.w;
      double z = B.sz / B.w;
      if (which)
      {
        const double step = stepOf (m);
        const double fb1000 = 1000.0 * m.fb ();
        const double levels = std::floor ((fb1000 / z + B.sdistortion / B.w) / step - lattice.phase);
        z = fb1000 / ((levels + lattice.phase + B.sphase / B.w) * step);
      }
      B.ctx.depth_mm = z;
      B.ctx.true_depth_mm = z;
    }
  return d;
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
