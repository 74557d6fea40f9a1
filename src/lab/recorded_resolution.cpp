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
  return quantised ? var + 1.0 / 12.0 : roundedVarianceOverPhases (std::sqrt (var), 1.0);
}

double
roundedVarianceOverPhases (double sigma, double step)
{
  const double kPi = 3.14159265358979323846;
  const double r = 2.0 * kPi * kPi * sigma * sigma / (step * step);
  // The series' terms fall as g_k^2 / k^2; for sigma near zero (g_k near 1) as 1 / k^2, and the
  // 4000 terms leave 1.3e-5 step^2 of the 1/12.
  double lost = 0;
  for (int k = 1; k <= 4000; ++k)
  {
    const double g2 = std::exp (-2.0 * r * k * k);
    if (g2 < 1e-18)
      break;
    lost += g2 / (double (k) * k);
  }
  return std::max (0.0, sigma * sigma + step * step / 12.0 - step * step * lost / (2.0 * kPi * kPi));
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
