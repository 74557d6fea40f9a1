#include "studies.h"

#include <pcl_texlet/camera/camera_model.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/noise/effects/intrinsics.h>

#include <Eigen/Eigenvalues>

void
pcl_texlet_sensor_figures::measureIntrinsics (Figures &figures)
{
  const effects::Intrinsics::SimParameters p;
  SimulationSettings s = figures.settings ();
  setEffectEnabled (s.effects, effects::Intrinsics::kName, true);
  const auto cloud = [&] (const KinectSimulator &sim, const DepthFrame &f, const CameraModel &cam) {
    std::vector<Eigen::Vector3d> points (f.depth_mm.size (), Eigen::Vector3d::Constant (kNaN));
    for (int v = 0; v < f.height; ++v)
      for (int u = 0; u < f.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * f.width + u;
        if (f.depth_mm[i] == 0)
          continue;
        double x, y;
        cam.pixelToRay (u, v, x, y);
        const double z = 1e-3 * f.depth_mm[i];
        points[i] = Eigen::Vector3d (x * z, y * z, z);
      }
    (void) sim;
    return points;
  };
  const auto tiltOf = [] (const std::vector<Eigen::Vector3d> &points) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero ();
    int n = 0;
    for (const auto &q : points)
      if (q.allFinite ())
      {
        mean += q;
        ++n;
      }
    mean /= n;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero ();
    for (const auto &q : points)
      if (q.allFinite ())
        cov += (q - mean) * (q - mean).transpose ();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es (cov);
    const Eigen::Vector3d normal = es.eigenvectors ().col (0);
    return std::acos (std::min (1.0, std::fabs (normal.z ()))) * 180.0 / M_PI;
  };

  // Lateral error along the central row of a frontal wall.
  {
    const KinectSimulator sim = figures.simulator (planeSetup (1.5, 0, 0), s);
    const PinholeModel labelled = PinholeModel::fromCameraInfo (sim.cameraInfo (0));
    const PinholeModel truth (figures.sensor ().fx, figures.sensor ().fy, figures.sensor ().cx, figures.sensor ().cy);
    const DepthFrame f = sim.simulateFrame (0, 0);
    const auto a = cloud (sim, f, labelled), b = cloud (sim, f, truth);
    const int row = static_cast<int> (std::lround (figures.sensor ().cy));
    std::ostringstream out;
    out << "# u_px x_true_m x_labelled_m x_error_mm model_error_mm   (frontal wall at 1.5 m, row " << row
        << "; camera.yaml fx = " << num (labelled.fx ()) << " px, rendered with " << num (figures.sensor ().fx)
        << " px)\n"
        << "# model: x (1 / focal_scale - 1)\n";
    double max_err = 0;
    for (int u = 0; u < f.width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (row) * f.width + u;
      if (!a[i].allFinite ())
        continue;
      const double err = 1000.0 * (a[i].x () - b[i].x ());
      out << u << " " << num (b[i].x ()) << " " << num (a[i].x ()) << " " << num (err) << " "
          << num (1000.0 * b[i].x () * (1.0 / p.focal_scale - 1.0)) << "\n";
      max_err = std::max (max_err, std::fabs (err));
    }
    figures.write ("intrinsics_row.dat", out.str ());
    figures.note (effects::Intrinsics::kName, "labelled_fx_px", labelled.fx ());
    figures.note (effects::Intrinsics::kName, "max_lateral_error_mm_at_1.5m", max_err);
    figures.note (effects::Intrinsics::kName, "lateral_scale_percent", 100.0 * (1.0 / p.focal_scale - 1.0));
  }
  // The fitted tilt of walls turned about the image y axis.
  std::ostringstream out;
  out << "# tilt_deg fitted_true_intrinsics_deg fitted_labelled_deg model_labelled_deg   (wall at 1.5 m, frame 0; "
         "focal_scale "
      << p.focal_scale << ")\n# model: atan(focal_scale tan(tilt))\n";
  for (const double tilt : {0.0, 10.0, 20.0, 30.0, 40.0, 45.0, 50.0, 60.0, 70.0})
  {
    const KinectSimulator sim = figures.simulator (planeSetup (1.5, 0, tilt), s);
    const PinholeModel labelled = PinholeModel::fromCameraInfo (sim.cameraInfo (0));
    const PinholeModel truth (figures.sensor ().fx, figures.sensor ().fy, figures.sensor ().cx, figures.sensor ().cy);
    const DepthFrame f = sim.simulateFrame (0, 0);
    const double fitted_true = tiltOf (cloud (sim, f, truth)), fitted_labelled = tiltOf (cloud (sim, f, labelled));
    const double model = std::atan (p.focal_scale * std::tan (tilt * M_PI / 180.0)) * 180.0 / M_PI;
    out << num (tilt) << " " << num (fitted_true) << " " << num (fitted_labelled) << " " << num (model) << "\n";
    if (tilt == 45.0)
    {
      figures.note (effects::Intrinsics::kName, "fitted_tilt_true_deg_at_45", fitted_true);
      figures.note (effects::Intrinsics::kName, "fitted_tilt_labelled_deg_at_45", fitted_labelled);
      figures.note (effects::Intrinsics::kName, "model_tilt_labelled_deg_at_45", model);
    }
  }
  figures.write ("intrinsics_tilt.dat", out.str ());
}
