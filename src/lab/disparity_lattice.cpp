#include <pcl_texlet/lab/disparity_lattice.h>

#include <pcl/exceptions.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <sstream>
#include <string>

namespace pcl
{
namespace texlet
{
namespace lab
{

namespace
{

constexpr double kTwoPi = 6.283185307179586;

/** A depth value and its weight: the coherence its own millimetre rounding leaves it. */
struct WeightedValue
{
  double inverse_mm; ///< 1 / z
  double weight;
};

/** The weighted sum of exp(2 pi i C / z) over the values, and the sum of the squared weights
  * (what that sum's modulus is expected to be on the lattice).
  */
std::complex<double>
latticeSum (const std::vector<WeightedValue> &values, double constant_mm)
{
  double re = 0.0, im = 0.0;
  for (const WeightedValue &v : values)
  {
    const double a = kTwoPi * constant_mm * v.inverse_mm;
    re += v.weight * std::cos (a);
    im += v.weight * std::sin (a);
  }
  return {re, im};
}

/** The 90th percentile, over the values whose rounding leaves a lattice step resolved (phase SD
  * under 0.15), of each value's distance from the lattice C / (k + phase) over the SD its whole-mm
  * rounding explains: about 1.6 for values on the lattice, far more for clusters of consecutive
  * millimetres that merely look coherent. NaN with fewer than 8 such values.
  */
double
residualRatio (const std::vector<WeightedValue> &values, double constant_mm, double phase)
{
  std::vector<double> ratios;
  for (const WeightedValue &v : values)
  {
    const double sd = constant_mm * v.inverse_mm * v.inverse_mm / std::sqrt (12.0); // cycles
    if (sd >= 0.15)
      continue;
    const double x = constant_mm * v.inverse_mm - phase;
    ratios.push_back (std::abs (x - std::round (x)) / sd);
  }
  if (ratios.size () < 8)
    return std::nan ("");
  const std::size_t k = (ratios.size () * 9) / 10;
  std::nth_element (ratios.begin (), ratios.begin () + k, ratios.end ());
  return ratios[k];
}

/** The largest coherence near \a c, within \a half_width either side (golden-section search). */
double
refinePeak (const std::vector<WeightedValue> &values, double c, double half_width)
{
  const double g = 0.5 * (std::sqrt (5.0) - 1.0);
  double a = c - half_width, b = c + half_width;
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double f1 = std::abs (latticeSum (values, x1)), f2 = std::abs (latticeSum (values, x2));
  for (int it = 0; it < 80 && b - a > 1e-9 * c; ++it)
  {
    if (f1 < f2)
    {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + g * (b - a);
      f2 = std::abs (latticeSum (values, x2));
    }
    else
    {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - g * (b - a);
      f1 = std::abs (latticeSum (values, x1));
    }
  }
  return 0.5 * (a + b);
}

/** Marks the nonzero depths of \a depth_mm in \a seen (65536 flags, one per millimetre value). */
void
markDepths (const std::vector<std::uint16_t> &depth_mm, std::vector<bool> &seen)
{
  for (const std::uint16_t z : depth_mm)
    if (z > 0)
      seen[z] = true;
}

/** fitDisparityLattice() of the distinct depth values flagged in \a seen. */
DisparityLattice
fitDistinctDepths (const std::vector<bool> &seen, double camera_constant_mm)
{
  if (!(camera_constant_mm > 0.0) || !std::isfinite (camera_constant_mm))
    throw pcl::BadArgumentException ("fitDisparityLattice: the camera's lattice constant 1000 f b / step must be "
                                     "positive (got " + std::to_string (camera_constant_mm) + " mm)");
  DisparityLattice out;
  out.camera_constant_mm = camera_constant_mm;

  // Rounding to whole mm moves 1 / z by an SD of 1 / (sqrt (12) z^2); in lattice steps of
  // 1 / C that is a phase SD s, which leaves exp (-2 pi^2 s^2) of a value's coherence.
  std::vector<WeightedValue> values;
  double sum_w2 = 0.0, w_min = 1e300, w_max = 0.0;
  for (int z = 1; z < 65536; ++z)
    if (seen[z])
    {
      const double s = camera_constant_mm / (std::sqrt (12.0) * double (z) * z);
      const double weight = std::exp (-0.5 * kTwoPi * kTwoPi * s * s);
      if (weight < 1e-3)
        continue;
      values.push_back ({1.0 / z, weight});
      sum_w2 += weight * weight;
      w_min = std::min (w_min, 1.0 / z);
      w_max = std::max (w_max, 1.0 / z);
    }
  out.values = values.size ();
  if (values.size () < 8 || w_max <= w_min)
    return out;

  // The coherence peak of C is about 1 / (2 (w_max - w_min)) wide: a grid of an eighth of that.
  const double lo = 0.7 * camera_constant_mm, hi = 1.45 * camera_constant_mm;
  const double step = std::max ((hi - lo) / 200000.0, 1.0 / (16.0 * (w_max - w_min)));
  double best_c = lo, best = -1.0;
  for (double c = lo; c <= hi; c += step)
  {
    const double m = std::abs (latticeSum (values, c));
    if (m > best)
    {
      best = m;
      best_c = c;
    }
  }
  // A lattice is coherent and not chance: on values without one, |sum|^2 is exponential with mean
  // sum_w2, so the largest of the ~cells independent peaks searched exceeds x^2 with probability
  // about cells exp (-x^2 / sum_w2); a lattice must be beyond what that gives 1 time in 1000.
  const double cells = (hi - lo) / (16.0 * step) + 8.0;
  const auto isLattice = [&] (double c) {
    const std::complex<double> sum = latticeSum (values, c);
    const double r = std::abs (sum) / sum_w2;
    const double phase = std::arg (sum) / kTwoPi;
    return r >= DisparityLattice::kMinCoherence && r * r * sum_w2 >= std::log (cells * 1000.0) &&
           residualRatio (values, c, phase) <= DisparityLattice::kMaxResidualRatio;
  };
  double c = refinePeak (values, best_c, step);
  // Every multiple of C fits as well as C: the coarsest lattice that holds the values is C / m
  // for the largest m whose lattice is still one.
  for (int m = 3; m >= 2; --m)
  {
    const double sub = refinePeak (values, c / m, step / m);
    if (isLattice (sub))
    {
      c = sub;
      break;
    }
  }
  const std::complex<double> sum = latticeSum (values, c);
  out.constant_mm = c;
  out.coherence = std::abs (sum) / sum_w2;
  double phase = std::arg (sum) / kTwoPi;
  out.phase = phase - std::floor (phase);
  out.residual_ratio = residualRatio (values, c, out.phase);
  out.found = isLattice (c);
  return out;
}

} // namespace

DisparityLattice
fitDisparityLattice (const std::vector<std::uint16_t> &depth_mm, double camera_constant_mm)
{
  std::vector<bool> seen (65536, false);
  markDepths (depth_mm, seen);
  return fitDistinctDepths (seen, camera_constant_mm);
}

DisparityLattice
fitDisparityLattice (const std::vector<RecordingMeasurement::ConstPtr> &recordings)
{
  if (recordings.empty () || !recordings.front ())
    throw pcl::BadArgumentException ("fitDisparityLattice: no recording");
  const RecordingMeasurement &first = *recordings.front ();
  const double step = first.camera.disparity_subpixel > 0 ? first.camera.disparity_subpixel : CameraInfo ().disparity_subpixel;
  if (!(first.fb () > 0.0))
    throw pcl::BadArgumentException ("fitDisparityLattice: " + first.name +
                                     ": camera.yaml gives no f b (baseline_m), so no lattice to search around");
  std::vector<bool> seen (65536, false);
  for (const auto &r : recordings)
    markDepths (r->depth_mm, seen);
  return fitDistinctDepths (seen, 1000.0 * first.fb () / step);
}

std::string
latticeSummary (const DisparityLattice &l)
{
  std::ostringstream out;
  if (!l.found)
  {
    out << "disparity lattice: none in " << l.values << " distinct depth values (coherence " << std::setprecision (2)
        << l.coherence << "; camera.yaml implies C = " << std::fixed << std::setprecision (0) << l.camera_constant_mm
        << " mm)";
    return out.str ();
  }
  out << "disparity lattice: depths sit on z_k = C / (k + " << std::setprecision (2) << l.phase << ") with C = "
      << std::fixed << std::setprecision (0) << l.constant_mm << " mm, " << std::setprecision (3)
      << l.constant_mm / l.camera_constant_mm << " times the " << std::setprecision (0) << l.camera_constant_mm
      << " mm camera.yaml implies (1000 f b / step); coherence " << std::setprecision (2) << l.coherence << ", "
      << l.values << " distinct values";
  return out.str ();
}

} // namespace lab
} // namespace texlet
} // namespace pcl
