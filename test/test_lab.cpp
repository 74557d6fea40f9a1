/*
 * The model lab's proof (issue: "watch the error fall"): plane recordings simulated with one
 * hidden physical effect on top of the paper's base noise; the lab, started from the paper's
 * model and not told the effect, must rank it first and significant, and adding it must halve
 * the error where it shows. With no hidden effect, no candidate may be significant.
 */
#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/noise/noise_terms.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <gtest/gtest.h>

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

/** Five plane recordings (0.8 to 3 m, 30 frames) with effect \a effect switched on ("" for none);
  * \a stripe_period: frames one layout of vertical stripes lasts (0: the effect's default, 10).
  */
std::vector<lab::RecordingMeasurement::ConstPtr>
simulatePlanes (const std::string &effect, std::uint32_t seed, int stripe_period = 0)
{
  const int W = imageWidth (), H = W * 3 / 4;
  const double distances[5] = {0.8, 1.35, 1.9, 2.45, 3.0};
  // Mild tilts spread the disparity's sub-step phase over the image; the angle case goes to 70.
  double tilt_y[5] = {12, -18, 24, -14, 20}, tilt_x[5] = {6, -4, 8, -6, 4};
  int projectors[5] = {1, 1, 1, 1, 1};
  if (effect == "incidence_angle")
  {
    const double t[5] = {0, 30, 50, 60, 70};
    for (int k = 0; k < 5; ++k)
      tilt_y[k] = t[k], tilt_x[k] = 0;
  }
  if (effect == "interference")
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
    if (!effect.empty ())
      sim::setEffectEnabled (settings.effects, effect, true);
    if (effect == "depth_distortion")
    {
      // One sensor's distortion is the same in every recording: one seed, other frame numbers.
      settings.seed = seed;
      first_frame = 1000 * k;
    }
    if (effect == "vertical_stripes" && stripe_period > 0)
      sim::setEffectParameter (settings.effects, "vertical_stripes", "period_frames", stripe_period);
    sim::KinectSimulator simulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (W, H)), settings);
    const auto frames = simulator.simulate (0, first_frame, 30);
    std::ostringstream meta;
    meta << "scene: plane\nprojectors: " << simulator.activeProjectors () << "\n";
    out.push_back (lab::measureFrames (frames, simulator.cameraInfo (0), "plane_" + std::to_string (k), meta.str ()));
  }
  return out;
}

struct LabRun
{
  lab::LabMetrics before, after;
  std::vector<lab::Candidate> candidates;
};

LabRun
runLab (const std::string &effect, std::uint32_t seed, int stripe_period = 0)
{
  lab::LabSettings settings;
  lab::ModelLab lab (settings);
  for (const auto &r : simulatePlanes (effect, seed, stripe_period))
    lab.addRecording (r);
  LabRun run;
  const NoiseModel paper = NoiseModel::paper ();
  run.before = lab.evaluate (paper);
  run.candidates = lab.rankCandidates (paper);
  std::cout << "hidden effect: " << (effect.empty () ? "none" : effect) << "\n";
  std::cout << "  start: sd_rmse " << run.before.sd_rmse_mm << " bias_rmse " << run.before.bias_rmse_mm << " nll "
            << run.before.nll << "\n";
  for (const auto &c : run.candidates)
    std::cout << "  " << c.effect << ": gain " << c.gain << " (" << c.total_gain << " nats in all) threshold " << c.threshold << " (null " << c.null_mean
              << " +- " << c.null_sd << ")" << (c.significant ? " significant" : "") << " sd_rmse "
              << c.metrics.sd_rmse_mm << " bias_rmse " << c.metrics.bias_rmse_mm << "\n";

  if (!effect.empty ())
  {
    const NoiseModel added = lab.addEffect (paper, run.candidates.front ().effect);
    run.after = lab.evaluate (added);
    std::cout << "  after adding " << run.candidates.front ().effect << ": sd_rmse " << run.after.sd_rmse_mm
              << " bias_rmse " << run.after.bias_rmse_mm << " nll " << run.after.nll << "\n";
  }
  return run;
}

/** The hidden \a effect must be ranked first and significant, and adding it must bring the error
  * where it shows to at most \a max_ratio of the paper's (the issue: at least half).
  */
void
expectFound (const std::string &effect, bool shows_in_bias, std::uint32_t seed, int stripe_period = 0,
             double max_ratio = 0.5)
{
  const LabRun run = runLab (effect, seed, stripe_period);
  ASSERT_FALSE (run.candidates.empty ());
  EXPECT_EQ (run.candidates.front ().effect, effect);
  EXPECT_TRUE (run.candidates.front ().significant);
  const double before = shows_in_bias ? run.before.bias_rmse_mm : run.before.sd_rmse_mm;
  const double after = shows_in_bias ? run.after.bias_rmse_mm : run.after.sd_rmse_mm;
  EXPECT_LE (after, max_ratio * before) << (shows_in_bias ? "bias_rmse_mm" : "sd_rmse_mm");
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
  const LabRun run = runLab ("", 17);
  for (const auto &c : run.candidates)
    EXPECT_FALSE (c.significant) << c.effect << " gain " << c.gain << " threshold " << c.threshold;
}

