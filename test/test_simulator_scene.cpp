/*
 * The simulator's geometry and configuration: exact depths of the ready-made scenes, meshes from
 * PLY and organised PCD files equal to the analytic scenes they describe, the BVH against brute
 * force, effects by name, and YAML configuration with its errors.
 */
#include <pcl_texlet/noise/effects/interference.h>
#include <pcl_texlet/noise/effects/radial.h>
#include <pcl_texlet/noise/effects/vertical_stripes.h>
#include <pcl_texlet/simulation/effects.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/simulation/simulation_config.h>
#include <pcl_texlet/simulation/triangle_mesh.h>

#include <pcl/conversions.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include "support/expect_error.h"
#include "support/temp_dir.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using pcl_texlet_test::expectError;
using namespace pcl::texlet;
using namespace pcl::texlet::sim;

namespace
{

SimulationSettings
noiseFree ()
{
  SimulationSettings s;
  s.base_noise = false;
  return s;
}

using SceneFiles = pcl_texlet_test::TempDirTest;

/** The 12 triangles of a box of \a size centred at \a centre, as a PolygonMesh. */
pcl::PolygonMesh
boxMesh (const Eigen::Vector3d &centre, const Eigen::Vector3d &size)
{
  pcl::PointCloud<pcl::PointXYZ> corners;
  for (int k = 0; k < 8; ++k)
  {
    const Eigen::Vector3d p = centre + 0.5 * Eigen::Vector3d ((k & 1) ? size.x () : -size.x (),
                                                              (k & 2) ? size.y () : -size.y (),
                                                              (k & 4) ? size.z () : -size.z ());
    corners.push_back (pcl::PointXYZ (p.x (), p.y (), p.z ()));
  }
  pcl::PolygonMesh mesh;
  pcl::toPCLPointCloud2 (corners, mesh.cloud);
  // Faces as quads (the loader fans them into triangles): -x, +x, -y, +y, -z, +z.
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto &q : quads)
  {
    pcl::Vertices v;
    v.vertices.assign (q, q + 4);
    mesh.polygons.push_back (v);
  }
  return mesh;
}

} // namespace

// ---------------------------------------------------------------------------------------------

TEST (SimulatorScene, TiltedWallDepthsLieOnThePlane)
{
  const double tilt_x = 20, tilt_y = -35, d = 1.4;
  const SceneSetup wall = planeSetup (d, tilt_x, tilt_y);
  const KinectSimulator sim (wall.scene, wall.sensors (DepthSensor::kinect ()), noiseFree ());
  const SensorTruth &t = sim.truth (0);
  const DepthSensor &s = sim.sensor (0);
  const Eigen::Vector3d n = (Eigen::AngleAxisd (tilt_x * M_PI / 180, Eigen::Vector3d::UnitX ()) *
                             Eigen::AngleAxisd (tilt_y * M_PI / 180, Eigen::Vector3d::UnitY ())) *
                            Eigen::Vector3d (0, 0, -1);
  EXPECT_NEAR (t.depth_m[240 * 640 + 320], d, 0.01); // near the axis
  for (int v = 0; v < 480; v += 7)
    for (int u = 0; u < 640; u += 7)
    {
      const std::size_t i = static_cast<std::size_t> (v) * 640 + u;
      ASSERT_GT (t.depth_m[i], 0.0f);
      const double z = t.depth_m[i];
      const Eigen::Vector3d p ((u - s.cx) / s.fx * z, (v - s.cy) / s.fy * z, z);
      EXPECT_NEAR (n.dot (p), n.dot (Eigen::Vector3d (0, 0, d)), 1e-6) << u << "," << v;
      EXPECT_NEAR (std::fabs (t.normal[i].cast<double> ().dot (n)), 1.0, 1e-6);
    }
}

TEST (SimulatorScene, BoxSceneHasThePapersBoxOnTheTable)
{
  const SceneSetup box = boxSetup (1.2, 40, 3);
  ASSERT_EQ (box.sensor_poses.size (), 3u);
  EXPECT_EQ (box.kind, "box");
  EXPECT_TRUE (box.box_size_m.isApprox (Eigen::Vector3d (0.128, 0.112, 0.240)));
  const KinectSimulator sim (box.scene, box.sensors (DepthSensor::kinect ()), noiseFree ());
  for (std::size_t k = 0; k < 3; ++k)
  {
    const DepthSensor &s = sim.sensor (k);
    // Sensors 120 degrees apart, 1.2 m from the box centre.
    EXPECT_NEAR ((s.cameraPosition () - Eigen::Vector3d (0, 0, 0.12)).norm (), 1.2, 1e-12);
    const SensorTruth &t = sim.truth (k);
    std::size_t top = 0, ground = 0, sides = 0;
    for (int v = 0; v < 480; ++v)
      for (int u = 0; u < 640; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * 640 + u;
        if (!(t.depth_m[i] > 0))
          continue;
        const double z = t.depth_m[i];
        const Eigen::Vector3d p = s.pose * Eigen::Vector3d ((u - s.cx) / s.fx * z, (v - s.cy) / s.fy * z, z);
        if (std::fabs (p.z () - 0.240) < 1e-5)
        {
          ++top;
          EXPECT_LE (std::fabs (p.x ()), 0.064 + 1e-5);
          EXPECT_LE (std::fabs (p.y ()), 0.056 + 1e-5);
        }
        else if (std::fabs (p.z ()) < 1e-5)
          ++ground;
        else
        {
          ++sides;
          EXPECT_TRUE (std::fabs (std::fabs (p.x ()) - 0.064) < 1e-5 || std::fabs (std::fabs (p.y ()) - 0.056) < 1e-5)
              << "side point " << p.transpose ();
        }
      }
    EXPECT_GT (top, 1000u) << "sensor " << k;
    EXPECT_GT (ground, 50000u);
    EXPECT_GT (sides, 1000u);
  }
}

TEST_F (SceneFiles, PlyMeshRendersLikeTheAnalyticBox)
{
  const Eigen::Vector3d size (0.128, 0.112, 0.240);
  ASSERT_EQ (pcl::io::savePLYFile (file ("box.ply"), boxMesh (Eigen::Vector3d (0, 0, 0.12), size)), 0);
  const TriangleMeshSurface mesh = loadTriangleMesh (file ("box.ply"));
  EXPECT_EQ (mesh.triangleCount (), 12u);

  const SceneSetup analytic = boxSetup (1.2, 40, 2);
  auto scene = std::make_shared<Scene> ();
  scene->add (analytic.scene->surfaces ()[0]); // the table
  scene->add (std::make_shared<TriangleMeshSurface> (mesh));
  const auto sensors = analytic.sensors (DepthSensor::kinect (320, 240));
  const KinectSimulator a (analytic.scene, sensors, noiseFree ()), b (scene, sensors, noiseFree ());
  for (std::size_t k = 0; k < 2; ++k)
  {
    const SensorTruth &ta = a.truth (k), &tb = b.truth (k);
    std::size_t box_pixels = 0;
    for (std::size_t i = 0; i < ta.depth_m.size (); ++i)
    {
      EXPECT_NEAR (ta.depth_m[i], tb.depth_m[i], 1e-6) << "sensor " << k << " pixel " << i;
      EXPECT_EQ (ta.lit[i], tb.lit[i]) << "shadows agree, sensor " << k << " pixel " << i;
      // On the box: a normal other than the table's (scene +z, turned into the camera frame).
      const Eigen::Vector3f table = (a.sensor (k).pose.linear ().transpose () * Eigen::Vector3d::UnitZ ()).cast<float> ();
      box_pixels += ta.depth_m[i] > 0 && std::fabs (ta.normal[i].dot (table)) < 0.99f;
    }
    EXPECT_GT (box_pixels, 100u);
    EXPECT_EQ (a.simulateFrame (k, 0).depth_mm, b.simulateFrame (k, 0).depth_mm);
  }
}

TEST_F (SceneFiles, OrganisedPcdIsTriangulatedOverItsPixelGrid)
{
  // A wall at 1.2 m seen by a 64x48 camera, with a foreground patch 20 cm nearer: the step
  // between them must not be bridged.
  pcl::PointCloud<pcl::PointXYZ> cloud (64, 48);
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u)
    {
      const double z = (u >= 20 && u < 40 && v >= 15 && v < 30) ? 1.0 : 1.2;
      cloud (u, v) = pcl::PointXYZ ((u - 31.5) / 60.0 * z, (v - 23.5) / 60.0 * z, z);
    }
  cloud (5, 5).x = std::numeric_limits<float>::quiet_NaN (); // a hole
  ASSERT_EQ (pcl::io::savePCDFileBinary (file ("wall.pcd"), cloud), 0);
  const TriangleMeshSurface mesh = loadTriangleMesh (file ("wall.pcd"));
  // 63 x 47 cells, two triangles each, minus the six touching the hole and the ones bridging
  // the step along the patch's border.
  EXPECT_LT (mesh.triangleCount (), 2u * 63 * 47 - 8);
  EXPECT_GT (mesh.triangleCount (), 2u * 63 * 47 - 300);

  Scene scene;
  scene.add (std::make_shared<TriangleMeshSurface> (mesh));
  SurfaceHit hit;
  // Through the middle of the patch and of the wall: the depths of the cloud.
  ASSERT_TRUE (scene.intersect (Eigen::Vector3d::Zero (), Eigen::Vector3d ((30 - 31.5) / 60.0, (22 - 23.5) / 60.0, 1),
                                1e-9, 1e9, hit));
  EXPECT_NEAR (hit.t, 1.0, 1e-6);
  ASSERT_TRUE (scene.intersect (Eigen::Vector3d::Zero (), Eigen::Vector3d ((50 - 31.5) / 60.0, (10 - 23.5) / 60.0, 1),
                                1e-9, 1e9, hit));
  EXPECT_NEAR (hit.t, 1.2, 1e-6);
  // Between the patch's last column (1.0 m) and the wall's first (1.2 m) there is no surface: a
  // bridge would be hit there.
  EXPECT_FALSE (scene.intersect (Eigen::Vector3d::Zero (),
                                 Eigen::Vector3d ((39.5 - 31.5) / 60.0, (22 - 23.5) / 60.0, 1), 1e-9, 1e9, hit));
}

TEST_F (SceneFiles, MeshLoaderErrorsNameTheFile)
{
  expectError<pcl::IOException> ([&] { loadTriangleMesh (file ("missing.ply")); }, {"missing.ply': does not exist"});
  std::ofstream (file ("model.xyz")) << "1 2 3\n";
  expectError<pcl::IOException> ([&] { loadTriangleMesh (file ("model.xyz")); }, {"unknown extension '.xyz'"});
  std::ofstream (file ("junk.ply")) << "not a ply file\n";
  expectError<pcl::IOException> ([&] { loadTriangleMesh (file ("junk.ply")); }, {"junk.ply"});
  pcl::PointCloud<pcl::PointXYZ> flat;
  flat.push_back (pcl::PointXYZ (0, 0, 1));
  flat.push_back (pcl::PointXYZ (1, 0, 1));
  flat.push_back (pcl::PointXYZ (0, 1, 1));
  ASSERT_EQ (pcl::io::savePCDFileASCII (file ("points.pcd"), flat), 0);
  expectError<pcl::IOException> ([&] { loadTriangleMesh (file ("points.pcd")); }, {"unorganised"});
  // A PLY of points only has nothing to hit.
  ASSERT_EQ (pcl::io::savePLYFile (file ("points.ply"), flat), 0);
  expectError<pcl::IOException> ([&] { loadTriangleMesh (file ("points.ply")); }, {"no faces"});
}

TEST (SimulatorScene, BvhFindsTheSameHitsAsBruteForce)
{
  std::mt19937 rng (3);
  std::uniform_real_distribution<double> uni (-1.0, 1.0);
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  for (int k = 0; k < 4000; ++k)
  {
    const Eigen::Vector3d c (uni (rng), uni (rng), 2.0 + uni (rng));
    const int i = static_cast<int> (vertices.size ());
    for (int j = 0; j < 3; ++j)
      vertices.push_back (c + 0.08 * Eigen::Vector3d (uni (rng), uni (rng), uni (rng)));
    triangles.push_back ({i, i + 1, i + 2});
  }
  const TriangleMeshSurface mesh (vertices, triangles);
  EXPECT_LE (mesh.bvhDepth (), 14);
  int hits = 0;
  for (int r = 0; r < 3000; ++r)
  {
    const Eigen::Vector3d origin (0.2 * uni (rng), 0.2 * uni (rng), 0.0);
    const Eigen::Vector3d direction (0.6 * uni (rng), 0.6 * uni (rng), 1.0);
    SurfaceHit a, b;
    const bool ha = mesh.intersect (origin, direction, 1e-9, a);
    const bool hb = mesh.intersectBruteForce (origin, direction, 1e-9, b);
    ASSERT_EQ (ha, hb) << "ray " << r;
    if (ha)
    {
      ++hits;
      EXPECT_EQ (a.t, b.t) << "ray " << r;
      EXPECT_TRUE (a.normal.isApprox (b.normal)) << "ray " << r;
    }
  }
  EXPECT_GT (hits, 1000);
}

TEST (SimulatorScene, BadGeometryIsRejected)
{
  expectError<pcl::BadArgumentException> ([] { planeSetup (0.0, 0, 0); }, {"distance"});
  expectError<pcl::BadArgumentException> ([] { planeSetup (1.0, 95, 0); }, {"tilt x"});
  expectError<pcl::BadArgumentException> ([] { boxSetup (1.0, 0, 1); }, {"elevation"});
  expectError<pcl::BadArgumentException> ([] { boxSetup (1.0, 30, 0); }, {"number of sensors"});
  expectError<pcl::BadArgumentException> (
      [] { TriangleMeshSurface (std::vector<Eigen::Vector3d> (3, Eigen::Vector3d::Zero ()), {{0, 1, 2}}); },
      {"no triangle with a non-zero area"});
  expectError<pcl::BadArgumentException> (
      [] { TriangleMeshSurface ({Eigen::Vector3d::Zero (), Eigen::Vector3d::UnitX (), Eigen::Vector3d::UnitY ()}, {{0, 1, 3}}); },
      {"refers to vertex 3"});
  const SceneSetup wall = planeSetup (1.0, 0, 0);
  DepthSensor bad = DepthSensor::kinect ();
  bad.max_depth_m = 70.0;
  expectError<pcl::BadArgumentException> ([&] { KinectSimulator (wall.scene, {bad}, noiseFree ()); }, {"65.535"});
  bad = DepthSensor::kinect ();
  bad.fx = -1;
  expectError<pcl::BadArgumentException> ([&] { KinectSimulator (wall.scene, {bad}, noiseFree ()); }, {"sensor 0"});
  SimulationSettings s = noiseFree ();
  effects::VerticalStripes::SimParameters no_bands;
  no_bands.bands = 0; // past setEffectParameter's check: the simulator must check it too
  s.effects.set<effects::VerticalStripes> (no_bands, false);
  expectError<pcl::BadArgumentException> ([&] { KinectSimulator (wall.scene, {DepthSensor::kinect ()}, s); },
                                          {"vertical_stripes': parameter bands"});
}

// ---------------------------------------------------------------------------------------------

TEST (SimulatorEffects, CatalogueFollowsTheDesignVocabulary)
{
  const std::vector<std::string> expected = {"axial_quadratic", "radial",        "disparity_quantization",
                                             "incidence_angle", "vertical_stripes", "depth_distortion",
                                             "interference",    "temporal_drift", "lateral_noise",
                                             "intrinsics",      "covariate:intensity", "rows",
                                             "spatial_correlation"};
  std::vector<std::string> names;
  for (const auto &e : effectCatalogue ())
  {
    names.push_back (e.name);
    // Terms built from the data (named by the residual structure they take off: rows,
    // spatial_correlation, or a covariate with a colon) have no generative form.
    const bool structure =
        e.name == "rows" || e.name == "spatial_correlation" || e.name.find (':') != std::string::npos;
    EXPECT_EQ (e.simulated, !structure) << e.name;
    EXPECT_EQ (e.parameters.empty (), !e.simulated) << e.name;
    for (const auto &p : e.parameters)
      EXPECT_FALSE (p.unit.empty ()) << e.name << "." << p.name;
  }
  EXPECT_EQ (names, expected);
  SensorEffects fx;
  EXPECT_TRUE (enabledEffects (fx).empty ()) << "all off by default";
  setEffectEnabled (fx, "interference", true);
  setEffectParameter (fx, "interference", "blob_px", 3);
  setEffectParameter (fx, "vertical_stripes", "offset_px", 0.25);
  EXPECT_EQ (fx.parameters<effects::Interference> ().blob_px, 3);
  EXPECT_EQ (fx.parameters<effects::VerticalStripes> ().offset_px, 0.25);
  EXPECT_EQ (effectParameter (fx, "vertical_stripes", "offset_px"), 0.25);
  EXPECT_EQ (enabledEffects (fx), std::vector<std::string> ({"interference"}));
  expectError<pcl::BadArgumentException> ([&] { setEffectEnabled (fx, "speckle", true); },
                                          {"unknown effect 'speckle'"});
  expectError<pcl::BadArgumentException> ([&] { setEffectEnabled (fx, "covariate:intensity", true); },
                                          {"covariate:intensity", "the simulator cannot draw it"});
  expectError<pcl::BadArgumentException> ([&] { setEffectParameter (fx, "radial", "sigma", 1); },
                                          {"has no parameter 'sigma' (its parameters: gain, reference_radius_px)"});
  expectError<pcl::BadArgumentException> ([&] { setEffectParameter (fx, "vertical_stripes", "bands", 2.5); },
                                          {"a whole number"});
  expectError<pcl::BadArgumentException> ([&] { setEffectParameter (fx, "incidence_angle", "max_angle_deg", 120); },
                                          {"in (0, 90]"});
  expectError<pcl::BadArgumentException> ([&] { applyEffectAssignment ("radial.gain", fx); },
                                          {"effect.parameter=value"});
  expectError<pcl::BadArgumentException> ([&] { applyEffectAssignment ("radial.gain=abc", fx); }, {"not a number"});
  applyEffectAssignment ("radial.gain=0.75", fx);
  EXPECT_EQ (fx.parameters<effects::Radial> ().gain, 0.75);
  EXPECT_FALSE (fx.isEnabled<effects::Radial> ()) << "setting a parameter does not switch the effect on";
}

TEST_F (SceneFiles, YamlConfigurationAndItsErrors)
{
  SimulationSettings s;
  parseSimulationConfig ("base_noise: none\n"
                         "projector_shadows: false\n"
                         "effects:\n"
                         "  disparity_quantization: true\n"
                         "  vertical_stripes: {bands: 8, offset_px: 0.0625}\n"
                         "  incidence_angle: {enabled: false, gain: 2}\n"
                         "  radial:\n",
                         s);
  EXPECT_FALSE (s.base_noise);
  EXPECT_FALSE (s.projector_shadows);
  EXPECT_EQ (enabledEffects (s.effects),
             std::vector<std::string> ({"radial", "disparity_quantization", "vertical_stripes"}));
  EXPECT_EQ (effectParameter (s.effects, "vertical_stripes", "bands"), 8);
  EXPECT_EQ (effectParameter (s.effects, "vertical_stripes", "offset_px"), 0.0625);
  EXPECT_EQ (effectParameter (s.effects, "incidence_angle", "gain"), 2.0);

  const SimulationSettings before = s;
  const auto rejected = [&] (const std::string &yaml, const std::string &needle) {
    SimulationSettings t = before;
    expectError<pcl::IOException> ([&] { parseSimulationConfig (yaml, t, "test.yaml"); }, {needle});
    EXPECT_EQ (enabledEffects (t.effects), enabledEffects (before.effects)) << "a bad file changes nothing";
  };
  rejected ("effects: {speckle: true}", "test.yaml: unknown effect 'speckle'");
  rejected ("effects: {radial: {gian: 1}}", "effect 'radial' has no parameter 'gian'");
  rejected ("effects: {radial: {gain: -1}}", "parameter gain must be >= 0 (got -1)");
  rejected ("effects: {radial: {gain: lots}}", "effects.radial.gain must be a number (found 'lots')");
  rejected ("effects: {radial: maybe}", "effects.radial must be true or false");
  rejected ("base_noise: loud", "base_noise must be 'paper' or 'none'");
  rejected ("efects: {}", "unknown key 'efects'");
  rejected ("effects: [radial]", "effects must be a map");
  rejected ("effects: {radial: true", "not valid YAML");

  std::ofstream (file ("effects.yaml")) << "effects:\n  temporal_drift: {amplitude_px: 0.3}\n";
  SimulationSettings fromFile;
  loadSimulationConfig (file ("effects.yaml"), fromFile);
  EXPECT_TRUE (isEffectEnabled (fromFile.effects, "temporal_drift"));
  EXPECT_EQ (effectParameter (fromFile.effects, "temporal_drift", "amplitude_px"), 0.3);
  expectError<pcl::IOException> ([&] { loadSimulationConfig (file ("nope.yaml"), fromFile); },
                                 {"nope.yaml': does not exist"});
}
