/*
 * pcl_texlet model lab (internal): the aggregates of one half of the recordings that the fits and
 * scores work on. Pixels with at least two samples in the half (one in single-frame sets, whose
 * within, column, row and frame parts are then empty), their covariate bins, and the
 * mean offsets of columns, rows and frames (the parts of the NLL in model_lab.h); buildData makes
 * them from the measured recordings.
 */
#pragma once

#include "quantisation_lattice.h"

#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/lab/recording_measurement.h>
#include <pcl_texlet/noise/pixel_context.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{

namespace detail
{
const double kTwoPi = 6.283185307179586;
const double kNaN = std::numeric_limits<double>::quiet_NaN ();
} // namespace detail

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
  float ss_within;  // ... after removing the frame, column-frame and row-frame means
  float dof;        // its degrees of freedom: n - 1 less the share those means take
  float log_n;
  int bin, qbin;
  std::uint8_t inlier;
};

/** Pixels with similar covariates: their within sums pooled, one context for the model. */
struct Bin
{
  PixelContext ctx;
  double dof = 0, ssw = 0, npix = 0, sum_log_n = 0;
  double su = 0, sv = 0, sr = 0, sz = 0, scos = 0, sedge = 0, sintensity = 0, sphase = 0, sdistortion = 0, w = 0;
  int rec = 0;
};

/** How the independent noise of a column's (a row's, a frame's) pixels reaches its mean offset: per
  * covariate bin b, the weight w_b with Var(offset) = sum_b w_b var_b (disparity px^2, var_b the
  * bin's variance in mm^2). w_b sums (1 - 1/n_i) / (J_i^2 N^2) over the offset's N samples i in
  * bin b (n_i: pixel i's samples in the half, whose mean is taken out first). Every pixel counts,
  * not a column's centre alone: the pixels of a column span every row, and their variances
  * change along it with radius and depth (docs/model_lab.md section 7).
  */
struct BinWeights
{
  std::vector<std::pair<int, double>> bins, qbins; // (bin index, weight) in each bin set

  const std::vector<std::pair<int, double>> &
  of (bool quantised) const { return quantised ? qbins : bins; }
};

/** The mean offsets of one column (or one row) about its frame's offset in the frames of a half. */
struct LineStat
{
  int rec;
  PixelContext ctx;     // the line's pixel nearest the principal point's row (column) (shared variances)
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

/** The aggregates of one half: what every fit and score of the lab reads. */
struct ModelLab::Data
{
  Half half = Half::all;
  std::vector<PixelRow> px;
  std::vector<Bin> bins, qbins;
  std::vector<LineStat> cols, rows;
  std::vector<FrameStat> frames;
  std::vector<PixelContext> rep;             // per recording: the used pixel nearest the centre
  std::vector<std::vector<int>> frame_list;  // per recording: frames of the half
  std::vector<char> plane;                   // per recording: plane scene
  detail::QuantisationLattice lattice;       // the recordings' disparity lattice, found once
  double samples = 0;
};

namespace detail
{

/** The model's context of pixel \a i of \a m: covariates from the measurement. */
PixelContext
pixelContext (const RecordingMeasurement &m, std::size_t i);

/** The aggregates of \a half of \a recs (frame halves when \a split_frames, else 32 px blocks).
  * A pixel's sub-step phase is that of its surface's disparity moved by \a distortion (a linear
  * bias term with its node values; none when null): the disparity the rounding sees.
  */
std::unique_ptr<ModelLab::Data>
buildData (const std::vector<RecordingMeasurement::ConstPtr> &recs, Half half, bool split_frames,
           const NoiseTerm *distortion);

} // namespace detail

} // namespace lab
} // namespace texlet
} // namespace pcl
