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
  * frame (taken out with the frame's mean), plus the noise of the mean of the line's pixels.
  */
double
lineOffsetVariance (const ModelView &mv, const LineStat &c, bool row, const StaticState &s);

/** The NLL (sum, not per sample) of a half under a model, on bins; without \a with_static, the
  * temporal parts only (the pixels' means left out).
  */
double
objective (const ModelView &mv, const ModelLab::Data &d, const StaticState &s, bool with_static = true);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
