/*
 * The model lab's proof (issue: "watch the error fall"): plane recordings simulated with one
 * hidden physical effect on top of the paper's base noise; the lab, started from the paper's
 * model and not told the effect, must rank it first and significant, and adding it must halve
 * the error where it shows. With no hidden effect, no candidate may be significant.
 */
#include "support/lab_proof.h"

#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/noise/noise_terms.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <sstream>

using namespace pcl::texlet;

namespace
{

int
imageWidth ()
{
  const char *w = std::getenv ("PCL_TEXLET_LAB_TEST_WIDTH");
  return w ? std::atoi (w) : 320;
}

/** Five plane recordings (0.8 to 3 m, 30 frames) with \a effects switched on (none: the paper's base noise);
  * \a stripe_period: frames one layout of vertical stripes lasts (0: the effect's default, 10).
  */
std::vector<lab::RecordingMeasurement::ConstPtr>
simulatePlanes (const std::vector<std::string> &effects, std::uint32_t seed, int stripe_period = 0)
{
  auto has = [&] (const char *name) { return std::find (effects.begin (), effects.end (), name) != effects.end (); };
  const int W = imageWidth (), H = W * 3 / 4;
  const double distances[5] = {0.8, 1.35, 1.9, 2.45, 3.0};
  // Mild tilts spread the disparity's sub-step phase over the image; the angle case goes to 70.
  double tilt_y[5] = {12, -18, 24, -14, 20}, tilt_x[5] = {6, -4, 8, -6, 4};
  int projectors[5] = {1, 1, 1, 1, 1};
  if (has ("incidence_angle"))
  {
    const double t[5] = {0, 30, 50, 60, 70};
    for (int k = 0; k < 5; ++k)
      tilt_y[k] = t[k], tilt_x[k] = 0;
  }
  if (has ("interference"))
  {
    const int p[5] = {1, 2, 3, 2, 3};
    for (int k = 0; k < 5; ++k)
      projectors[k] = p[k];
  }
  std::vector<lab::RecordingMeasurement::ConstPtr> out;
  for (int k = 0; k < 5; ++k)
  {
    const sim::SceneSetup setup = sim::planeSetup (distances[k], tilt_x[k], tilt_y[k], projectors[k]);
    sim::SimulationSettings settings;
    settings.seed = seed + 101 * k;
    std::uint32_t first_frame = 0;
    for (const auto &effect : effects)
      sim::setEffectEnabled (settings.effects, effect, true);
    if (has ("depth_distortion"))
    {
      // One sensor's distortion is the same in every recording: one seed, other frame numbers.
      settings.seed = seed;
      first_frame = 1000 * k;
    }
    if (has ("vertical_stripes") && stripe_period > 0)
      sim::setEffectParameter (settings.effects, "vertical_stripes", "period_frames", stripe_period);
    sim::KinectSimulator simulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (W, H)), settings);
    const auto frames = simulator.simulate (0, first_frame, 30);
    std::ostringstream meta;
    meta << "scene: plane\nprojectors: " << simulator.activeProjectors () << "\n";
    out.push_back (lab::measureFrames (frames, simulator.cameraInfo (0), "plane_" + std::to_string (k), meta.str ()));
  }
  return out;
}

/** The lab's proof on the simulator's planes with \a effect hidden (test/support/lab_proof.h). */
void
expectFound (const std::string &effect, bool shows_in_bias, std::uint32_t seed, int stripe_period = 0,
             double max_ratio = 0.5)
{
  pcl_texlet_test::expectFoundIn (simulatePlanes ({effect}, seed, stripe_period), effect, shows_in_bias, max_ratio);
}

} // namespace

TEST (ModelLabProof, FindsDisparityQuantization) { expectFound ("disparity_quantization", false, 11); }
// At the default period (a new layout every 10 frames) each column shows 3 layouts in 30 frames:
// its measured temporal SD rests on 3 draws of a band offset, which no model can predict pixel
// by pixel. Even the best constant prediction per recording, knowing the simulated truth, leaves
// about 0.52 of the paper's sd_rmse (docs/model_lab.md section 7), so halving is out of reach
// there; the lab must still find the stripes and make the error fall.
TEST (ModelLabProof, FindsVerticalStripes) { expectFound ("vertical_stripes", false, 12, 0, 0.75); }
// With a new layout every 2 frames (15 layouts) the per-pixel SD is predictable: the issue's
// criterion, the error halves.
TEST (ModelLabProof, FindsVerticalStripesHalvingTheErrorWithFastLayouts)
{
  expectFound ("vertical_stripes", false, 12, 2);
}
TEST (ModelLabProof, FindsIncidenceAngle) { expectFound ("incidence_angle", false, 13); }
TEST (ModelLabProof, FindsDepthDistortion) { expectFound ("depth_distortion", true, 14); }
TEST (ModelLabProof, FindsInterference) { expectFound ("interference", false, 15); }
TEST (ModelLabProof, FindsTemporalDrift) { expectFound ("temporal_drift", false, 16); }

TEST (ModelLabProof, NothingSignificantWithoutAHiddenEffect)
{
  pcl_texlet_test::expectNothingSignificantIn (simulatePlanes ({}, 17));
}

