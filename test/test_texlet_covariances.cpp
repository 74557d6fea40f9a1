/*
 * Honest texlet covariances at the extractor's default settings (automatic RANSAC threshold,
 * P on the centre ray), measured as a user would: texlets of every frame of a static wall
 * recording, grouped by centre pixel, each frame's P and N against their mean over the frames,
 * in that frame's Sigma_P and Sigma_N (lab::texletConsistency: median NEES over its ideal median,
 * 1 when honest). On walls of the project's simulator and of the independent generator
 * (test/generators/independent_walls.py: noise drawn in depth, whole millimetres), whose noise
 * the paper's model describes, both propagations must be honest to 30 %; the paper's own
 * definition of P (the inliers' mean) must not be, as it moves with the inlier set. On walls
 * with column stripes (both generators), with the model the lab fits to them, Sigma_P holds the
 * offsets the disc's columns share to 50 %, and on walls with row bands (the generator) with the
 * data-driven term `rows`, those its rows share.
 */
#include "support/generated_walls.h"
#include "support/simulated_walls.h"

#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/lab/texlet_consistency.h>

#include <gtest/gtest.h>

#include <iostream>

using namespace pcl::texlet;
using pcl_texlet_test::WallPose;

namespace
{

/** Five walls from 0.8 to 3 m with mild tilts, as the lab's texlet tests. */
std::vector<WallPose>
walls ()
{
  return {{0.8, 6, 12}, {1.35, -4, -18}, {1.9, 8, 24}, {2.45, -6, -14}, {3.0, 4, 20}};
}

lab::TexletConsistency
atDefaults (const std::vector<lab::RecordingMeasurement::ConstPtr> &recs, UncertaintyMethod method,
            TexletCentre centre, const std::string &what)
{
  lab::TexletConsistencySettings s;
  s.ransac_threshold_m = 0; // TexletEstimation's default: 3 depth SDs of the model
  s.uncertainty = method;
  s.centre = centre;
  const lab::TexletConsistency c = lab::texletConsistency (recs, NoiseModel::paper (), s);
  std::cout << what << ", " << toString (method) << ", centre " << toString (centre) << ": median NEES ratio P "
            << c.medianRatioP () << " N " << c.medianRatioN () << ", mean NEES ratio P " << c.ratioP () << " N "
            << c.ratioN () << " (" << c.texlets << " centres, " << c.samples << " texlets)\n";
  return c;
}

void
expectHonest (const std::vector<lab::RecordingMeasurement::ConstPtr> &recs, const std::string &what)
{
  for (const UncertaintyMethod method : {UncertaintyMethod::Analytic, UncertaintyMethod::MonteCarlo})
  {
    const lab::TexletConsistency c = atDefaults (recs, method, TexletCentre::CentreRay, what);
    ASSERT_GT (c.texlets, 3000) << what;
    EXPECT_NEAR (c.medianRatioP (), 1.0, 0.3) << what << ", " << toString (method);
    EXPECT_NEAR (c.medianRatioN (), 1.0, 0.3) << what << ", " << toString (method);
  }
  // The paper's P moves sideways with the inlier set, which Sigma_P does not hold: where a
  // point drops out, its NEES jumps (the median hardly shows it, the mean does).
  const lab::TexletConsistency mean = atDefaults (recs, UncertaintyMethod::Analytic, TexletCentre::InlierMean, what);
  EXPECT_GT (mean.ratioP (), 30.0) << what;
}

} // namespace

TEST (TexletCovariances, HonestAtDefaultSettingsOnSimulatedWalls)
{
  expectHonest (pcl_texlet_test::simulatedWalls (walls (), {}, 21, 30, 320), "simulator walls");
}

TEST (TexletCovariances, HonestAtDefaultSettingsOnGeneratedWalls)
{
  expectHonest (pcl_texlet_test::generatedWalls (walls (), {}, 731, 30, 320), "generator walls");
}

namespace
{

/** Texlet NEES on banded walls with the model the lab fits to them (the paper's plus \a term:
  * vertical_stripes or rows), whose column (row) offsets the disc shares
  * (Neighbourhood::shared_fraction).
  */
void
expectBandsInSigmaP (const std::vector<lab::RecordingMeasurement::ConstPtr> &recs, const std::string &what,
                     const std::string &term = "vertical_stripes")
{
  lab::ModelLab lab;
  for (const auto &r : recs)
    lab.addRecording (r);
  const NoiseModel model = lab.addEffect (NoiseModel::paper (), term);
  for (const UncertaintyMethod method : {UncertaintyMethod::Analytic, UncertaintyMethod::MonteCarlo})
  {
    lab::TexletConsistencySettings s;
    s.uncertainty = method;
    const lab::TexletConsistency c = lab::texletConsistency (recs, model, s);
    std::cout << what << " + the lab's " << term << ", " << toString (method) << ": median NEES ratio P "
              << c.medianRatioP () << " N " << c.medianRatioN () << ", mean NEES ratio P " << c.ratioP () << " N "
              << c.ratioN () << " (" << c.texlets << " centres)\n";
    ASSERT_GT (c.texlets, 3000) << what;
    EXPECT_NEAR (c.medianRatioP (), 1.0, 0.5) << what << ", " << toString (method);
    EXPECT_NEAR (c.ratioP (), 1.0, 0.5) << what << ", " << toString (method);
    // N: a band boundary crosses the disc in some frames and tilts the texlet; Sigma_N holds it
    // on average over the layouts (columns correlated by exp(-du / L)), so the NEES is a mixture:
    // below its ideal in most frames, far above it in the few with a boundary (figures:
    // docs/texlet_covariances.md, section 6).
    EXPECT_LT (c.medianRatioN (), 1.0) << what << ", " << toString (method);
    EXPECT_LT (c.ratioN (), 10.0) << what << ", " << toString (method);
  }
}

} // namespace

TEST (TexletCovariances, StripesReachSigmaPOnSimulatedWalls)
{
  expectBandsInSigmaP (pcl_texlet_test::simulatedWalls (walls (), {"vertical_stripes"}, 22, 30, 320, 2),
                       "simulator walls with stripes");
}

TEST (TexletCovariances, StripesReachSigmaPOnGeneratedWalls)
{
  expectBandsInSigmaP (pcl_texlet_test::generatedWalls (walls (), {"vertical_stripes"}, 733, 30, 320),
                       "generator walls with stripes");
}

// The rows' counterpart: horizontal bands and the data-driven term `rows`, shared along rows.
TEST (TexletCovariances, RowBandsReachSigmaPOnGeneratedWalls)
{
  expectBandsInSigmaP (pcl_texlet_test::generatedWalls (walls (), {"row_bands"}, 739, 30, 320),
                       "generator walls with row bands", "rows");
}

// Noise shared over a window smaller than the disc (the generator's `correlated`: the paper's SD,
// its white noise averaged over 9 x 9 pixels): with the term spatial_correlation as the lab fits it
// to the residuals, the disc's points correlate by their windows' overlap (kernels/shared_noise.h)
// and both covariances hold it to 30 %; with the paper's model N is far too confident.
TEST (TexletCovariances, WindowCorrelationInSigmaOnGeneratedWalls)
{
  const auto recs = pcl_texlet_test::generatedWalls (walls (), {"correlated"}, 743, 30, 320);
  lab::ModelLab lab;
  for (const auto &r : recs)
    lab.addRecording (r);
  const NoiseModel model = lab.addEffect (NoiseModel::paper (), "spatial_correlation");
  const std::vector<double> p = model.find ("spatial_correlation")->parameters ();
  std::cout << "the lab's spatial_correlation: share " << p[0] << ", window " << p[1] << " px\n";
  for (const UncertaintyMethod method : {UncertaintyMethod::Analytic, UncertaintyMethod::MonteCarlo})
  {
    lab::TexletConsistencySettings s;
    s.uncertainty = method;
    for (const bool with_window : {false, true})
    {
      if (!with_window && method == UncertaintyMethod::MonteCarlo)
        continue; // the paper's model: analytic alone shows the over-confidence
      const lab::TexletConsistency c = lab::texletConsistency (recs, with_window ? model : NoiseModel::paper (), s);
      std::cout << "generator walls with 9 x 9 correlated noise, " << (with_window ? "+ the lab's spatial_correlation" : "paper")
                << ", " << toString (method) << ": median NEES ratio P " << c.medianRatioP () << " N "
                << c.medianRatioN () << ", mean NEES ratio P " << c.ratioP () << " N " << c.ratioN () << " ("
                << c.texlets << " centres)\n";
      ASSERT_GT (c.texlets, 3000);
      if (with_window)
      {
        EXPECT_NEAR (c.medianRatioP (), 1.0, 0.3) << toString (method);
        EXPECT_NEAR (c.medianRatioN (), 1.0, 0.3) << toString (method);
      }
      else
        EXPECT_GT (c.medianRatioN (), 5.0) << toString (method);
    }
  }
}
