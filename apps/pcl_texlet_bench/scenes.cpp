/*
 * pcl_texlet_bench: simulated scenes with ground truth (see scenes.h).
 */
#include "scenes.h"

#include <pcl_texlet/camera/depth_image.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <limits>
#include <random>

namespace pcl_texlet_bench
{

namespace sim = pcl::texlet::sim;

const std::vector<std::string> &
sceneNames ()
{
  static const std::vector<std::string> names = {"plane", "sphere", "box"};
  return names;
}

SimulatedScene
simulateScene (const std::string &name, int width, int height, std::uint32_t seed)
{
  sim::SceneSetup setup;
  if (name == "plane")
    setup = sim::planeSetup (1.2, 20.0, 30.0);
  else if (name == "box")
    setup = sim::boxSetup (1.2, 45.0);
  else if (name == "sphere")
  {
    auto scene = std::make_shared<sim::Scene> ();
    scene->add (std::make_shared<sim::PlaneSurface> (Eigen::Vector3d (0, 0, 1.6), Eigen::Vector3d (0, 0, -1)));
    scene->add (std::make_shared<sim::SphereSurface> (Eigen::Vector3d (0, 0, 1.1), 0.25));
    setup.scene = scene;
    setup.sensor_poses = {Eigen::Isometry3d::Identity ()};
    setup.kind = "free";
  }
  else
    throw pcl::BadArgumentException ("unknown scene '" + name + "' (plane, sphere or box)");

  sim::SimulationSettings settings; // the paper's noise and projector shadows, no other effect
  settings.seed = seed;
  const sim::KinectSimulator simulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (width, height)),
                                        settings);
  const pcl::texlet::DepthFrame frame = simulator.simulateFrame (0, 0);
  SimulatedScene s;
  s.name = name;
  auto camera = std::make_shared<pcl::texlet::PinholeModel> (
      pcl::texlet::PinholeModel::fromCameraInfo (simulator.cameraInfo (0)));
  s.camera = camera;
  s.cloud = std::make_shared<Cloud> ();
  pcl::texlet::depthToCloud (frame, *camera, *s.cloud);
  const sim::SensorTruth &truth = simulator.truth (0);
  const std::size_t n = static_cast<std::size_t> (width) * height;
  s.truth_normal.assign (n, Eigen::Vector3f::Constant (std::numeric_limits<float>::quiet_NaN ()));
  s.truth_depth.assign (n, 0.0f);
  for (std::size_t i = 0; i < n; ++i)
    if (truth.depth_m[i] > 0.0f)
    {
      s.truth_depth[i] = truth.depth_m[i];
      s.truth_normal[i] = truth.normal[i];
    }
  return s;
}

std::vector<std::uint8_t>
edgePixels (const SimulatedScene &scene)
{
  const int w = static_cast<int> (scene.cloud->width), h = static_cast<int> (scene.cloud->height);
  std::vector<std::uint8_t> edge (static_cast<std::size_t> (w) * h, 0);
  const float cos30 = std::cos (30.0f * static_cast<float> (M_PI) / 180.0f);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * w + u;
      if (scene.truth_depth[i] <= 0.0f)
        continue;
      const int nu[4] = {u - 1, u + 1, u, u}, nv[4] = {v, v, v - 1, v + 1};
      for (int k = 0; k < 4 && !edge[i]; ++k)
      {
        if (nu[k] < 0 || nv[k] < 0 || nu[k] >= w || nv[k] >= h)
          continue;
        const std::size_t j = static_cast<std::size_t> (nv[k]) * w + nu[k];
        const bool no_reading = !std::isfinite ((*scene.cloud)[j].z);
        edge[i] = scene.truth_depth[j] <= 0.0f || no_reading ||
                  std::fabs (scene.truth_depth[j] - scene.truth_depth[i]) > 0.02f ||
                  scene.truth_normal[j].dot (scene.truth_normal[i]) < cos30;
      }
    }
  return edge;
}

std::vector<std::uint8_t>
nearEdge (const std::vector<std::uint8_t> &edges, int width, int height, const pcl::Indices &centres, int radius)
{
  const int n = pcl::texlet::kernels::pixelDiscSize (radius);
  std::vector<int> du (n), dv (n);
  pcl::texlet::kernels::pixelDiscOffsets (radius, du.data (), dv.data (), n);
  std::vector<std::uint8_t> near (centres.size (), 0);
  for (std::size_t c = 0; c < centres.size (); ++c)
  {
    const int cu = centres[c] % width, cv = centres[c] / width;
    for (int o = 0; o < n && !near[c]; ++o)
    {
      const int u = cu + du[o], v = cv + dv[o];
      if (u >= 0 && v >= 0 && u < width && v < height)
        near[c] = edges[static_cast<std::size_t> (v) * width + u];
    }
  }
  return near;
}

Cloud::Ptr
noisyPlane (int width, int height, double distance_m, double tilt_deg, double sigma_m, std::uint32_t seed,
            Eigen::Vector3f &normal)
{
  const double f = 525.0, cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
  const double a = tilt_deg * M_PI / 180.0;
  const Eigen::Vector3d n (0.0, std::sin (a), -std::cos (a)); // faces the camera
  const double d = n.dot (Eigen::Vector3d (0, 0, distance_m));
  normal = n.cast<float> ();
  auto cloud = std::make_shared<Cloud> (width, height);
  cloud->is_dense = true;
  std::mt19937 rng (seed);
  std::normal_distribution<double> gauss (0.0, 1.0);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
    {
      const Eigen::Vector3d r ((u - cx) / f, (v - cy) / f, 1.0);
      const double z = d / n.dot (r) + sigma_m * gauss (rng);
      (*cloud) (u, v).getVector3fMap () = (z * r).cast<float> ();
    }
  return cloud;
}

} // namespace pcl_texlet_bench
