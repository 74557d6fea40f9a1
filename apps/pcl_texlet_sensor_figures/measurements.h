/*
 * pcl_texlet_sensor_figures: the measurements the studies take of simulated frames, and numbers
 * as the data files write them.
 */
#pragma once

#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/simulation/kinect_simulator.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace pcl_texlet_sensor_figures
{

const double kNaN = std::numeric_limits<double>::quiet_NaN ();

/** \brief A number for a data file: NaN as gnuplot's "NaN". */
std::string
num (double v, int precision = 6);

/** \brief Per-pixel statistics over frames of the reported depth minus the true depth, mm. */
struct PixelStats
{
  int width = 0, height = 0;
  std::vector<int> n;        ///< frames with a reading
  std::vector<double> mean;  ///< mean residual, mm
  std::vector<double> m2;    ///< sum of squared deviations from the mean, mm^2
  std::vector<double> truth; ///< true depth, mm (0: no surface)
  std::size_t frames = 0;

  double
  sd (std::size_t i) const { return n[i] >= 2 ? std::sqrt (m2[i] / (n[i] - 1)) : kNaN; }

  double
  bias (std::size_t i) const { return n[i] >= 1 ? mean[i] : kNaN; }
};

/** \brief The statistics over \a frames of sensor 0 of \a sim against its true depth. */
PixelStats
pixelStats (const pcl::texlet::sim::KinectSimulator &sim, const std::vector<pcl::texlet::DepthFrame> &frames);

/** \brief Mean of \a value over the pixels where it is finite, in bins of the distance from the
  * principal point (bin width \a bin_px); one row per bin with data.
  */
struct RadialProfile
{
  double bin_px = 10;
  std::vector<double> sum;
  std::vector<int> count;

  void
  add (double r, double v)
  {
    if (!std::isfinite (v))
      return;
    const std::size_t b = static_cast<std::size_t> (r / bin_px);
    if (b >= sum.size ())
    {
      sum.resize (b + 1, 0.0);
      count.resize (b + 1, 0);
    }
    sum[b] += v;
    ++count[b];
  }

  double
  mean (std::size_t b) const { return b < sum.size () && count[b] > 0 ? sum[b] / count[b] : kNaN; }

  double
  centre (std::size_t b) const { return (b + 0.5) * bin_px; }
};

/** \brief Mean of the finite values in blocks of \a block x \a block pixels: a map for gnuplot's
  * `with image` (x y value, a blank line after each row), in pixel coordinates of the block centres.
  */
std::string
blockMap (const std::vector<double> &values, int width, int height, int block);

/** \brief Mean of finite values. */
double
meanOf (const std::vector<double> &v);

/** \brief Standard deviation of finite values. */
double
sdOf (const std::vector<double> &v);

/** \brief Standard normal CDF. */
double
normalCdf (double x);

/** \brief SD (mm) of a reading whose noise-free SD is \a sigma_mm once rounded to whole millimetres. */
double
withRounding (double sigma_mm);

} // namespace pcl_texlet_sensor_figures
