/*
 * pcl_texlet model lab (internal): the Gaussian NLL of a half under a model, on the bins, the
 * column offsets and the frame offsets (the parts named in model_lab.h), and the predicted
 * variances of those offsets.
 */
#pragma once

#include "static_fit.h"

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** Whether a term of \a model changes with the frame index. */
bool
frameDependent (const NoiseModel &model);

/** The frame-dependent bias of the model at a context, per frame, relative to the steady state. */
double
frameBias (const NoiseModel &model, PixelContext ctx, int frame);

/** Variance (disparity px^2) that the pixels' independent noise gives an offset whose noise
  * weights are \a w, from the bins' variances in \a s (the set the model uses).
  */
double
pixelNoiseIn (const BinWeights &w, bool quantised, const StaticState &s);

/** Predicted variance (disparity px^2) of a column's (\a row: a row's) mean offset about its
  * frame's mean: the model's column-shared (row-shared) variance less the part shared by the whole
  * frame (taken out with the frame's mean), plus the noise of the mean of the line's pixels (more
  * where neighbours share it over a window, windowedNoiseFactor()).
  */
double
lineOffsetVariance (const ModelView &mv, const LineStat &c, bool row, const StaticState &s);

/** How much more the pixels' own noise reaches a mean over a line (\a dims 1) or a whole frame
  * (2) of pixels when a share of it is shared over a window (NoiseMoments::window_share,
  * window_px = w): 1 + share (w^dims - 1), a pixel's summed correlation with the others over the
  * window, far from the image's border.
  */
double
windowedNoiseFactor (const NoiseMoments &m, int dims);

/** Predicted variance (disparity px^2) of a frame's mean offset \a f: the model's frame-shared
  * variance (\a m at the recording's central pixel, J its depth per disparity) plus the noise of
  * the mean of the frame's pixels.
  */
double
frameOffsetVariance (const ModelView &mv, const FrameStat &f, const NoiseMoments &m, double J, const StaticState &s);

/** The NLL (sum, not per sample) of a half under a model, on bins; without \a with_static, the
  * temporal parts only (the pixels' means left out).
  */
double
objective (const ModelView &mv, const ModelLab::Data &d, const StaticState &s, bool with_static = true);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
