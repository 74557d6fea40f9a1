#include "recorded_resolution.h"

#include <pcl_texlet/noise/effects/disparity_quantization.h>

#include <algorithm>
#include <cmath>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

namespace
{

/** The model's variance, never below its floor. */
double
flooredVariance (const NoiseModel &model, double variance_mm2)
{
  const double f = model.minSigmaMm () * model.minSigmaMm ();
  return variance_mm2 > f ? variance_mm2 : f;
}

} // namespace

RecordedMoments
recordedMoments (const NoiseModel &model, bool quantised, double variance_mm2, double mean_mm)
{
  RecordedMoments out;
  const double var = flooredVariance (model, variance_mm2);
  if (quantised || !std::isfinite (mean_mm))
  {
    out.variance_mm2 = var + 1.0 / 12.0;
    return out;
  }
  effects::DisparityQuantization::moments (mean_mm, std::sqrt (var), 1.0, out.mean_offset_mm, out.variance_mm2);
  return out;
}

double
recordedVarianceOverPhases (const NoiseModel &model, bool quantised, double variance_mm2)
{
  const double var = flooredVariance (model, variance_mm2);
  return quantised ? var + 1.0 / 12.0 : effects::DisparityQuantization::varianceOverPhases (std::sqrt (var), 1.0);
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
