#include "measurements.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace pcl_texlet_sensor_figures
{

namespace
{

/** Variance of rounding to whole millimetres (Sheppard's correction), mm^2. */
const double kRoundingVariance = 1.0 / 12.0;

} // namespace

std::string
num (double v, int precision)
{
  if (!std::isfinite (v))
    return "NaN";
  std::ostringstream s;
  s << std::setprecision (precision) << v;
  return s.str ();
}

PixelStats
pixelStats (const pcl::texlet::sim::KinectSimulator &sim, const std::vector<pcl::texlet::DepthFrame> &frames)
{
  const pcl::texlet::sim::SensorTruth &t = sim.truth (0);
  PixelStats s;
  s.width = t.width;
  s.height = t.height;
  const std::size_t n = static_cast<std::size_t> (t.width) * t.height;
  s.n.assign (n, 0);
  s.mean.assign (n, 0.0);
  s.m2.assign (n, 0.0);
  s.truth.resize (n);
  s.frames = frames.size ();
  for (std::size_t i = 0; i < n; ++i)
    s.truth[i] = 1000.0 * t.depth_m[i];
  for (const auto &f : frames)
    for (std::size_t i = 0; i < n; ++i)
    {
      if (f.depth_mm[i] == 0 || s.truth[i] <= 0)
        continue;
      // Welford's update: stable for any number of frames.
      const double r = f.depth_mm[i] - s.truth[i];
      const int k = ++s.n[i];
      const double delta = r - s.mean[i];
      s.mean[i] += delta / k;
      s.m2[i] += delta * (r - s.mean[i]);
    }
  return s;
}

std::string
blockMap (const std::vector<double> &values, int width, int height, int block)
{
  std::ostringstream out;
  out << "# u_px v_px value (mean over " << block << "x" << block << " pixel blocks)\n";
  for (int by = 0; by * block < height; ++by)
  {
    for (int bx = 0; bx * block < width; ++bx)
    {
      double sum = 0;
      int n = 0;
      for (int v = by * block; v < std::min (height, (by + 1) * block); ++v)
        for (int u = bx * block; u < std::min (width, (bx + 1) * block); ++u)
        {
          const double x = values[static_cast<std::size_t> (v) * width + u];
          if (std::isfinite (x))
          {
            sum += x;
            ++n;
          }
        }
      out << num ((bx + 0.5) * block - 0.5) << " " << num ((by + 0.5) * block - 0.5) << " "
          << (n > 0 ? num (sum / n) : std::string ("NaN")) << "\n";
    }
    out << "\n";
  }
  return out.str ();
}

double
meanOf (const std::vector<double> &v)
{
  double s = 0;
  int n = 0;
  for (const double x : v)
    if (std::isfinite (x))
    {
      s += x;
      ++n;
    }
  return n > 0 ? s / n : kNaN;
}

double
sdOf (const std::vector<double> &v)
{
  const double m = meanOf (v);
  double s = 0;
  int n = 0;
  for (const double x : v)
    if (std::isfinite (x))
    {
      s += (x - m) * (x - m);
      ++n;
    }
  return n > 1 ? std::sqrt (s / (n - 1)) : kNaN;
}

double
normalCdf (double x)
{
  return 0.5 * std::erfc (-x / std::sqrt (2.0));
}

double
withRounding (double sigma_mm)
{
  return std::sqrt (sigma_mm * sigma_mm + kRoundingVariance);
}

} // namespace pcl_texlet_sensor_figures
