/*
 * The model lab at texlet level (issue 4, "Compare"): the NEES of texlet P and N across frames
 * against the texlets' own covariances. On plane recordings with the paper's base noise only,
 * texlets from the paper's model must be calibrated (mean NEES near its expectation); with a
 * hidden effect that adds variance the paper's texlets must be over-confident, and adding the
 * effect (fitted by the lab) must bring the NEES down.
 */
#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/lab/texlet_consistency.h>
#include <pcl_texlet/noise/noise_terms.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <gtest/gtest.h>

#include <pcl_texlet/noise/effect_adapter.h>
#include <pcl_texlet/noise/effects/incidence_angle.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/exceptions.h>

#include <cmath>

#include <iostream>
#include <sstream>

using namespace pcl::texlet;

namespace
{

/** Five plane recordings at 320 x 240 (0.8 to 3 m, mild tilts, 30 frames), \a effect on ("" none). */
std::vector<lab::RecordingMeasurement::ConstPtr>
simulatePlanes (const std::string &effect, std::uint32_t seed)
{
  const int W = 320, H = 240;
  const double distances[5] = {0.8, 1.35, 1.9, 2.45, 3.0};
  double tilt_y[5] = {12, -18, 24, -14, 20}, tilt_x[5] = {6, -4, 8, -6, 4};
  if (effect == "incidence_angle")
  {
    // As in test_lab.cpp: the angle effect needs steep walls.
    const double t[5] = {0, 30, 50, 60, 70};
    for (int k = 0; k < 5; ++k)
      tilt_y[k] = t[k], tilt_x[k] = 0;
  }
  std::vector<lab::RecordingMeasurement::ConstPtr> out;
  for (int k = 0; k < 5; ++k)
  {
    const sim::SceneSetup setup = sim::planeSetup (distances[k], tilt_x[k], tilt_y[k], 1);
    sim::SimulationSettings settings;
    settings.seed = seed + 101 * k;
    if (!effect.empty ())
      sim::setEffectEnabled (settings.effects, effect, true);
    if (effect == "vertical_stripes")
      sim::setEffectParameter (settings.effects, "vertical_stripes", "period_frames", 2); // as in test_lab.cpp
    sim::KinectSimulator simulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (W, H)), settings);
    const auto frames = simulator.simulate (0, 0, 30);
    out.push_back (lab::measureFrames (frames, simulator.cameraInfo (0), "plane_" + std::to_string (k),
                                       "scene: plane\nprojectors: 1\n"));
  }
  return out;
}

void
print (const std::string &what, const lab::TexletConsistency &c)
{
  std::cout << what << ": nees_p " << c.nees_p << " (ideal " << c.ideal_p << ", ratio " << c.ratioP () << ") nees_n "
            << c.nees_n << " (ideal " << c.ideal_n << ", ratio " << c.ratioN () << ") nees_p_normal " << c.nees_p_normal
            << " (ratio " << c.ratioPNormal () << ") median ratio P " << c.medianRatioP () << " N " << c.medianRatioN () << " texlets " << c.texlets
            << " samples " << c.samples << "\n";
}

} // namespace

TEST (ModelLabTexlets, PaperModelIsCalibratedOnPaperNoise)
{
  const auto recs = simulatePlanes ("", 21);
  const lab::TexletConsistency c = lab::texletConsistency (recs, NoiseModel::paper ());
  print ("paper noise, paper model", c);
  // 5 recordings x (320 / 10 spacing) hexagonal centres, every one valid in the 15 frames.
  ASSERT_GT (c.texlets, 4000);
  // 15 frames per centre: the ideal is 1 * 14 / 15 (P on its centre ray: Sigma_P has rank 1) and
  // 2 * 14 / 15 (the mean is estimated).
  EXPECT_NEAR (c.ideal_p, 1.0 * 14 / 15, 1e-9);
  EXPECT_NEAR (c.ideal_n, 2.0 * 14 / 15, 1e-9);
  // Measured 1.135 (P) and 1.124 (N): the texlets are calibrated to about 13 %. The excess is
  // what the model leaves out of the simulated sensor (whole-millimetre depth, noise drawn in
  // disparity) and the first-order propagation; 25 % leaves room for that, not for a model off
  // by a factor (the hidden-effect test below is off by 1.2 to 4000).
  EXPECT_NEAR (c.ratioP (), 1.0, 0.25);
  EXPECT_NEAR (c.ratioN (), 1.0, 0.25);
  EXPECT_NEAR (c.ratioPNormal (), 1.0, 0.25);
  EXPECT_NEAR (c.medianRatioP (), 1.0, 0.25); // measured 1.117
  EXPECT_NEAR (c.medianRatioN (), 1.0, 0.25); // measured 1.109

  // With TexletEstimation's automatic RANSAC threshold a point drops out now and then. P on the
  // centre ray does not move with it (measured 1.15); the inliers' mean, the paper's P, moves
  // sideways, where its Sigma_P is tiny: its mean NEES is then over a hundred times its ideal
  // (N is hardly affected).
  lab::TexletConsistencySettings ransac;
  ransac.ransac_threshold_m = 0;
  const lab::TexletConsistency r = lab::texletConsistency (recs, NoiseModel::paper (), ransac);
  print ("paper noise, paper model, automatic RANSAC threshold", r);
  EXPECT_NEAR (r.ratioP (), 1.0, 0.35);
  EXPECT_NEAR (r.ratioN (), 1.0, 0.4);
  ransac.centre = TexletCentre::InlierMean;
  const lab::TexletConsistency m = lab::texletConsistency (recs, NoiseModel::paper (), ransac);
  print ("paper noise, paper model, automatic RANSAC threshold, P the inliers' mean", m);
  EXPECT_GT (m.ratioP (), 30.0);
  EXPECT_NEAR (m.ratioN (), 1.0, 0.4);

  // The lab's score half: the odd frames only (15 of the 30), evenly spaced over them.
  lab::TexletConsistencySettings odd;
  odd.max_frames = 20;
  odd.frame_parity = 1;
  const lab::TexletConsistency o = lab::texletConsistency (recs, NoiseModel::paper (), odd);
  odd.frame_parity = -1;
  const lab::TexletConsistency every = lab::texletConsistency (recs, NoiseModel::paper (), odd);
  EXPECT_EQ (o.frames, 5 * 15);
  EXPECT_EQ (every.frames, 5 * 20);
  EXPECT_NEAR (o.medianRatioP (), 1.0, 0.25);
  EXPECT_NEAR (o.medianRatioN (), 1.0, 0.25);
  EXPECT_LT (o.logRatioError (), std::log (1.25));
}

/** NEES under the paper's model and after the lab adds \a effect (fitted on the recordings). */
void
beforeAndAfter (const std::string &effect, std::uint32_t seed, lab::TexletConsistency &before,
                lab::TexletConsistency &after)
{
  lab::ModelLab lab;
  for (const auto &r : simulatePlanes (effect, seed))
    lab.addRecording (r);
  const NoiseModel paper = NoiseModel::paper ();
  before = lab::texletConsistency (lab.recordings (), paper);
  after = lab::texletConsistency (lab.recordings (), lab.addEffect (paper, effect));
  print (effect + ", paper model", before);
  print (effect + ", + " + effect, after);
}

TEST (ModelLabTexlets, StripesMakePaperTexletsOverconfidentUntilAdded)
{
  lab::TexletConsistency before, after;
  beforeAndAfter ("vertical_stripes", 22, before, after);
  // Measured: ratio 12569 (P), 210 (N) under the paper model. With the stripes added, the
  // texlets take the column offsets as shared by their disc's columns, correlated by
  // exp(-du / L) across them (kernels/shared_noise.h): P 1.13 (median 1.21). While they took
  // them as independent per pixel, P was 125. N: mean 9.1, median 0.45: a band boundary
  // crosses the disc in some frames only, and tilts it there (docs/texlet_covariances.md).
  EXPECT_GT (before.ratioP (), 100.0);
  EXPECT_GT (before.ratioN (), 100.0);
  EXPECT_NEAR (after.ratioP (), 1.0, 0.5);
  EXPECT_NEAR (after.medianRatioP (), 1.0, 0.5);
  EXPECT_LT (after.ratioN (), 10.0);
  EXPECT_LT (after.medianRatioN (), 1.0);
}

TEST (ModelLabTexlets, RadialVarianceFallsWhenAdded)
{
  lab::TexletConsistency before, after;
  beforeAndAfter ("radial", 22, before, after);
  // Measured: ratio 1.215 (P), 1.214 (N) under the paper model, 1.121 and 1.120 with radial
  // added: back to the 1.13 of recordings without a hidden effect.
  EXPECT_LT (after.ratioP (), before.ratioP () - 0.05);
  EXPECT_LT (after.ratioN (), before.ratioN () - 0.05);
  EXPECT_NEAR (after.ratioP (), 1.0, 0.25);
  EXPECT_NEAR (after.ratioN (), 1.0, 0.25);
}

TEST (ModelLabTexlets, IncidenceAngleReachesTexletsAtTheirOwnAngle)
{
  // Walls at 0 to 70 degrees with the angle effect hidden. TexletEstimation evaluates the
  // noise per pixel at a frontal view and rescales each texlet's covariances to its own
  // incidence (normal against viewing ray); before, the angle term did not reach the texlets.
  lab::ModelLab lab;
  for (const auto &r : simulatePlanes ("incidence_angle", 23))
    lab.addRecording (r);
  const NoiseModel paper = NoiseModel::paper ();
  const NoiseModel fitted = lab.addEffect (paper, "incidence_angle");
  NoiseModel frontal (fitted); // what the texlets got before: the angle term at cos = 1 is neutral
  frontal.remove ("incidence_angle");
  const lab::TexletConsistency p = lab::texletConsistency (lab.recordings (), paper);
  const lab::TexletConsistency f = lab::texletConsistency (lab.recordings (), frontal);
  const lab::TexletConsistency a = lab::texletConsistency (lab.recordings (), fitted);
  print ("incidence_angle, paper model", p);
  print ("incidence_angle, + incidence_angle evaluated at a frontal view", f);
  print ("incidence_angle, + incidence_angle at each texlet's angle", a);
  ASSERT_GT (a.texlets, 3000);
  // The paper's texlets are over-confident on steep walls; the fitted angle term, at each
  // texlet's own angle, brings the NEES of P and N near their ideal, which the same model at a
  // frontal view does not.
  EXPECT_GT (p.ratioN (), 1.3);
  EXPECT_LT (a.ratioN (), f.ratioN () - 0.2);
  EXPECT_LT (a.ratioP (), f.ratioP () - 0.2);
  EXPECT_NEAR (a.ratioN (), 1.0, 0.25);
  EXPECT_NEAR (a.medianRatioN (), 1.0, 0.25);
  EXPECT_NEAR (a.medianRatioP (), 1.0, 0.25);
}

TEST (ModelLabTexlets, TexletCovarianceScalesWithItsOwnIncidenceAngle)
{
  // A noise-free plane 2 m away, turned 45 degrees about the vertical axis (incidence 16 to 74 degrees over the image), seen by a 320 x 240
  // pinhole: with an incidence_angle term of gain g in the model, every texlet's covariances
  // are those of the model without it times the closed-form factor (1 + g (1/cos - 1))^2 at the
  // texlet's angle between the plane's normal and the ray to the texlet.
  const double fx = 290, cx = 159.5, cy = 119.5, theta = 45.0 * M_PI / 180.0;
  const Eigen::Vector3d n (std::sin (theta), 0.0, -std::cos (theta)), p0 (0, 0, 2.0);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (320, 240);
  for (int v = 0; v < 240; ++v)
    for (int u = 0; u < 320; ++u)
    {
      const Eigen::Vector3d ray ((u - cx) / fx, (v - cy) / fx, 1.0);
      const double z = n.dot (p0) / n.dot (ray);
      (*cloud) (u, v).getVector3fMap () = (z * ray).cast<float> ();
    }
  NoiseModel with = NoiseModel::paper ();
  with.add (EffectTermOf<effects::IncidenceAngle> ({0.5}));
  pcl::TexletEstimation<pcl::PointXYZ, pcl::Texlet> estimation;
  estimation.setCameraModel (std::make_shared<PinholeModel> (fx, fx, cx, cy));
  estimation.setInputCloud (cloud);
  estimation.setRansacThreshold (1.0);
  pcl::PointCloud<pcl::Texlet> a, b;
  estimation.setNoiseModel (NoiseModel::paper ());
  estimation.compute (a);
  estimation.setNoiseModel (with);
  estimation.compute (b);
  ASSERT_EQ (a.size (), b.size ());
  int checked = 0;
  for (std::size_t k = 0; k < a.size (); ++k)
  {
    if (!std::isfinite (a[k].x) || !std::isfinite (b[k].x))
      continue;
    const Eigen::Vector3d P = a[k].getVector3fMap ().cast<double> ();
    const double cos_t = std::fabs (n.dot (P)) / P.norm ();
    const double factor = effects::IncidenceAngle::varianceFactorAt (0.5, cos_t);
    EXPECT_NEAR (b[k].cov_p_zz / a[k].cov_p_zz, factor, 2e-3 * factor) << "texlet " << k;
    EXPECT_NEAR (b[k].cov_n_11 / a[k].cov_n_11, factor, 2e-3 * factor) << "texlet " << k;
    ++checked;
  }
  EXPECT_GT (checked, 500);
}

TEST (ModelLabTexlets, BadInput)
{
  EXPECT_THROW (lab::texletConsistency ({}, NoiseModel::paper ()), pcl::BadArgumentException);
  lab::TexletConsistencySettings s;
  s.max_frames = 2;
  EXPECT_THROW (lab::texletConsistency ({nullptr}, NoiseModel::paper (), s), pcl::BadArgumentException);
  EXPECT_THROW (lab::texletConsistency ({nullptr}, NoiseModel::paper ()), pcl::BadArgumentException);
  lab::TexletConsistencySettings parity;
  parity.frame_parity = 2;
  try
  {
    lab::texletConsistency ({nullptr}, NoiseModel::paper (), parity); // the settings are checked first
    ADD_FAILURE () << "frame_parity 2 accepted";
  }
  catch (const pcl::BadArgumentException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("frame_parity"), std::string::npos) << e.what ();
  }
  EXPECT_TRUE (std::isnan (lab::TexletConsistency ().logRatioError ())); // nothing compared
}
