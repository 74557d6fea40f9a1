/*
 * The Kinect simulator: the base noise reproduces the paper's polynomial, each physical effect
 * leaves its own measurable signature and none when switched off, recordings written to disk
 * read back equal, and frames are the same for a seed whatever the thread count.
 *
 * Lines starting with "[signature]" report the measured figures.
 */
#include <pcl_texlet/kernels/structured_light.h>
#include <pcl_texlet/io/recording_folder_reader.h>
#include <pcl_texlet/io/recording_writer.h>
#include <pcl_texlet/noise/effect_adapter.h>
#include <pcl_texlet/noise/effects/axial_quadratic.h>
#include <pcl_texlet/noise/effects/depth_distortion.h>
#include <pcl_texlet/noise/effects/disparity_quantization.h>
#include <pcl_texlet/noise/effects/incidence_angle.h>
#include <pcl_texlet/noise/effects/interference.h>
#include <pcl_texlet/noise/effects/intrinsics.h>
#include <pcl_texlet/noise/effects/lateral_noise.h>
#include <pcl_texlet/noise/effects/radial.h>
#include <pcl_texlet/noise/effects/temporal_drift.h>
#include <pcl_texlet/noise/effects/vertical_stripes.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/simulation/simulated_recording.h>
#include <pcl_texlet/simulation/simulation_config.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pcl::texlet;
using namespace pcl::texlet::sim;

namespace
{

constexpr int kFrames = 30;

/** Settings with the paper's noise on, or no noise at all, and every effect off. */
SimulationSettings
settingsWith (bool base_noise, std::uint32_t seed = 1)
{
  SimulationSettings s;
  s.base_noise = base_noise;
  s.seed = seed;
  return s;
}

KinectSimulator
simulator (const SceneSetup &setup, const SimulationSettings &settings, const DepthSensor &model = DepthSensor::kinect ())
{
  return KinectSimulator (setup.scene, setup.sensors (model), settings);
}

/** Per-pixel statistics over frames, in millimetres, of the readings (0 = none left out). */
struct PixelStats
{
  std::vector<int> count;
  std::vector<double> mean;
  std::vector<double> var; ///< unbiased; NaN with fewer than two readings

  explicit PixelStats (const std::vector<DepthFrame> &frames)
  {
    const std::size_t n = frames.front ().depth_mm.size ();
    count.assign (n, 0);
    mean.assign (n, 0.0);
    var.assign (n, std::nan (""));
    std::vector<double> m2 (n, 0.0);
    for (const auto &f : frames)
      for (std::size_t i = 0; i < n; ++i)
        if (f.depth_mm[i] > 0)
        {
          // Welford's update: exact enough for 16-bit values, no cancellation.
          const double x = f.depth_mm[i], d = x - mean[i];
          mean[i] += d / ++count[i];
          m2[i] += d * (x - mean[i]);
        }
    for (std::size_t i = 0; i < n; ++i)
      if (count[i] > 1)
        var[i] = m2[i] / (count[i] - 1);
  }
};

/** Variance of rounding to whole millimetres (Sheppard's correction): the sensor reports mm. */
constexpr double kRoundingVariance = 1.0 / 12.0;

double
correlation (const std::vector<double> &a, const std::vector<double> &b)
{
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size (); ++i)
  {
    ma += a[i];
    mb += b[i];
  }
  ma /= a.size ();
  mb /= b.size ();
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size (); ++i)
  {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt (saa * sbb);
}

/** Residual in mm of pixel i of a frame against the truth; NaN where either has no depth. */
double
residualMm (const DepthFrame &f, const SensorTruth &t, std::size_t i)
{
  if (f.depth_mm[i] == 0 || !(t.depth_m[i] > 0))
    return std::nan ("");
  return f.depth_mm[i] - 1000.0 * t.depth_m[i];
}

void
signature (const std::string &line)
{
  std::cout << "[signature] " << line << std::endl;
}

/** A fresh folder per test, unique across processes. */
using SimulatorFiles = pcl_texlet_test::TempDirTest;

} // namespace

// ---------------------------------------------------------------------------------------------
// Base noise: the paper's polynomial, converted to disparity and back.

TEST (Simulator, BaseNoiseMatchesThePaperPolynomialOnAFrontalWall)
{
  for (const double distance : {1.0, 1.5})
  {
    const KinectSimulator sim = simulator (planeSetup (distance, 0, 0), settingsWith (true, 11));
    const auto frames = sim.simulate (0, 0, kFrames);
    const PixelStats stats (frames);
    const DepthSensor &s = sim.sensor (0);
    const NoiseModel paper = NoiseModel::paper ();
    // Radius bins of 50 px: mean measured variance against the mean of the model's variance.
    std::vector<double> measured (9, 0.0), model (9, 0.0);
    std::vector<int> pixels (9, 0);
    for (int v = 0; v < s.height; ++v)
      for (int u = 0; u < s.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * s.width + u;
        ASSERT_EQ (stats.count[i], kFrames) << "every pixel of the wall reads in every frame";
        PixelContext ctx;
        ctx.radius_px = std::hypot (u - s.cx, v - s.cy);
        ctx.depth_mm = 1000.0 * distance;
        const int bin = static_cast<int> (ctx.radius_px / 50.0);
        const double sigma = paper.sigmaMm (ctx);
        measured[bin] += stats.var[i] - kRoundingVariance;
        model[bin] += sigma * sigma;
        ++pixels[bin];
      }
    std::ostringstream line;
    line << "base noise, frontal wall at " << distance << " m, per-pixel SD over " << kFrames
         << " frames / paper polynomial by radius bin (50 px):";
    for (int b = 0; b < 9; ++b)
    {
      if (pixels[b] < 200)
        continue;
      const double ratio = std::sqrt (measured[b] / model[b]);
      line << " " << std::fixed << std::setprecision (3) << ratio;
      EXPECT_NEAR (ratio, 1.0, 0.10) << "distance " << distance << " m, radius " << 50 * b << "-" << 50 * b + 50 << " px";
    }
    signature (line.str ());
  }
}

// ---------------------------------------------------------------------------------------------
// A base noise model with effect terms

TEST (Simulator, BaseNoiseModelSeesTheSensorsFocalBaselineAndIncidence)
{
  // A base model of a constant disparity SD and incidence growth: the simulator must evaluate it
  // with the sensor's own f b (QVGA: half the default 580 px x 7.5 cm) and each pixel's angle,
  // so that 0.05 px of disparity SD comes back as 0.05 px times the incidence factor.
  SimulationSettings s = settingsWith (true);
  s.noise_model = NoiseModel ();
  s.noise_model.setMinSigmaMm (1e-6);
  s.noise_model.add (EffectTermOf<effects::AxialQuadratic> ({0.05}));
  const DepthSensor qvga = DepthSensor::kinect (320, 240);
  ASSERT_NE (qvga.fb (), PixelContext ().fb_px_m);
  {
    const KinectSimulator sim = simulator (planeSetup (1.5, 0, 0), s, qvga);
    const SensorTruth &t = sim.truth (0);
    std::size_t checked = 0;
    for (std::size_t i = 0; i < t.sigma_px.size (); ++i)
      if (t.disparity_px[i] > 0)
      {
        EXPECT_NEAR (t.sigma_px[i], 0.05, 1e-6) << "pixel " << i;
        ++checked;
      }
    EXPECT_GT (checked, t.sigma_px.size () / 2);
  }
  s.noise_model.add (EffectTermOf<effects::IncidenceAngle> ({0.5}));
  const KinectSimulator sim = simulator (planeSetup (1.5, 0, 40), s, qvga);
  const SensorTruth &t = sim.truth (0);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < t.sigma_px.size (); ++i)
    if (t.disparity_px[i] > 0)
    {
      const double factor = 1.0 + 0.5 * (1.0 / t.cos_incidence[i] - 1.0);
      EXPECT_NEAR (t.sigma_px[i] / (0.05 * factor), 1.0, 1e-5) << "pixel " << i;
      ++checked;
    }
  EXPECT_GT (checked, t.sigma_px.size () / 2);
}

// ---------------------------------------------------------------------------------------------
// axial_quadratic

TEST (Simulator, AxialQuadraticFollowsDepthSquared)
{
  SimulationSettings on = settingsWith (false);
  setEffectEnabled (on.effects, "axial_quadratic", true);
  setEffectParameter (on.effects, "axial_quadratic", "sigma_px", 0.05);
  std::ostringstream line;
  line << "axial_quadratic (sigma_px 0.05): SD/expected at";
  double sd_per_z2_first = 0;
  for (const double z : {1.0, 2.0, 3.0})
  {
    const KinectSimulator sim = simulator (planeSetup (z, 0, 0), on);
    const PixelStats stats (sim.simulate (0, 0, kFrames));
    double var = 0;
    for (const double v : stats.var)
      var += v - kRoundingVariance;
    const double sd = std::sqrt (var / stats.var.size ());
    const double expected = 1000.0 * kernels::depthSigmaFromDisparitySigma (0.05, z, sim.sensor (0).fb ());
    EXPECT_NEAR (sd / expected, 1.0, 0.05) << z << " m";
    if (z == 1.0)
      sd_per_z2_first = sd;
    else
      EXPECT_NEAR (sd / (z * z) / sd_per_z2_first, 1.0, 0.05) << "SD / z^2 constant, " << z << " m";
    line << " " << z << " m: " << std::setprecision (3) << sd << "/" << expected << " mm";
  }
  signature (line.str ());

  // Off, with no base noise either: no noise at all, every frame the same.
  const KinectSimulator off = simulator (planeSetup (2.0, 0, 0), settingsWith (false));
  const auto frames = off.simulate (0, 0, 3);
  EXPECT_EQ (frames[0].depth_mm, frames[1].depth_mm);
  EXPECT_EQ (frames[0].depth_mm, frames[2].depth_mm);
}

// ---------------------------------------------------------------------------------------------
// radial

TEST (Simulator, RadialRaisesTheSdWithRadius)
{
  SimulationSettings off = settingsWith (false);
  setEffectEnabled (off.effects, "axial_quadratic", true);
  setEffectParameter (off.effects, "axial_quadratic", "sigma_px", 0.05);
  SimulationSettings on = off;
  setEffectEnabled (on.effects, "radial", true); // gain 0.5 at 400 px

  const auto binnedRatio = [] (const KinectSimulator &sim, bool with_radial) {
    const PixelStats stats (sim.simulate (0, 0, kFrames));
    const DepthSensor &s = sim.sensor (0);
    const double base = 1000.0 * kernels::depthSigmaFromDisparitySigma (0.05, 1.5, s.fb ());
    std::vector<double> measured (9, 0.0), expected (9, 0.0);
    std::vector<int> pixels (9, 0);
    for (int v = 0; v < s.height; ++v)
      for (int u = 0; u < s.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * s.width + u;
        const double r = std::hypot (u - s.cx, v - s.cy);
        const double factor = with_radial ? effects::Radial::factor (sim.settings ().effects.parameters<effects::Radial> (), r) : 1.0;
        const int bin = static_cast<int> (r / 50);
        measured[bin] += stats.var[i] - kRoundingVariance;
        expected[bin] += base * base * factor * factor;
        ++pixels[bin];
      }
    std::vector<double> ratio;
    for (int b = 0; b < 8; ++b)
      ratio.push_back (std::sqrt (measured[b] / expected[b]));
    return std::make_pair (ratio, std::sqrt ((measured[7] / pixels[7]) / (measured[0] / pixels[0])));
  };

  const auto [ratio_on, outer_inner_on] = binnedRatio (simulator (planeSetup (1.5, 0, 0), on), true);
  const auto [ratio_off, outer_inner_off] = binnedRatio (simulator (planeSetup (1.5, 0, 0), off), false);
  for (std::size_t b = 0; b < ratio_on.size (); ++b)
  {
    EXPECT_NEAR (ratio_on[b], 1.0, 0.05) << "radius bin " << b;
    EXPECT_NEAR (ratio_off[b], 1.0, 0.05) << "radius bin " << b;
  }
  // At 350-400 px the factor is 1 + 0.5 (r/400)^2, about 1.44; at 0-50 px about 1.004.
  EXPECT_GT (outer_inner_on, 1.35);
  EXPECT_NEAR (outer_inner_off, 1.0, 0.05);
  std::ostringstream line;
  line << std::setprecision (3) << "radial (gain 0.5 at 400 px): SD at 350-400 px / SD at 0-50 px = " << outer_inner_on
       << " on, " << outer_inner_off << " off";
  signature (line.str ());
}

// ---------------------------------------------------------------------------------------------
// disparity_quantization

namespace
{

/** Share of readings that are f b / (k step) rounded to mm for some integer k. */
double
latticeShare (const std::vector<DepthFrame> &frames, double fb, double step, std::size_t &distinct)
{
  std::size_t on = 0, total = 0;
  std::vector<bool> seen (65536, false);
  for (const auto &f : frames)
    for (const std::uint16_t mm : f.depth_mm)
    {
      if (mm == 0)
        continue;
      ++total;
      seen[mm] = true;
      const double k0 = std::floor (fb / (mm * 1e-3) / step + 0.5);
      for (double k = k0 - 1; k <= k0 + 1; ++k)
        if (std::floor (fb / (k * step) * 1000.0 + 0.5) == mm)
        {
          ++on;
          break;
        }
    }
  distinct = std::count (seen.begin (), seen.end (), true);
  return static_cast<double> (on) / total;
}

} // namespace

TEST (Simulator, DisparityQuantizationPutsDepthsOnTheStepLattice)
{
  SimulationSettings on = settingsWith (true);
  setEffectEnabled (on.effects, "disparity_quantization", true);
  const SceneSetup wall = planeSetup (1.5, 30, 20); // depths from about 1.1 m to 2.5 m
  const KinectSimulator sim_on = simulator (wall, on), sim_off = simulator (wall, settingsWith (true));
  const double fb = sim_on.sensor (0).fb ();
  std::size_t distinct_on, distinct_off;
  const double share_on = latticeShare (sim_on.simulate (0, 0, 5), fb, 0.125, distinct_on);
  const double share_off = latticeShare (sim_off.simulate (0, 0, 5), fb, 0.125, distinct_off);
  EXPECT_EQ (share_on, 1.0);
  EXPECT_LT (share_off, 0.5);
  EXPECT_LT (distinct_on * 3, distinct_off);
  EXPECT_EQ (sim_on.cameraInfo (0).disparity_subpixel, 0.125);

  // The depth step at 1.5 m is z^2 step / (f b), 6.5 mm: a frontal wall reads at most two values
  // apart by one step near the centre (noise 1 mm).
  const KinectSimulator frontal = simulator (planeSetup (1.5, 0, 0), on);
  const DepthFrame f = frontal.simulateFrame (0, 0);
  const double step_mm = 1000.0 * kernels::depthStep (1.5, 0.125, fb);
  std::set<int> centre;
  for (int v = 230; v < 250; ++v)
    for (int u = 310; u < 330; ++u)
      centre.insert (f.depth_mm[v * 640 + u]);
  ASSERT_GE (centre.size (), 1u);
  EXPECT_LE (centre.size (), 3u);
  EXPECT_LE (*centre.rbegin () - *centre.begin (), 2 * step_mm + 1);

  std::ostringstream line;
  line << std::setprecision (3) << "disparity_quantization (1/8 px): on the f b/(k step) lattice " << 100 * share_on
       << " % on, " << 100 * share_off << " % off; distinct depths " << distinct_on << " on, " << distinct_off
       << " off; step at 1.5 m " << step_mm << " mm";
  signature (line.str ());
}

// ---------------------------------------------------------------------------------------------
// incidence_angle

TEST (Simulator, IncidenceAngleRaisesTheSdWithTilt)
{
  SimulationSettings off = settingsWith (false);
  setEffectEnabled (off.effects, "axial_quadratic", true);
  setEffectParameter (off.effects, "axial_quadratic", "sigma_px", 0.05);
  SimulationSettings on = off;
  setEffectEnabled (on.effects, "incidence_angle", true); // gain 0.5

  std::ostringstream line;
  line << std::setprecision (3) << "incidence_angle (gain 0.5): SD on/off in the central 40x40 px at tilt";
  double previous = 0.0;
  for (const double tilt : {0.0, 30.0, 60.0})
  {
    const SceneSetup wall = planeSetup (1.5, 0, tilt);
    const KinectSimulator sim_on = simulator (wall, on), sim_off = simulator (wall, off);
    const PixelStats s_on (sim_on.simulate (0, 0, kFrames)), s_off (sim_off.simulate (0, 0, kFrames));
    const SensorTruth &t = sim_on.truth (0);
    double var_on = 0, var_off = 0, expected = 0;
    int n = 0;
    for (int v = 220; v < 260; ++v)
      for (int u = 300; u < 340; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * 640 + u;
        var_on += s_on.var[i] - kRoundingVariance;
        var_off += s_off.var[i] - kRoundingVariance;
        expected += effects::IncidenceAngle::factor (on.effects.parameters<effects::IncidenceAngle> (), t.cos_incidence[i]);
        ++n;
      }
    const double ratio = std::sqrt (var_on / var_off);
    EXPECT_NEAR (ratio, expected / n, 0.05 * expected / n) << "tilt " << tilt;
    EXPECT_GE (ratio, previous - 0.02);
    previous = ratio;
    line << " " << tilt << " deg: " << ratio << " (expected " << expected / n << ")";
  }
  signature (line.str ());

  // Beyond max_angle_deg the pattern cannot be matched: no reading.
  setEffectParameter (on.effects, "incidence_angle", "max_angle_deg", 50);
  const DepthFrame steep = simulator (planeSetup (1.5, 0, 60), on).simulateFrame (0, 0);
  EXPECT_EQ (steep.depth_mm[240 * 640 + 320], 0);
  const DepthFrame steep_off = simulator (planeSetup (1.5, 0, 60), off).simulateFrame (0, 0);
  EXPECT_GT (steep_off.depth_mm[240 * 640 + 320], 0);
}

// ---------------------------------------------------------------------------------------------
// vertical_stripes

TEST (Simulator, VerticalStripesGiveColumnCorrelatedOffsetsThatChangeOverTime)
{
  SimulationSettings on = settingsWith (true, 5);
  setEffectEnabled (on.effects, "vertical_stripes", true); // 6 bands, 1/8 px, 10 frames
  const SceneSetup wall = planeSetup (1.5, 0, 0);

  const auto measure = [&] (const SimulationSettings &settings, double &along, double &across,
                            std::vector<std::vector<double>> &column_means) {
    const KinectSimulator sim = simulator (wall, settings);
    const auto frames = sim.simulate (0, 0, kFrames);
    const SensorTruth &t = sim.truth (0);
    std::vector<double> a1, a2, c1, c2;
    column_means.assign (kFrames, std::vector<double> (640, 0.0));
    for (int f = 0; f < kFrames; ++f)
    {
      for (int v = 0; v + 20 < 480; v += 4)
        for (int u = 0; u < 640; u += 2)
        {
          a1.push_back (residualMm (frames[f], t, v * 640 + u));
          a2.push_back (residualMm (frames[f], t, (v + 20) * 640 + u));
        }
      // Pairs 5 columns apart straddling each band boundary of this frame's layout.
      const std::uint32_t epoch = effects::VerticalStripes::epoch (on.effects.parameters<effects::VerticalStripes> (), f);
      for (int k = 0; k + 1 < on.effects.parameters<effects::VerticalStripes> ().bands; ++k)
      {
        const int c = effects::VerticalStripes::boundary (settings.seed, 0, epoch, k, 640);
        if (c < 3 || c + 2 >= 640)
          continue;
        for (int v = 0; v < 480; ++v)
        {
          c1.push_back (residualMm (frames[f], t, v * 640 + c - 3));
          c2.push_back (residualMm (frames[f], t, v * 640 + c + 2));
        }
      }
      for (int u = 0; u < 640; ++u)
      {
        for (int v = 0; v < 480; ++v)
          column_means[f][u] += residualMm (frames[f], t, v * 640 + u) / 480.0;
      }
    }
    along = correlation (a1, a2);
    across = correlation (c1, c2);
  };

  double along_on, across_on, along_off, across_off;
  std::vector<std::vector<double>> columns_on, columns_off;
  measure (on, along_on, across_on, columns_on);
  measure (settingsWith (true, 5), along_off, across_off, columns_off);
  EXPECT_GT (along_on, 0.9);
  EXPECT_LT (std::fabs (across_on), 0.5);
  EXPECT_LT (std::fabs (along_off), 0.05);
  // Within one layout (frames 0 and 9) the column profile repeats; a new layout (frame 10, 20)
  // puts the bands elsewhere.
  const double same_layout = correlation (columns_on[0], columns_on[9]);
  const double next_layout = correlation (columns_on[9], columns_on[10]);
  const double later_layout = correlation (columns_on[19], columns_on[20]);
  EXPECT_GT (same_layout, 0.95);
  EXPECT_LT (next_layout, 0.8);
  EXPECT_LT (later_layout, 0.8);
  std::ostringstream line;
  line << std::setprecision (3) << "vertical_stripes (6 bands, 1/8 px, 10 frames): residual correlation along columns "
       << along_on << " on / " << along_off << " off, across band boundaries " << across_on
       << "; column profile frame 0 vs 9 " << same_layout << ", 9 vs 10 " << next_layout << ", 19 vs 20 "
       << later_layout;
  signature (line.str ());
}

// ---------------------------------------------------------------------------------------------
// depth_distortion

TEST (Simulator, DepthDistortionIsAStaticBiasMapGrowingWithDepth)
{
  SimulationSettings on = settingsWith (true, 3);
  setEffectEnabled (on.effects, "depth_distortion", true);

  const auto biasMap = [&] (const SimulationSettings &settings, double z, int first, int count) {
    const KinectSimulator sim = simulator (planeSetup (z, 0, 0), settings);
    const PixelStats stats (sim.simulate (0, first, count));
    std::vector<double> bias (stats.mean.size ());
    for (std::size_t i = 0; i < bias.size (); ++i)
      bias[i] = stats.mean[i] - 1000.0 * z;
    return bias;
  };
  const std::vector<double> b1 = biasMap (on, 1.0, 0, kFrames), b2 = biasMap (on, 2.0, 0, kFrames);
  double s12 = 0, s11 = 0;
  for (std::size_t i = 0; i < b1.size (); ++i)
  {
    s12 += b1[i] * b2[i];
    s11 += b1[i] * b1[i];
  }
  const double slope = s12 / s11;
  EXPECT_NEAR (slope, 4.0, 0.2) << "a disparity offset biases depth by z^2 delta / (f b)";
  EXPECT_GT (correlation (b1, b2), 0.95);

  // The map is what the model predicts, -z^2 delta(u, v) / (f b), and static over time.
  const DepthSensor s = DepthSensor::kinect ();
  const double r_corner = std::hypot (s.cx, s.cy);
  double err2 = 0, rms2 = 0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u)
    {
      const double delta = effects::DepthDistortion::offset (on.effects.parameters<effects::DepthDistortion> (), on.seed, 0, u, v, s.cx, s.cy, r_corner);
      const double predicted = 1000.0 * (s.fb () / (s.fb () / 2.0 + delta) - 2.0);
      err2 += std::pow (b2[v * 640 + u] - predicted, 2);
      rms2 += predicted * predicted;
    }
  const double rms_error = std::sqrt (err2 / b2.size ()), rms_bias = std::sqrt (rms2 / b2.size ());
  EXPECT_LT (rms_error, 0.15 * rms_bias);
  const std::vector<double> early = biasMap (on, 2.0, 0, 15), late = biasMap (on, 2.0, 15, 15);
  const double static_corr = correlation (early, late);
  EXPECT_GT (static_corr, 0.9);

  const std::vector<double> off = biasMap (settingsWith (true, 3), 2.0, 0, kFrames);
  double rms_off = 0;
  for (const double b : off)
    rms_off += b * b;
  rms_off = std::sqrt (rms_off / off.size ());
  EXPECT_LT (rms_off, 0.25 * rms_bias);
  std::ostringstream line;
  line << std::setprecision (3) << "depth_distortion: bias map at 2 m = " << slope
       << " x map at 1 m (z^2: 4); RMS bias at 2 m " << rms_bias << " mm, model error " << rms_error
       << " mm, frames 0-14 vs 15-29 correlation " << static_corr << "; off: RMS " << rms_off << " mm";
  signature (line.str ());
}

// ---------------------------------------------------------------------------------------------
// interference

TEST (Simulator, InterferenceRaisesSdAndDropoutWithTheNumberOfProjectors)
{
  SimulationSettings on = settingsWith (true, 9);
  setEffectEnabled (on.effects, "interference", true);
  std::ostringstream line;
  line << std::setprecision (3) << "interference (noise_gain 1, dropout_rate 0.1): sensor 0 of a wall at 1.5 m,";
  double previous_sd = 0, previous_dropout = -1;
  std::vector<std::uint16_t> single_projector;
  for (int projectors = 1; projectors <= 3; ++projectors)
  {
    const SceneSetup wall = planeSetup (1.5, 0, 0, projectors);
    const KinectSimulator sim = simulator (wall, on);
    const auto frames = sim.simulate (0, 0, kFrames);
    const PixelStats stats (frames);
    const SensorTruth &t = sim.truth (0);
    double var = 0, expected = 0, load = 0;
    std::size_t holes = 0, pixels = 0, n = 0;
    for (std::size_t i = 0; i < stats.var.size (); ++i)
    {
      holes += kFrames - stats.count[i];
      pixels += kFrames;
      if (stats.count[i] > 1)
      {
        var += stats.var[i];
        ++n;
      }
      expected += effects::Interference::dropoutAt (on.effects.parameters<effects::Interference> (), t.foreign_load[i]);
      load += t.foreign_load[i];
    }
    const double sd = std::sqrt (var / n), dropout = static_cast<double> (holes) / pixels;
    EXPECT_NEAR (dropout, expected / stats.var.size (), 0.01);
    EXPECT_GT (sd, previous_sd * (projectors > 1 ? 1.15 : 1.0));
    EXPECT_GT (dropout, previous_dropout + (projectors > 1 ? 0.05 : 0.0));
    if (projectors == 1)
    {
      EXPECT_EQ (dropout, 0.0);
      single_projector = frames[3].depth_mm;
    }
    previous_sd = sd;
    previous_dropout = dropout;
    line << " " << projectors << " projector(s): mean load " << load / stats.var.size () << ", SD " << sd
         << " mm, dropout " << 100 * dropout << " %;";

    if (projectors == 3)
    {
      // Switched off, the other projectors change nothing.
      const KinectSimulator quiet = simulator (wall, settingsWith (true, 9));
      EXPECT_EQ (quiet.simulateFrame (0, 3).depth_mm, single_projector);
    }
  }
  signature (line.str ());
}

// ---------------------------------------------------------------------------------------------
// temporal_drift

TEST (Simulator, TemporalDriftGivesATrendInFrameMeans)
{
  SimulationSettings on = settingsWith (true, 4);
  setEffectEnabled (on.effects, "temporal_drift", true); // 0.2 px, 10 frames
  const auto frameMeans = [&] (const SimulationSettings &settings) {
    const KinectSimulator sim = simulator (planeSetup (1.5, 0, 0), settings);
    std::vector<double> means;
    for (const auto &f : sim.simulate (0, 0, kFrames))
    {
      double sum = 0;
      for (const std::uint16_t mm : f.depth_mm)
        sum += mm - 1500.0;
      means.push_back (sum / f.depth_mm.size ());
    }
    return means;
  };
  const std::vector<double> m_on = frameMeans (on), m_off = frameMeans (settingsWith (true, 4));
  const double fb = DepthSensor::kinect ().fb ();
  std::vector<double> expected, off_abs;
  for (int f = 0; f < kFrames; ++f)
  {
    const double delta = effects::TemporalDrift::frameOffset (on.effects.parameters<effects::TemporalDrift> (), f);
    expected.push_back (1000.0 * (fb / (fb / 1.5 + delta) - 1.5));
    EXPECT_NEAR (m_on[f], expected.back (), 0.1 + 0.02 * std::fabs (expected.back ())) << "frame " << f;
    EXPECT_LT (std::fabs (m_off[f]), 0.05) << "frame " << f;
  }
  EXPECT_GT (correlation (m_on, expected), 0.999);
  std::ostringstream line;
  line << std::setprecision (3) << "temporal_drift (0.2 px, tau 10 frames): frame mean residual " << m_on[0] << " mm (frame 0), "
       << m_on[10] << " (10), " << m_on[29] << " (29), expected " << expected[0] << ", " << expected[10] << ", "
       << expected[29] << "; off: at most " << *std::max_element (m_off.begin (), m_off.end (), [] (double a, double b) {
            return std::fabs (a) < std::fabs (b);
          }) << " mm";
  signature (line.str ());
}

// ---------------------------------------------------------------------------------------------
// lateral_noise

TEST (Simulator, LateralNoiseRaisesTheErrorOnlyNearDepthEdges)
{
  SimulationSettings on = settingsWith (true, 6);
  setEffectEnabled (on.effects, "lateral_noise", true); // 0.8 px
  const SceneSetup box = boxSetup (1.2, 40, 1);
  const KinectSimulator sim_on = simulator (box, on), sim_off = simulator (box, settingsWith (true, 6));
  const auto f_on = sim_on.simulate (0, 0, kFrames), f_off = sim_off.simulate (0, 0, kFrames);
  const SensorTruth &t = sim_on.truth (0);

  // Edge pixels: a depth jump over 2 cm (or a missing surface) within one pixel; far pixels:
  // none within six (a jitter of 0.8 px never reaches that far: 8 SDs).
  const auto jumpWithin = [&] (int u, int v, int radius) {
    for (int dv = -radius; dv <= radius; ++dv)
      for (int du = -radius; du <= radius; ++du)
      {
        const int x = u + du, y = v + dv;
        if (x < 0 || y < 0 || x >= 640 || y >= 480)
          continue;
        const float a = t.depth_m[v * 640 + u], b = t.depth_m[y * 640 + x];
        if ((a > 0) != (b > 0) || std::fabs (a - b) > 0.02)
          return true;
      }
    return false;
  };
  double near_on = 0, near_off = 0, far_on = 0, far_off = 0;
  std::size_t n_near = 0, n_far = 0, far_differ = 0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * 640 + u;
      if (!(t.depth_m[i] > 0) || !t.lit[i])
        continue;
      const bool near = jumpWithin (u, v, 1), far = !jumpWithin (u, v, 6);
      if (!near && !far)
        continue;
      for (int f = 0; f < kFrames; ++f)
      {
        const double e_on = residualMm (f_on[f], t, i), e_off = residualMm (f_off[f], t, i);
        if (std::isnan (e_on) || std::isnan (e_off))
          continue;
        if (near)
        {
          near_on += e_on * e_on;
          near_off += e_off * e_off;
          ++n_near;
        }
        else
        {
          far_on += e_on * e_on;
          far_off += e_off * e_off;
          far_differ += f_on[f].depth_mm[i] != f_off[f].depth_mm[i] ? 1 : 0;
          ++n_far;
        }
      }
    }
  ASSERT_GT (n_near, 1000u);
  ASSERT_GT (n_far, 100000u);
  const double rms_near_on = std::sqrt (near_on / n_near), rms_near_off = std::sqrt (near_off / n_near);
  const double rms_far_on = std::sqrt (far_on / n_far), rms_far_off = std::sqrt (far_off / n_far);
  EXPECT_GT (rms_near_on, 5 * rms_near_off);
  EXPECT_EQ (far_differ, 0u) << "away from edges lateral noise changes nothing";
  EXPECT_LT (rms_near_off, 3 * rms_far_off);
  std::ostringstream line;
  line << std::setprecision (3) << "lateral_noise (0.8 px), box scene: RMS error near depth edges " << rms_near_on
       << " mm on / " << rms_near_off << " mm off; away from edges " << rms_far_on << " / " << rms_far_off << " mm";
  signature (line.str ());
}

// ---------------------------------------------------------------------------------------------
// intrinsics

TEST (Simulator, IntrinsicsMisScaleTheLabelledBackProjection)
{
  SimulationSettings on = settingsWith (false);
  setEffectEnabled (on.effects, "intrinsics", true);
  setEffectParameter (on.effects, "intrinsics", "focal_scale", 1.1);
  setEffectParameter (on.effects, "intrinsics", "cx_offset_px", 4);
  setEffectParameter (on.effects, "intrinsics", "cy_offset_px", -3);
  const SceneSetup wall = planeSetup (1.5, 0, 0);
  const KinectSimulator sim_on = simulator (wall, on), sim_off = simulator (wall, settingsWith (false));
  const DepthSensor &s = sim_on.sensor (0);

  const auto span = [] (const CameraInfo &info, const DepthFrame &f, int u1, int u2, int v) {
    const double z1 = f.depth_mm[v * f.width + u1] * 1e-3, z2 = f.depth_mm[v * f.width + u2] * 1e-3;
    return (u2 - info.cx ()) / info.fx () * z2 - (u1 - info.cx ()) / info.fx () * z1;
  };
  const double truth = (540 - 100) / s.fx * 1.5;
  const CameraInfo label = sim_on.cameraInfo (0), plain = sim_off.cameraInfo (0);
  const double ratio_on = span (label, sim_on.simulateFrame (0, 0), 100, 540, 240) / truth;
  const double ratio_off = span (plain, sim_off.simulateFrame (0, 0), 100, 540, 240) / truth;
  EXPECT_NEAR (ratio_on, 1.0 / 1.1, 1e-3);
  EXPECT_NEAR (ratio_off, 1.0, 1e-3);
  EXPECT_DOUBLE_EQ (label.fx (), 1.1 * s.fx);
  EXPECT_DOUBLE_EQ (label.cx (), s.cx + 4);
  EXPECT_DOUBLE_EQ (label.cy (), s.cy - 3);
  EXPECT_DOUBLE_EQ (plain.fx (), s.fx);
  // The optical axis pixel lands 4 px off the labelled principal point: x = -4 / fx' z.
  const DepthFrame f = sim_on.simulateFrame (0, 0);
  const double x_axis = (s.cx - label.cx ()) / label.fx () * f.depth_mm[240 * 640 + 320] * 1e-3;
  EXPECT_NEAR (x_axis, -4.0 / label.fx () * 1.5, 1e-4);
  // Depths are untouched.
  EXPECT_EQ (f.depth_mm, sim_off.simulateFrame (0, 0).depth_mm);
  std::ostringstream line;
  line << std::setprecision (5) << "intrinsics (focal_scale 1.1): labelled span / true span = " << ratio_on
       << " (expected " << 1.0 / 1.1 << "), off " << ratio_off;
  signature (line.str ());
}

// ---------------------------------------------------------------------------------------------
// Geometry the sensor cannot avoid: its own projector's shadow.

TEST (Simulator, ProjectorShadowsLeaveHolesBesideTheBox)
{
  const SceneSetup box = boxSetup (1.2, 40, 1);
  SimulationSettings with = settingsWith (false), without = settingsWith (false);
  without.projector_shadows = false;
  const KinectSimulator a = simulator (box, with), b = simulator (box, without);
  const SensorTruth &t = a.truth (0);
  std::size_t shadowed = 0, surface = 0;
  for (std::size_t i = 0; i < t.depth_m.size (); ++i)
    if (t.depth_m[i] > 0)
    {
      ++surface;
      shadowed += t.lit[i] ? 0 : 1;
    }
  const DepthFrame fa = a.simulateFrame (0, 0), fb = b.simulateFrame (0, 0);
  std::size_t holes_a = 0, holes_b = 0;
  for (std::size_t i = 0; i < t.depth_m.size (); ++i)
    if (t.depth_m[i] > 0)
    {
      holes_a += fa.depth_mm[i] == 0;
      holes_b += fb.depth_mm[i] == 0;
    }
  EXPECT_GT (shadowed, 100u);
  EXPECT_LT (shadowed, surface / 10);
  EXPECT_EQ (holes_a, shadowed);
  EXPECT_EQ (holes_b, 0u);
}

// ---------------------------------------------------------------------------------------------
// Determinism and recordings.

TEST (Simulator, SameSeedSameBytesWhateverTheThreads)
{
  SimulationSettings s = settingsWith (true, 77);
  for (const char *name : {"disparity_quantization", "vertical_stripes", "interference", "lateral_noise",
                           "depth_distortion", "temporal_drift", "radial", "incidence_angle"})
    setEffectEnabled (s.effects, name, true);
  const SceneSetup box = boxSetup (1.3, 35, 3);
  const auto sensors = box.sensors (DepthSensor::kinect (320, 240));
  const KinectSimulator one (box.scene, sensors, s, 1), two (box.scene, sensors, s, 2);
  for (std::size_t sensor = 0; sensor < 3; ++sensor)
  {
    const auto a = one.simulate (sensor, 0, 6), b = two.simulate (sensor, 0, 6);
    for (int f = 0; f < 6; ++f)
    {
      EXPECT_EQ (a[f].depth_mm, b[f].depth_mm) << "sensor " << sensor << " frame " << f;
      EXPECT_EQ (a[f].depth_mm, two.simulateFrame (sensor, f).depth_mm) << "one frame alone, threads over rows";
    }
  }
  const KinectSimulator again (box.scene, sensors, s, 2);
  EXPECT_EQ (again.simulateFrame (1, 4).depth_mm, one.simulateFrame (1, 4).depth_mm);
  s.seed = 78;
  const KinectSimulator other (box.scene, sensors, s, 2);
  EXPECT_NE (other.simulateFrame (1, 4).depth_mm, one.simulateFrame (1, 4).depth_mm);
}

TEST_F (SimulatorFiles, WrittenRecordingReadsBackAsSimulated)
{
  SimulationSettings s = settingsWith (true, 7);
  setEffectEnabled (s.effects, "vertical_stripes", true);
  setEffectEnabled (s.effects, "disparity_quantization", true);
  setEffectEnabled (s.effects, "intrinsics", true);
  const SceneSetup box = boxSetup (1.3, 35, 3);
  const KinectSimulator sim (box.scene, box.sensors (DepthSensor::kinect ()), s);
  const fs::path folder = dir_ / "rec";
  writeSimulatedRecording (sim, box, 1, 0, 8, folder.string ());

  RecordingFolderReader reader (folder.string ());
  ASSERT_EQ (reader.size (), 8u);
  const CameraInfo expected = sim.cameraInfo (1);
  EXPECT_EQ (reader.cameraInfo ().width, 640);
  for (int k = 0; k < 9; ++k)
    EXPECT_DOUBLE_EQ (reader.cameraInfo ().K[k], expected.K[k]);
  EXPECT_DOUBLE_EQ (reader.cameraInfo ().baseline_m, 0.075);
  EXPECT_DOUBLE_EQ (reader.cameraInfo ().disparity_subpixel, 0.125);
  const auto frames = sim.simulate (1, 0, 8);
  DepthFrame f;
  for (int k = 0; k < 8; ++k)
  {
    ASSERT_TRUE (reader.next (f));
    EXPECT_EQ (f.name, frames[k].name);
    EXPECT_EQ (f.depth_mm, frames[k].depth_mm) << "frame " << k;
  }
  EXPECT_FALSE (reader.next (f));

  // meta.yaml: scene, projectors, box size, the active effects with their parameters; and it
  // configures the same effects when read back.
  std::ifstream meta_file (folder / "meta.yaml");
  std::stringstream meta;
  meta << meta_file.rdbuf ();
  const std::string text = meta.str ();
  for (const char *needle : {"scene: box", "projectors: 3", "sensor: 1", "box_size_m: [0.128, 0.112, 0.24]",
                             "vertical_stripes: {bands: 6, offset_px: 0.125, period_frames: 10}",
                             "disparity_quantization: {step_px: 0.125}", "intrinsics: {focal_scale: 1.088",
                             "base_noise: paper", "seed: 7", "frames: 8"})
    EXPECT_NE (text.find (needle), std::string::npos) << needle << "\n" << text;
  EXPECT_EQ (text.find ("lateral_noise"), std::string::npos) << "only active effects are listed";
  SimulationSettings reread = settingsWith (false);
  loadSimulationConfig ((folder / "meta.yaml").string (), reread);
  EXPECT_EQ (enabledEffects (reread.effects), enabledEffects (s.effects));
  EXPECT_TRUE (reread.base_noise);
  EXPECT_EQ (temp_.entries (), std::vector<std::string> ({"rec"})) << "no temporary folder is left";
}

TEST_F (SimulatorFiles, AFailedWriteLeavesNoRecording)
{
  const SceneSetup wall = planeSetup (1.5, 0, 0);
  const KinectSimulator sim (wall.scene, wall.sensors (DepthSensor::kinect (160, 120)), settingsWith (true));
  // An existing destination is never written over.
  fs::create_directories (dir_ / "taken");
  EXPECT_THROW (writeSimulatedRecording (sim, wall, 0, 0, 3, (dir_ / "taken").string ()), pcl::IOException);
  EXPECT_TRUE (fs::is_empty (dir_ / "taken"));
  // A frame that fails midway (wrong size) aborts the recording and removes what was written.
  {
    RecordingFolderWriter writer ((dir_ / "broken").string (), sim.cameraInfo (0));
    writer.writeFrame (sim.simulateFrame (0, 0));
    EXPECT_TRUE (fs::exists (fs::path (writer.temporaryFolder ()) / "depth" / "000000.png"));
    DepthFrame wrong = sim.simulateFrame (0, 1);
    wrong.width = 80;
    EXPECT_THROW (writer.writeFrame (wrong), pcl::BadArgumentException);
  }
  EXPECT_FALSE (fs::exists (dir_ / "broken"));
  EXPECT_EQ (temp_.entries (), std::vector<std::string> ({"taken"})) << "no temporary folder is left";
  // A missing parent folder is reported before anything is made.
  try
  {
    writeSimulatedRecording (sim, wall, 0, 0, 3, (dir_ / "no" / "such" / "rec").string ());
    FAIL () << "expected an IOException";
  }
  catch (const pcl::IOException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("does not exist"), std::string::npos) << e.what ();
  }
  EXPECT_EQ (temp_.entries (), std::vector<std::string> ({"taken"}));
}
