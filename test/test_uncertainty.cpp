/*
 * Calibration of the texlet covariances: over many independently noised copies of a scene
 * whose noise follows the model, the errors of P and N must be as large as Sigma_P and
 * Sigma_N say (mean normalised squared error = degrees of freedom: 1 for P on the centre ray,
 * whose Sigma_P lies along it, 3 for the inliers' mean), and the analytic propagation must
 * agree with Monte Carlo.
 */
#include "support/synthetic_scene.h"

#include <pcl_texlet/features/texlet_estimation.h>

#include <gtest/gtest.h>

using namespace pcl_texlet_test;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::TexletCentre;
using pcl::texlet::UncertaintyMethod;

namespace
{

struct Nees
{
  double p = 0, n = 0;
  int count = 0;
};

Scene
wall ()
{
  Scene s;
  const Eigen::Vector3d n = Eigen::AngleAxisd (0.2, Eigen::Vector3d::UnitX ()) *
                            Eigen::AngleAxisd (-0.35, Eigen::Vector3d::UnitY ()) * Eigen::Vector3d (0, 0, -1);
  s.add<PlaneSurface> (n, Eigen::Vector3d (0, 0, 1.1));
  return s;
}

/** Mean NEES of P and N over `copies` noisy renders of the wall, with P defined by \a centre. */
Nees
meanNees (UncertaintyMethod method, int copies, TexletCentre centre)
{
  const CameraSpec cam;
  const auto noise = pcl::texlet::NoiseModel::paper ();
  const Scene scene = wall ();
  const auto plane = std::static_pointer_cast<PlaneSurface> (scene.surfaces[0]);
  const Eigen::Vector3d n_true = plane->n;
  Nees acc;
  for (int copy = 0; copy < copies; ++copy)
  {
    const Render r = render (scene, cam, &noise, 5000 + copy);
    pcl::TexletEstimation<pcl::PointXYZ> est;
    est.setInputCloud (r.cloud.makeShared ());
    est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (cam.pinhole ()));
    est.setSpacing (12);
    est.setUncertaintyMethod (method);
    est.setSeed (static_cast<std::uint32_t> (copy));
    est.setCentreDefinition (centre);
    // Every valid point is an inlier, so the true P is the mean of the same pixels' noise-free
    // points: the test measures the propagation, not RANSAC's selection.
    est.setRansacThreshold (1.0);
    pcl::PointCloud<pcl::Texlet> out;
    est.compute (out);
    const int radius = est.getRadius ();
    for (const auto &t : out)
    {
      if (!std::isfinite (t.x))
        continue;
      const int cu = static_cast<int> (t.pixel_index % cam.width), cv = static_cast<int> (t.pixel_index / cam.width);
      Eigen::Vector3d p_true = Eigen::Vector3d::Zero ();
      int k = 0;
      for (int dv = -radius; dv <= radius; ++dv)
        for (int du = -radius; du <= radius; ++du)
        {
          const int u = cu + du, v = cv + dv;
          if (du * du + dv * dv > radius * radius || u < 0 || v < 0 || u >= cam.width || v >= cam.height)
            continue;
          p_true += r.clean[static_cast<std::size_t> (v) * cam.width + u];
          ++k;
        }
      EXPECT_EQ (static_cast<std::uint32_t> (k), t.support);
      p_true /= k;
      if (centre == TexletCentre::CentreRay)
      {
        // The true plane's point on the centre pixel's ray; P's error and Sigma_P lie along it.
        const Eigen::Vector3d &clean = r.clean[t.pixel_index];
        const Eigen::Vector3d ray = clean / clean.z ();
        const Eigen::Vector3d on_ray = ray * (plane->d / n_true.dot (ray));
        const Eigen::Vector3d e = Eigen::Vector3d (t.x, t.y, t.z) - on_ray, along = ray.normalized ();
        EXPECT_LT ((e - e.dot (along) * along).norm (), 1e-6 * on_ray.norm ()) << "P is off its centre ray";
        acc.p += std::pow (e.dot (along), 2) / along.dot (t.covarianceP ().cast<double> () * along);
      }
      else
      {
        const Eigen::Vector3d e = Eigen::Vector3d (t.x, t.y, t.z) - p_true;
        acc.p += e.dot (t.covarianceP ().cast<double> ().ldlt ().solve (e));
      }
      // N's error in its own tangent frame.
      const Eigen::Matrix<double, 3, 2> tf = t.tangentFrame ().cast<double> ();
      const Eigen::Vector3d n_est (t.normal_x, t.normal_y, t.normal_z);
      const Eigen::Vector3d truth = n_true.dot (n_est) > 0 ? n_true : Eigen::Vector3d (-n_true);
      const Eigen::Vector2d en = -(tf.transpose () * truth);
      acc.n += en.dot (t.covarianceN ().cast<double> ().inverse () * en);
      ++acc.count;
    }
  }
  acc.p /= acc.count;
  acc.n /= acc.count;
  return acc;
}

double
relativeFrobenius (const Eigen::MatrixXd &a, const Eigen::MatrixXd &ref) { return (a - ref).norm () / ref.norm (); }

} // namespace

TEST (Uncertainty, MonteCarloCovariancesAreCalibrated)
{
  for (const TexletCentre centre : {TexletCentre::CentreRay, TexletCentre::InlierMean})
  {
    const Nees nees = meanNees (UncertaintyMethod::MonteCarlo, 200, centre);
    const double dof_p = centre == TexletCentre::CentreRay ? 1.0 : 3.0;
    ASSERT_GT (nees.count, 20000);
    // Degrees of freedom 1 or 3, and 2. With 50 samples the estimated covariance inflates the
    // expected NEES by 49/47 (P on the ray), 49/45 (P the mean) and 49/46 (N); 20 % covers that
    // and the sampling noise.
    EXPECT_NEAR (nees.p, dof_p, 0.2 * dof_p) << "mean NEES of P over " << nees.count << " texlets";
    EXPECT_NEAR (nees.n, 2.0, 0.4) << "mean NEES of N over " << nees.count << " texlets";
    std::cout << "Monte Carlo NEES, centre " << pcl::texlet::toString (centre) << ": P " << nees.p << " (dof " << dof_p
              << "), N " << nees.n << " (dof 2), " << nees.count << " texlets\n";
  }
}

TEST (Uncertainty, AnalyticCovariancesAreCalibrated)
{
  for (const TexletCentre centre : {TexletCentre::CentreRay, TexletCentre::InlierMean})
  {
    const Nees nees = meanNees (UncertaintyMethod::Analytic, 100, centre);
    const double dof_p = centre == TexletCentre::CentreRay ? 1.0 : 3.0;
    EXPECT_NEAR (nees.p, dof_p, 0.1 * dof_p);
    EXPECT_NEAR (nees.n, 2.0, 0.2);
    std::cout << "Analytic NEES, centre " << pcl::texlet::toString (centre) << ": P " << nees.p << " (dof " << dof_p
              << "), N " << nees.n << " (dof 2), " << nees.count << " texlets\n";
  }
}

TEST (Uncertainty, AnalyticAgreesWithMonteCarloOnPlanarPatches)
{
  const CameraSpec cam;
  const auto noise = pcl::texlet::NoiseModel::paper ();
  for (const PlaneFitMethod fit : {PlaneFitMethod::PCA, PlaneFitMethod::SVD, PlaneFitMethod::Averaging})
  {
    const Render r = render (wall (), cam, &noise, 77);
    pcl::PointCloud<pcl::Texlet> analytic, mc;
    for (auto [method, out] : {std::pair<UncertaintyMethod, pcl::PointCloud<pcl::Texlet> *>{UncertaintyMethod::Analytic, &analytic},
                               {UncertaintyMethod::MonteCarlo, &mc}})
    {
      pcl::TexletEstimation<pcl::PointXYZ> est;
      est.setInputCloud (r.cloud.makeShared ());
      est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (cam.pinhole ()));
      est.setSpacing (12);
      est.setPlaneFitMethod (fit);
      est.setUncertaintyMethod (method);
      est.setMonteCarloSamples (4000); // sampling error of the reference ~ sqrt(2/4000) = 2 %
      est.compute (*out);
    }
    double worst_p = 0, worst_n = 0;
    int n = 0;
    for (std::size_t i = 0; i < mc.size (); ++i)
    {
      if (!std::isfinite (mc[i].x))
        continue;
      ASSERT_TRUE (std::isfinite (analytic[i].x));
      worst_p = std::max (worst_p, relativeFrobenius (analytic[i].covarianceP ().cast<double> (),
                                                      mc[i].covarianceP ().cast<double> ()));
      worst_n = std::max (worst_n, relativeFrobenius (analytic[i].covarianceN ().cast<double> (),
                                                      mc[i].covarianceN ().cast<double> ()));
      ++n;
    }
    ASSERT_GT (n, 100);
    EXPECT_LT (worst_p, 0.15) << pcl::texlet::toString (fit);
    EXPECT_LT (worst_n, 0.15) << pcl::texlet::toString (fit);
    std::cout << pcl::texlet::toString (fit) << ": worst relative Frobenius difference over " << n
              << " texlets: Sigma_P " << worst_p << ", Sigma_N " << worst_n << "\n";
  }
}
