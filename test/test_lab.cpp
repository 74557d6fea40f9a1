/*
 * The model lab's proof (issue: "watch the error fall"): plane recordings simulated with one
 * hidden physical effect on top of the paper's base noise; the lab, started from the paper's
 * model and not told the effect, must rank it first and significant, and adding it must halve
 * the error where it shows. With no hidden effect, no candidate may be significant.
 */
#include "support/lab_proof.h"
#include "support/simulated_walls.h"

#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>

using namespace pcl::texlet;

namespace
{

int
imageWidth ()
{
  const char *w = std::getenv ("PCL_TEXLET_LAB_TEST_WIDTH");
  return w ? std::atoi (w) : 320;
}

/** Five plane recordings (0.8 to 3 m, 30 frames) with \a effects switched on (none: the paper's
  * base noise); \a stripe_period: frames one layout of vertical stripes lasts (0: the effect's
  * default, 10).
  */
std::vector<lab::RecordingMeasurement::ConstPtr>
simulatePlanes (const std::vector<std::string> &effects, std::uint32_t seed, int stripe_period = 0)
{
  auto hidden = [&] (const char *name) { return std::find (effects.begin (), effects.end (), name) != effects.end (); };
  const double distances[5] = {0.8, 1.35, 1.9, 2.45, 3.0};
  // Mild tilts spread the disparity's sub-step phase over the image; the angle case goes to 70.
  const double tilt_y[5] = {12, -18, 24, -14, 20}, tilt_x[5] = {6, -4, 8, -6, 4};
  const double steep_y[5] = {0, 30, 50, 60, 70};
  const int varied_projectors[5] = {1, 2, 3, 2, 3};
  std::vector<pcl_texlet_test::WallPose> poses (5);
  for (int k = 0; k < 5; ++k)
  {
    poses[k] = {distances[k], tilt_x[k], tilt_y[k], 1};
    if (hidden ("incidence_angle"))
      poses[k].tilt_x_deg = 0, poses[k].tilt_y_deg = steep_y[k];
    if (hidden ("interference"))
      poses[k].projectors = varied_projectors[k];
  }
  return pcl_texlet_test::simulatedWalls (poses, effects, seed, 30, imageWidth (), stripe_period);
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

// Quantisation and the sensor's distortion at once: the distortion moves the sub-step phase the
// rounding sees (docs/model_lab.md section 7).
TEST (ModelLabProof, FindsQuantisationAndDistortionTogether)
{
  pcl_texlet_test::expectBothFoundIn (simulatePlanes ({"disparity_quantization", "depth_distortion"}, 18),
                                      {"disparity_quantization", "depth_distortion"});
}
TEST (ModelLabProof, NothingSignificantWithoutAHiddenEffect)
{
  pcl_texlet_test::expectNothingSignificantIn (simulatePlanes ({}, 17));
}

