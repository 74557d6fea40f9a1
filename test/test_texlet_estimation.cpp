/*
 * TexletEstimation on rendered scenes with known normals: fits against each other and the
 * truth, RANSAC at depth steps, determinism, colour, and bad input.
 */
#include "support/synthetic_scene.h"

#include <pcl_texlet/camera/camera_estimation.h>
#include <pcl_texlet/features/cloud_points.h>
#include <pcl_texlet/features/texlet_estimation.h>
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <pcl/common/io.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

using namespace pcl_texlet_test;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::UncertaintyMethod;

namespace
{

Eigen::Vector3d
normalOf (const pcl::Texlet &t) { return {t.normal_x, t.normal_y, t.normal_z}; }

Eigen::Vector3d
centreOf (const pcl::Texlet &t) { return {t.x, t.y, t.z}; }

pcl::PointCloud<pcl::Texlet>
extract (const pcl::PointCloud<pcl::PointXYZ> &cloud, const CameraSpec &cam, PlaneFitMethod fit,
         UncertaintyMethod unc, const pcl::texlet::NoiseModel &noise = pcl::texlet::NoiseModel::paper (),
         int spacing = 6, unsigned threads = 1, std::uint32_t seed = 1,
         pcl::texlet::TexletCentre centre = pcl::texlet::TexletCentre::CentreRay)
{
  pcl::TexletEstimation<pcl::PointXYZ> est;
  est.setCentreDefinition (centre);
  est.setInputCloud (cloud.makeShared ());
  est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (cam.pinhole ()));
  est.setNoiseModel (noise);
  est.setPlaneFitMethod (fit);
  est.setUncertaintyMethod (unc);
  est.setSpacing (spacing);
  est.setNumberOfThreads (threads);
  est.setSeed (seed);
  pcl::PointCloud<pcl::Texlet> out;
  est.compute (out);
  return out;
}

/** A depth bias of \a b mm at every reading and no variance: a closed-form stand-in for a
  * warm-up drift or a distortion map. It does not say whether it moves the mean (a user's term
  * need not): the extractor takes it to.
  */
class ConstantBias : public pcl::texlet::NoiseTerm
{
public:
  explicit ConstantBias (double b) : b_ (b) {}
  std::string name () const override { return "constant_bias"; }
  double variance (const pcl::texlet::PixelContext &) const override { return 0.0; }
  double bias (const pcl::texlet::PixelContext &) const override { return b_; }
  std::vector<std::string> parameterNames () const override { return {"bias_mm"}; }
  std::vector<double> parameters () const override { return {b_}; }
  void setParameters (const std::vector<double> &v) override { b_ = v.at (0); }
  pcl::texlet::NoiseTerm::Ptr clone () const override { return std::make_shared<ConstantBias> (*this); }

private:
  double b_;
};

/** True normal at the surface point under a texlet's centre pixel. */
Eigen::Vector3d
trueNormal (const Render &r, const pcl::Texlet &t) { return r.normals[t.pixel_index]; }

} // namespace

TEST (TexletEstimation, OneTexletPerHexCentreWithPixelIndex)
{
  const CameraSpec cam;
  const Render r = render (tiltedPlane (10, 20, 1.0), cam, nullptr, 0);
  const auto out = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::None);
  const auto grid = pcl::texlet::kernels::makeHexGrid (cam.width, cam.height, 6);
  ASSERT_EQ (static_cast<int> (out.size ()), grid.size ());
  EXPECT_EQ (out.height, 1u);
  for (int i = 0; i < grid.size (); ++i)
  {
    int u, v;
    pcl::texlet::kernels::hexCentre (grid, i, u, v);
    EXPECT_EQ (out[i].pixel_index, static_cast<std::uint32_t> (v * cam.width + u));
  }
  EXPECT_TRUE (out.is_dense);
}

TEST (TexletEstimation, InteriorFastPathGathersWhatTheBoundsCheckedPathGathers)
{
  // A small cloud with holes; every centre, inside and at the borders, gathered both ways.
  pcl::PointCloud<pcl::PointXYZ> cloud (23, 17);
  for (int v = 0; v < 17; ++v)
    for (int u = 0; u < 23; ++u)
      cloud (u, v) = pcl::PointXYZ (0.01f * u, 0.01f * v, (u * 7 + v * 3) % 5 == 0 ? NAN : 1.0f + 0.001f * u);
  const pcl::texlet::detail::CloudPoints<pcl::PointXYZ> frame (cloud);
  const int radius = 4, n = pcl::texlet::kernels::pixelDiscSize (radius);
  std::vector<int> du (n), dv (n);
  pcl::texlet::kernels::pixelDiscOffsets (radius, du.data (), dv.data (), n);
  std::vector<std::ptrdiff_t> linear (n);
  for (int o = 0; o < n; ++o)
    linear[o] = static_cast<std::ptrdiff_t> (dv[o]) * cloud.width + du[o];
  pcl::texlet::kernels::PixelDisc checked;
  checked.du = du.data ();
  checked.dv = dv.data ();
  checked.size = n;
  checked.radius = radius;
  pcl::texlet::kernels::PixelDisc fast = checked;
  fast.linear = linear.data ();
  int interior = 0;
  for (int cv = 0; cv < 17; ++cv)
    for (int cu = 0; cu < 23; ++cu)
    {
      std::vector<int> a, b;
      pcl::texlet::kernels::forEachDiscPoint (frame, fast, cu, cv,
                                              [&] (const pcl::PointXYZ &, int index) { a.push_back (index); });
      pcl::texlet::kernels::forEachDiscPoint (frame, checked, cu, cv,
                                              [&] (const pcl::PointXYZ &, int index) { b.push_back (index); });
      ASSERT_EQ (a, b) << "centre " << cu << ", " << cv;
      for (const int i : a)
        ASSERT_TRUE (std::isfinite (cloud[i].z));
      interior += cu >= radius && cv >= radius && cu + radius < 23 && cv + radius < 17;
    }
  EXPECT_GT (interior, 100);
}

TEST (TexletEstimation, PcaMatchesSvdOnPlanesSpheresAndBoxes)
{
  const CameraSpec cam;
  const auto noise = pcl::texlet::NoiseModel::paper ();
  int compared = 0;
  for (const Scene &scene : {tiltedPlane (0, 0, 0.9), tiltedPlane (25, -30, 1.4), sphereScene (), boxScene ()})
  {
    const Render r = render (scene, cam, &noise, 11);
    const auto pca = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::None);
    const auto svd = extract (r.cloud, cam, PlaneFitMethod::SVD, UncertaintyMethod::None);
    ASSERT_EQ (pca.size (), svd.size ());
    for (std::size_t i = 0; i < pca.size (); ++i)
    {
      ASSERT_EQ (std::isfinite (pca[i].x), std::isfinite (svd[i].x));
      if (!std::isfinite (pca[i].x))
        continue;
      EXPECT_LT (axisAngle (normalOf (pca[i]), normalOf (svd[i])), 1e-3);
      EXPECT_EQ (pca[i].support, svd[i].support); // same RANSAC draws, same inliers
      ++compared;
    }
  }
  EXPECT_GT (compared, 1000);
}

TEST (TexletEstimation, PlaneNormalsMatchTruthWithinTheirPredictedNoise)
{
  // The angular error to the true normal should be as large as Sigma_N says, no more:
  // RMS error / RMS predicted SD near 1.
  const CameraSpec cam;
  const auto noise = pcl::texlet::NoiseModel::paper ();
  for (auto [tx, ty, d] : {std::tuple<double, double, double>{0, 0, 0.8}, {20, 0, 1.2}, {-15, 30, 1.6}})
  {
    double err2 = 0, pred2 = 0;
    int n = 0;
    for (std::uint32_t copy = 0; copy < 5; ++copy)
    {
      const Render r = render (tiltedPlane (tx, ty, d), cam, &noise, 100 + copy);
      const auto out = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::Analytic);
      for (const auto &t : out)
      {
        if (!std::isfinite (t.x))
          continue;
        err2 += std::pow (axisAngle (normalOf (t), trueNormal (r, t)), 2);
        pred2 += t.cov_n_11 + t.cov_n_22;
        ++n;
      }
    }
    ASSERT_GT (n, 1000);
    const double ratio = std::sqrt (err2 / pred2);
    EXPECT_GT (ratio, 0.85) << "tilt " << tx << "," << ty << " at " << d << " m";
    EXPECT_LT (ratio, 1.15) << "tilt " << tx << "," << ty << " at " << d << " m";
    EXPECT_LT (std::sqrt (err2 / n), 0.1); // and the errors are small: a few degrees at most
  }
}

TEST (TexletEstimation, SphereAndBoxNormalsMatchTruth)
{
  const CameraSpec cam;
  const auto noise = pcl::texlet::NoiseModel::paper ();
  const Render sphere = render (sphereScene (), cam, &noise, 5);
  for (const auto centre : {pcl::texlet::TexletCentre::InlierMean, pcl::texlet::TexletCentre::CentreRay})
  {
    const auto out = extract (sphere.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::Analytic, noise, 6, 1, 1, centre);
    const Eigen::Vector3d c (0, 0, 1.3);
    int n = 0, within = 0;
    for (const auto &t : out)
    {
      // Patches seen at more than 53 degrees (or at the limb) carry a curvature bias larger than
      // the noise: obliquely, the disc spans more of the sphere (12-17 mrad at 55-60 degrees,
      // docs/texlet_covariances.md). This check is about the rest.
      const Eigen::Vector3d &n_pixel = sphere.normals[t.pixel_index];
      if (!std::isfinite (t.x) || n_pixel.isZero () || -n_pixel.dot (centreOf (t).normalized ()) < 0.6)
        continue;
      // Truth at the patch centre: the sphere's radial direction through P.
      const double err = axisAngle (normalOf (t), (centreOf (t) - c).normalized ());
      const double sd = std::sqrt (t.cov_n_11 + t.cov_n_22);
      within += err < 3 * sd + 0.005 ? 1 : 0; // 0.005 rad: the patch's own curvature bias
      ++n;
    }
    ASSERT_GT (n, 130);
    // The normal belongs where the inliers are, at their mean; the centre ray's point can lie a
    // little off it where the inliers are not centred on the ray (measured 144 of 144, 141 of 145).
    const double share = centre == pcl::texlet::TexletCentre::InlierMean ? 0.97 : 0.95;
    EXPECT_GT (within, share * n) << within << " of " << n << ", centre " << pcl::texlet::toString (centre);
  }
  {
    const Render r = render (boxScene (), cam, &noise, 6);
    const auto out = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::Analytic);
    int n = 0, within = 0;
    for (const auto &t : out)
    {
      if (!std::isfinite (t.x))
        continue;
      const double err = axisAngle (normalOf (t), trueNormal (r, t));
      within += err < 3 * std::sqrt (t.cov_n_11 + t.cov_n_22) ? 1 : 0;
      ++n;
    }
    ASSERT_GT (n, 300);
    // Texlets straddling a fold of the box may fit either face; nearly all others match.
    EXPECT_GT (within, 0.9 * n);
  }
}

TEST (TexletEstimation, AveragingIsWorseThanPcaAtEveryNoiseLevel)
{
  // The ordering of the paper's Fig. 8: normal averaging is the most noise-sensitive fit.
  const CameraSpec cam;
  double last_pca = 0, last_avg = 0;
  for (double factor : {0.5, 1.0, 2.0, 4.0})
  {
    const auto noise = scaledPaperNoise (factor);
    double pca_err = 0, avg_err = 0;
    int n = 0;
    for (std::uint32_t copy = 0; copy < 3; ++copy)
    {
      const Render r = render (tiltedPlane (15, 10, 1.0), cam, &noise, 300 + copy);
      const auto pca = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::None, noise);
      const auto avg = extract (r.cloud, cam, PlaneFitMethod::Averaging, UncertaintyMethod::None, noise);
      for (std::size_t i = 0; i < pca.size (); ++i)
        if (std::isfinite (pca[i].x) && std::isfinite (avg[i].x))
        {
          pca_err += axisAngle (normalOf (pca[i]), trueNormal (r, pca[i]));
          avg_err += axisAngle (normalOf (avg[i]), trueNormal (r, avg[i]));
          ++n;
        }
    }
    ASSERT_GT (n, 500);
    pca_err /= n;
    avg_err /= n;
    EXPECT_GT (avg_err, 1.5 * pca_err) << "noise x" << factor;
    EXPECT_GT (pca_err, last_pca);
    EXPECT_GT (avg_err, last_avg);
    last_pca = pca_err;
    last_avg = avg_err;
  }
}

TEST (TexletEstimation, RansacKeepsTheNormalOfItsOwnSurfaceAtADepthStep)
{
  // Left of column 80: a wall tilted 30 degrees at ~1 m; right of it: a frontal wall 15 cm behind.
  const CameraSpec cam;
  Scene s;
  auto left = std::make_shared<PlaneSurface> (Eigen::Vector3d (std::sin (0.5236), 0, -std::cos (0.5236)),
                                              Eigen::Vector3d (0, 0, 1.0));
  left->side = Eigen::Vector3d (-1, 0, 0);
  left->side_offset = 0.0; // x < 0 only: the left half of the image
  auto right = std::make_shared<PlaneSurface> (Eigen::Vector3d (0, 0, -1), Eigen::Vector3d (0, 0, 1.15));
  s.surfaces = {left, right};
  const auto noise = pcl::texlet::NoiseModel::paper ();
  const Render r = render (s, cam, &noise, 21);
  const Eigen::Vector3d n_left = left->n.dot (Eigen::Vector3d (0, 0, 1)) < 0 ? left->n : Eigen::Vector3d (-left->n);

  // Texlets centred 2 px left of the step: about a third of each disc lies on the other wall.
  pcl::IndicesPtr centres (new pcl::Indices);
  for (int v = 20; v < 100; v += 5)
    centres->push_back (v * cam.width + 77);
  for (const double threshold : {0.0, 1.0}) // automatic (3 sigma), and 1 m: no rejection
  {
    pcl::TexletEstimation<pcl::PointXYZ> est;
    est.setInputCloud (r.cloud.makeShared ());
    est.setIndices (centres);
    est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (cam.pinhole ()));
    est.setUncertaintyMethod (UncertaintyMethod::None);
    est.setRansacThreshold (threshold);
    pcl::PointCloud<pcl::Texlet> out;
    est.compute (out);
    ASSERT_EQ (out.size (), centres->size ());
    for (const auto &t : out)
    {
      ASSERT_TRUE (std::isfinite (t.x));
      const double err = axisAngle (normalOf (t), n_left);
      if (threshold == 0.0)
      {
        EXPECT_LT (err, 0.05) << "RANSAC should reject the far wall";
        EXPECT_LT (t.support, 100u); // the disc has 113 pixels; the far wall's are outliers
      }
      else
        EXPECT_GT (err, 0.15) << "without rejection the step bends the normal";
    }
  }
}

TEST (TexletEstimation, SameSeedSameOutputOnOneAndTwoThreads)
{
  const CameraSpec cam;
  const auto noise = pcl::texlet::NoiseModel::paper ();
  const Render r = render (boxScene (), cam, &noise, 8);
  for (auto unc : {UncertaintyMethod::MonteCarlo, UncertaintyMethod::Analytic})
  {
    const auto a = extract (r.cloud, cam, PlaneFitMethod::PCA, unc, noise, 3, 1, 42);
    const auto b = extract (r.cloud, cam, PlaneFitMethod::PCA, unc, noise, 3, 2, 42);
    ASSERT_EQ (a.size (), b.size ());
    EXPECT_EQ (0, std::memcmp (a.data (), b.data (), a.size () * sizeof (pcl::Texlet)));
  }
  // A different seed changes the Monte Carlo covariances.
  const auto c = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::MonteCarlo, noise, 3, 2, 43);
  const auto a = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::MonteCarlo, noise, 3, 2, 42);
  EXPECT_NE (0, std::memcmp (a.data (), c.data (), a.size () * sizeof (pcl::Texlet)));
}

TEST (TexletEstimation, MeanColourOfTheInliers)
{
  const CameraSpec cam;
  const Render r = render (tiltedPlane (0, 0, 1.0), cam, nullptr, 0);
  pcl::PointCloud<pcl::PointXYZRGB> cloud;
  pcl::copyPointCloud (r.cloud, cloud);
  for (std::size_t i = 0; i < cloud.size (); ++i)
  {
    const int u = static_cast<int> (i % cam.width);
    cloud[i].r = u < 80 ? 200 : 100; // two colour halves
    cloud[i].g = 50;
    cloud[i].b = static_cast<std::uint8_t> (u % 2 ? 11 : 13); // alternating columns: mean 12
  }
  pcl::TexletEstimation<pcl::PointXYZRGB> est;
  est.setInputCloud (cloud.makeShared ());
  est.setUncertaintyMethod (UncertaintyMethod::None);
  pcl::PointCloud<pcl::Texlet> out;
  est.compute (out);
  int checked = 0;
  for (const auto &t : out)
  {
    const int u = static_cast<int> (t.pixel_index % cam.width);
    if (u < 10 || u > 150 || std::abs (u - 80) < 8)
      continue;
    EXPECT_EQ (t.r, u < 80 ? 200 : 100);
    EXPECT_EQ (t.g, 50);
    EXPECT_NEAR (t.b, 12, 1);
    ++checked;
  }
  EXPECT_GT (checked, 200);
}

TEST (TexletEstimation, EstimatesTheCameraWhenNoneIsSet)
{
  const CameraSpec cam{160, 120, 131.0, 129.0, 83.0, 55.5};
  const Render r = render (tiltedPlane (10, 10, 1.0), cam, nullptr, 0);
  const auto estimated = pcl::texlet::estimatePinholeModel (r.cloud);
  EXPECT_NEAR (estimated.fx (), 131.0, 1e-3);
  EXPECT_NEAR (estimated.fy (), 129.0, 1e-3);
  EXPECT_NEAR (estimated.cx (), 83.0, 1e-3);
  EXPECT_NEAR (estimated.cy (), 55.5, 1e-3);
}

TEST (TexletEstimation, DegenerateNeighbourhoodsGiveNaNTexletsAndANonDenseOutput)
{
  // Only one row of valid pixels: every neighbourhood is collinear.
  const CameraSpec cam;
  Render r = render (tiltedPlane (0, 0, 1.0), cam, nullptr, 0);
  for (std::size_t i = 0; i < r.cloud.size (); ++i)
    if (i / cam.width != 60)
      r.cloud[i].x = r.cloud[i].y = r.cloud[i].z = std::numeric_limits<float>::quiet_NaN ();
  const auto out = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::MonteCarlo);
  EXPECT_FALSE (out.is_dense);
  for (const auto &t : out)
  {
    EXPECT_FALSE (std::isfinite (t.x));
    EXPECT_FALSE (std::isfinite (t.normal_x));
    EXPECT_FALSE (std::isfinite (t.cov_p_xx));
    EXPECT_EQ (t.support, 0u);
  }
}

TEST (TexletEstimation, BadInputGetsAClearError)
{
  pcl::TexletEstimation<pcl::PointXYZ> est;
  pcl::PointCloud<pcl::Texlet> out;
  EXPECT_THROW (est.compute (out), pcl::InitFailedException); // no input at all

  pcl::PointCloud<pcl::PointXYZ>::Ptr flat (new pcl::PointCloud<pcl::PointXYZ>);
  flat->resize (1000, pcl::PointXYZ (0, 0, 1)); // width 1000, height 1: unorganised
  est.setInputCloud (flat);
  try
  {
    est.compute (out);
    FAIL () << "an unorganised cloud must be rejected";
  }
  catch (const pcl::UnorganizedPointCloudException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("not organised"), std::string::npos) << e.what ();
  }

  try
  {
    est.setSpacing (0);
    FAIL () << "spacing 0 must be rejected";
  }
  catch (const pcl::BadArgumentException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("spacing"), std::string::npos) << e.what ();
  }
  EXPECT_EQ (est.getSpacing (), 6); // a rejected value leaves the setting as it was
  EXPECT_THROW (est.setRadius (-2), pcl::BadArgumentException);
  EXPECT_THROW (est.setRansacIterations (0), pcl::BadArgumentException);
  EXPECT_THROW (est.setRansacThreshold (-0.01), pcl::BadArgumentException);
  EXPECT_THROW (est.setRansacThreshold (std::nan ("")), pcl::BadArgumentException);
  EXPECT_THROW (est.setRansacThresholdSigmas (0), pcl::BadArgumentException);
  EXPECT_THROW (est.setMonteCarloSamples (1), pcl::BadArgumentException);
  EXPECT_THROW (est.setMinSupport (2), pcl::BadArgumentException);
  EXPECT_THROW (est.setViewPoint (0, std::nanf (""), 0), pcl::BadArgumentException);
  EXPECT_THROW (pcl::texlet::PinholeModel (0, 500, 320, 240), pcl::BadArgumentException);
  EXPECT_THROW (pcl::texlet::planeFitMethodFromString ("ransac"), pcl::BadArgumentException);
  for (auto m : {pcl::texlet::UncertaintyMethod::None, pcl::texlet::UncertaintyMethod::Analytic,
                 pcl::texlet::UncertaintyMethod::MonteCarlo})
    EXPECT_EQ (pcl::texlet::uncertaintyMethodFromString (pcl::texlet::toString (m)), m);
  try
  {
    pcl::texlet::uncertaintyMethodFromString ("mc");
    ADD_FAILURE () << "'mc' accepted";
  }
  catch (const pcl::BadArgumentException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("unknown uncertainty method 'mc' (use none, analytic or montecarlo)"),
               std::string::npos)
        << e.what ();
  }

  // All depth invalid.
  pcl::PointCloud<pcl::PointXYZ>::Ptr empty (new pcl::PointCloud<pcl::PointXYZ> (64, 48));
  for (auto &p : *empty)
    p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN ();
  est.setInputCloud (empty);
  est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (50, 50, 32, 24));
  EXPECT_THROW (est.compute (out), pcl::ComputeFailedException);

  // An index outside the cloud.
  const CameraSpec cam;
  const Render r = render (tiltedPlane (0, 0, 1.0), cam, nullptr, 0);
  est.setInputCloud (r.cloud.makeShared ());
  est.setIndices (pcl::IndicesPtr (new pcl::Indices{5, static_cast<int> (r.cloud.size ())}));
  EXPECT_THROW (est.compute (out), pcl::BadArgumentException);

  pcl::Texlet t;
  pcl::texlet::TexletParameters p;
  EXPECT_THROW (pcl::computeTexlet (r.cloud, -1, p, cam.pinhole (), pcl::texlet::NoiseModel::paper (), t),
                pcl::BadArgumentException);
  EXPECT_THROW (pcl::computeTexlet (*flat, 0, p, cam.pinhole (), pcl::texlet::NoiseModel::paper (), t),
                pcl::UnorganizedPointCloudException);
}

TEST (TexletEstimation, NormalsFaceTheSensorOriginUnlessAViewpointIsSet)
{
  // A wall 1 m in front of the camera, in a cloud whose sensor origin lies 2 m out, behind the
  // wall: as in PCL's NormalEstimation the normals face the sensor origin by default.
  const CameraSpec cam;
  const Render r = render (tiltedPlane (0, 0, 1.0), cam, nullptr, 0);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud = r.cloud.makeShared ();
  cloud->sensor_origin_ = Eigen::Vector4f (0.0f, 0.0f, 2.0f, 0.0f);
  pcl::TexletEstimation<pcl::PointXYZ> est;
  est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (cam.pinhole ()));
  est.setUncertaintyMethod (UncertaintyMethod::None);
  est.setInputCloud (cloud);
  float vx, vy, vz;
  est.getViewPoint (vx, vy, vz);
  EXPECT_EQ (vz, 2.0f);
  pcl::PointCloud<pcl::Texlet> from_origin, from_camera, again;
  est.compute (from_origin);

  est.setViewPoint (0, 0, 0); // the camera centre, as the cloud's points are seen from
  est.getViewPoint (vx, vy, vz);
  EXPECT_EQ (vz, 0.0f);
  est.compute (from_camera);
  ASSERT_EQ (from_origin.size (), from_camera.size ());
  std::size_t made = 0;
  for (std::size_t i = 0; i < from_origin.size (); ++i)
  {
    const pcl::Texlet &a = from_origin[i], &b = from_camera[i];
    ASSERT_EQ (a.support, b.support);
    if (a.support == 0)
      continue;
    ++made;
    EXPECT_GT (a.normal_z, 0.99f) << "texlet " << i;
    EXPECT_LT (b.normal_z, -0.99f) << "texlet " << i;
    // The same fit, only turned the other way.
    EXPECT_EQ (a.normal_x, -b.normal_x);
    EXPECT_EQ (a.normal_y, -b.normal_y);
    EXPECT_EQ (a.normal_z, -b.normal_z);
    EXPECT_EQ (a.x, b.x);
    EXPECT_EQ (a.z, b.z);
  }
  EXPECT_GT (made, from_origin.size () / 2);

  // Back to the sensor origin; setParameters with the viewpoint unchanged keeps it, a new one
  // counts as set.
  est.useSensorOriginAsViewPoint ();
  pcl::texlet::TexletParameters p = est.getParameters ();
  p.spacing = 8;
  est.setParameters (p);
  // Made texlets, and how many of them face +z (the sensor origin) and -z (the camera).
  const auto facing = [] (const pcl::PointCloud<pcl::Texlet> &c, std::size_t &away, std::size_t &toward) {
    std::size_t n = 0;
    away = toward = 0;
    for (const pcl::Texlet &x : c)
      if (x.support > 0)
      {
        ++n;
        away += x.normal_z > 0.99f ? 1 : 0;
        toward += x.normal_z < -0.99f ? 1 : 0;
      }
    return n;
  };
  std::size_t away, toward;
  est.compute (again);
  std::size_t n = facing (again, away, toward);
  EXPECT_GT (n, 0u);
  EXPECT_EQ (away, n);
  p.viewpoint[2] = -1.0f;
  est.setParameters (p);
  est.compute (again);
  n = facing (again, away, toward);
  EXPECT_GT (n, 0u);
  EXPECT_EQ (toward, n);

  // The free function faces the parameters' viewpoint.
  pcl::Texlet t;
  ASSERT_TRUE (pcl::computeTexlet (*cloud, from_camera[from_camera.size () / 2].pixel_index,
                                   pcl::texlet::TexletParameters (), cam.pinhole (), pcl::texlet::NoiseModel::paper (),
                                   t));
  EXPECT_LT (t.normal_z, -0.99f);

  // A sensor origin that is no point is an error, not a random orientation.
  cloud->sensor_origin_ = Eigen::Vector4f (0.0f, std::nanf (""), 0.0f, 0.0f);
  est.useSensorOriginAsViewPoint ();
  try
  {
    est.compute (again);
    FAIL () << "a NaN sensor origin must be rejected";
  }
  catch (const pcl::BadArgumentException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("sensor_origin_"), std::string::npos) << e.what ();
  }
}

TEST (TexletEstimation, FreeFunctionMatchesTheClass)
{
  const CameraSpec cam;
  const auto noise = pcl::texlet::NoiseModel::paper ();
  const Render r = render (sphereScene (), cam, &noise, 3);
  const auto out = extract (r.cloud, cam, PlaneFitMethod::PCA, UncertaintyMethod::MonteCarlo);
  pcl::texlet::TexletParameters p;
  p.seed = 1;
  for (std::size_t i = 0; i < out.size (); i += 17)
  {
    pcl::Texlet t;
    const bool ok = pcl::computeTexlet (r.cloud, out[i].pixel_index, p, cam.pinhole (), noise, t);
    EXPECT_EQ (ok, std::isfinite (out[i].x));
    if (ok)
      EXPECT_EQ (0, std::memcmp (&t, &out[i], sizeof (pcl::Texlet)));
  }
}

TEST (TexletEstimation, TheModelsBiasIsTakenOffTheReadings)
{
  // A wall tilted by 35 degrees read 20 mm too far at every pixel, with a model that knows that
  // bias: each reading loses it along its ray before the fit, so the texlets are those of the
  // unbiased readings (P to float precision, the same covariances); kept, P lies off the wall by
  // the bias along the ray. The free function does the same per texlet.
  const CameraSpec cam;
  const double bias_mm = 20.0;
  const Render r = render (tiltedPlane (10, 35, 1.2), cam, nullptr, 0);
  pcl::PointCloud<pcl::PointXYZ> biased = r.cloud;
  for (auto &p : biased.points)
    if (std::isfinite (p.z))
    {
      const float s = static_cast<float> ((p.z * 1000.0 + bias_mm) / (p.z * 1000.0));
      p.x *= s, p.y *= s, p.z *= s;
    }
  pcl::texlet::NoiseModel model = pcl::texlet::NoiseModel::paper ();
  model.add (ConstantBias (bias_mm));
  EXPECT_TRUE (model.movesMean ());
  EXPECT_FALSE (pcl::texlet::NoiseModel::paper ().movesMean ());
  for (auto unc : {UncertaintyMethod::Analytic, UncertaintyMethod::MonteCarlo})
  {
    const auto truth = extract (r.cloud, cam, PlaneFitMethod::PCA, unc);
    const auto removed = extract (biased, cam, PlaneFitMethod::PCA, unc, model);
    pcl::TexletEstimation<pcl::PointXYZ> est;
    est.setInputCloud (biased.makeShared ());
    est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (cam.pinhole ()));
    est.setNoiseModel (model);
    est.setUncertaintyMethod (unc);
    est.setSeed (1);
    est.setRemoveModelBias (false);
    EXPECT_FALSE (est.getRemoveModelBias ());
    pcl::PointCloud<pcl::Texlet> kept;
    est.compute (kept);
    ASSERT_EQ (truth.size (), removed.size ());
    ASSERT_EQ (truth.size (), kept.size ());
    int compared = 0;
    double worst_p = 0, worst_cov = 0, worst_kept = 0;
    for (std::size_t i = 0; i < truth.size (); ++i)
    {
      if (!std::isfinite (truth[i].x) || !std::isfinite (removed[i].x) || !std::isfinite (kept[i].x))
        continue;
      ++compared;
      worst_p = std::max (worst_p, (centreOf (removed[i]) - centreOf (truth[i])).norm ());
      const float a[4] = {removed[i].cov_p_xx, removed[i].cov_p_zz, removed[i].cov_n_11, removed[i].cov_n_22};
      const float b[4] = {truth[i].cov_p_xx, truth[i].cov_p_zz, truth[i].cov_n_11, truth[i].cov_n_22};
      for (int k = 0; k < 4; ++k)
        worst_cov = std::max (worst_cov, std::fabs (double (a[k]) - b[k]) / b[k]);
      // Kept, each reading lies bias_mm further along its ray: P is off the wall by that times
      // the cosine between the wall's normal and the ray scaled to unit depth.
      const Eigen::Vector3d n = normalOf (truth[i]), P = centreOf (truth[i]);
      const double expected = bias_mm * 1e-3 * std::fabs (n.dot (P / P.z ()));
      worst_kept = std::max (worst_kept, std::fabs (std::fabs (n.dot (centreOf (kept[i]) - P)) - expected) / expected);
    }
    EXPECT_GT (compared, 100);
    EXPECT_LT (worst_p, 2e-6) << "metres";
    EXPECT_LT (worst_kept, 0.02);
    // Monte Carlo's draws on an exact plane move with float-level changes of the readings: its
    // texlets are compared by P alone.
    if (unc == UncertaintyMethod::Analytic)
      EXPECT_LT (worst_cov, 1e-4);

    pcl::texlet::TexletParameters p;
    p.seed = 1;
    p.uncertainty = unc;
    for (std::size_t i = 0; i < removed.size (); i += 13)
    {
      pcl::Texlet t;
      const bool ok = pcl::computeTexlet (biased, removed[i].pixel_index, p, cam.pinhole (), model, t);
      EXPECT_EQ (ok, std::isfinite (removed[i].x));
      if (ok)
        EXPECT_LT ((centreOf (t) - centreOf (removed[i])).norm (), 1e-6);
    }
  }
}

TEST (TexletEstimation, PerPixelNoiseFollowsTheCameraAndEqualsTheGeneralModel)
{
  // The paper's model is evaluated per pixel without virtual calls, from distances to the
  // principal point kept between frames. A camera with another principal point must give what
  // a fresh estimator gives, and a model that takes the general path (a second term that adds
  // a zero variance) the very same bits.
  const CameraSpec cam;
  const auto noise = pcl::texlet::NoiseModel::paper ();
  const Render r = render (sphereScene (), cam, &noise, 5);
  const pcl::texlet::PinholeModel a = cam.pinhole ();
  const auto b = std::make_shared<pcl::texlet::PinholeModel> (a.fx (), a.fy (), a.cx () + 40.5, a.cy () - 31.25);
  pcl::texlet::NoiseModel general = pcl::texlet::NoiseModel::paper ();
  general.add (pcl::texlet::PolynomialSigmaTerm ({0, 0, 0, 0, 0, 0}));
  for (auto unc : {UncertaintyMethod::Analytic, UncertaintyMethod::MonteCarlo})
  {
    pcl::TexletEstimation<pcl::PointXYZ> est;
    est.setInputCloud (r.cloud.makeShared ());
    est.setUncertaintyMethod (unc);
    est.setMonteCarloSamples (10);
    est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (a));
    pcl::PointCloud<pcl::Texlet> first, second, fresh, slow;
    est.compute (first);
    est.setCameraModel (b);
    est.compute (second);

    pcl::TexletEstimation<pcl::PointXYZ> other;
    other.setInputCloud (r.cloud.makeShared ());
    other.setUncertaintyMethod (unc);
    other.setMonteCarloSamples (10);
    other.setCameraModel (b);
    other.compute (fresh);
    ASSERT_EQ (second.size (), fresh.size ());
    EXPECT_EQ (0, std::memcmp (second.data (), fresh.data (), fresh.size () * sizeof (pcl::Texlet)));
    // The principal point moved: the per-pixel SDs and so the covariances changed.
    EXPECT_NE (0, std::memcmp (first.data (), second.data (), first.size () * sizeof (pcl::Texlet)));

    other.setNoiseModel (general);
    other.compute (slow);
    ASSERT_EQ (slow.size (), fresh.size ());
    EXPECT_EQ (0, std::memcmp (slow.data (), fresh.data (), fresh.size () * sizeof (pcl::Texlet)));
  }
}

namespace
{

/** Analytic texlets of \a cloud under \a model with a fixed RANSAC threshold (the same inliers
  * whatever the model's variances). */
template <typename PointT>
pcl::PointCloud<pcl::Texlet>
analyticWithFixedThreshold (const pcl::PointCloud<PointT> &cloud, const pcl::texlet::NoiseModel &model,
                            const CameraSpec &cam)
{
  pcl::TexletEstimation<PointT> est;
  est.setInputCloud (cloud.makeShared ());
  est.setNoiseModel (model);
  est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (cam.pinhole ()));
  est.setRansacThreshold (1.0);
  est.setUncertaintyMethod (UncertaintyMethod::Analytic);
  pcl::PointCloud<pcl::Texlet> out;
  est.compute (out);
  return out;
}

/** \a cloud with every point of grey level \a g. */
pcl::PointCloud<pcl::PointXYZRGBA>
greyCopy (const pcl::PointCloud<pcl::PointXYZ> &cloud, std::uint8_t g)
{
  pcl::PointCloud<pcl::PointXYZRGBA> c;
  pcl::copyPointCloud (cloud, c);
  for (auto &p : c.points)
    p.r = p.g = p.b = g;
  return c;
}

} // namespace

TEST (TexletEstimation, GreyLevelOfColourPointsReachesTheNoiseModel)
{
  // covariate:intensity multiplies every variance of a point by exp (log_factor_black) on a
  // black surface and by 1 on a white one; first-order propagation is linear in the variances,
  // so with the same inliers (a fixed threshold) the analytic Sigma_P and Sigma_N scale by that factor. A
  // point type without colour has no grey level: factor 1.
  const CameraSpec cam;
  const auto paper = pcl::texlet::NoiseModel::paper ();
  const Render r = render (sphereScene (), cam, &paper, 7);
  const pcl::texlet::NoiseTerm::Ptr term = pcl::texlet::makeNoiseTerm ("covariate:intensity");
  term->setParameters ({std::log (4.0), 1.0, 0.5, 0.25, 0.0, 0.0, 0.0, 0.0});
  pcl::texlet::NoiseModel model = paper;
  model.add (*term);
  auto run = [&] (const auto &cloud) { return analyticWithFixedThreshold (cloud, model, cam); };
  const auto none = run (r.cloud), white = run (greyCopy (r.cloud, 255)), black = run (greyCopy (r.cloud, 0));
  ASSERT_EQ (none.size (), black.size ());
  std::size_t compared = 0;
  for (std::size_t i = 0; i < none.size (); ++i)
  {
    if (!std::isfinite (none[i].cov_p_xx) || !(none[i].cov_p_xx > 0))
      continue;
    EXPECT_FLOAT_EQ (white[i].cov_p_xx, none[i].cov_p_xx);
    EXPECT_NEAR (black[i].cov_p_zz / none[i].cov_p_zz, 4.0, 1e-4);
    EXPECT_NEAR (black[i].cov_n_11 / none[i].cov_n_11, 4.0, 1e-4);
    ++compared;
  }
  EXPECT_GT (compared, 100u);
}

TEST (TexletEstimation, GreyLevelsOffsetComesOffTheReadings)
{
  // covariate:intensity's disparity offset on a black surface (the model: a dim dot is read
  // nearer by j o, j the depth per px of disparity) comes off each reading before the fit: P moves
  // further along its ray, by an amount linear in the offset to first order; on a white surface
  // the offset is 0 and nothing moves.
  const CameraSpec cam;
  const auto paper = pcl::texlet::NoiseModel::paper ();
  const Render r = render (sphereScene (), cam, &paper, 7);
  auto run = [&] (std::uint8_t g, double offset_px) {
    const pcl::texlet::NoiseTerm::Ptr term = pcl::texlet::makeNoiseTerm ("covariate:intensity");
    term->setParameters ({0.0, 0.0, 0.0, 0.0, offset_px, 0.0, 0.0, 0.0});
    pcl::texlet::NoiseModel model = paper;
    model.add (*term);
    EXPECT_TRUE (model.movesMean ());
    return analyticWithFixedThreshold (greyCopy (r.cloud, g), model, cam);
  };
  const auto none = run (0, 0.0), black = run (0, 0.1), blacker = run (0, 0.2), white = run (255, 0.2);
  ASSERT_EQ (none.size (), black.size ());
  std::size_t compared = 0;
  for (std::size_t i = 0; i < none.size (); ++i)
  {
    if (!std::isfinite (none[i].x) || !std::isfinite (black[i].x) || !std::isfinite (blacker[i].x))
      continue;
    const Eigen::Vector3d p = centreOf (none[i]), ray = p.normalized ();
    const Eigen::Vector3d d1 = centreOf (black[i]) - p, d2 = centreOf (blacker[i]) - p;
    EXPECT_EQ ((centreOf (white[i]) - p).norm (), 0.0);
    EXPECT_GT (d1.dot (ray), 0.0) << "the offset reads nearer: taken off, P moves away";
    EXPECT_NEAR (d1.dot (ray), 0.5 * d2.dot (ray), 0.02 * d2.dot (ray));
    ++compared;
  }
  EXPECT_GT (compared, 100u);
}
