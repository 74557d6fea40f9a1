/*
 * pcl_texlet_sim end to end: recordings of each scene that the recording reader takes, the
 * same bytes for the same seed, configuration files, and bad input (exit code 2, one line on
 * stderr, no output left behind).
 */
#include <pcl_texlet/io/recording_folder_reader.h>

#include <pcl/conversions.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include "support/app_test.h"
#include "support/temp_dir.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace
{

using pcl_texlet_test::slurp;

class SimApp : public pcl_texlet_test::AppTest
{
protected:
  SimApp () : AppTest (SIM_APP) {}
};

} // namespace

TEST_F (SimApp, HelpAndEffectList)
{
  Result r = run ("--help");
  EXPECT_EQ (r.code, 0);
  for (const char *option : {"--scene", "--effect", "--set", "--config", "--projectors", "--fx", "--seed"})
    EXPECT_NE (r.out.find (option), std::string::npos) << option;
  r = run ("--list-effects");
  EXPECT_EQ (r.code, 0);
  for (const char *name : {"axial_quadratic", "radial", "disparity_quantization", "incidence_angle", "vertical_stripes",
                           "depth_distortion", "interference", "temporal_drift", "lateral_noise", "intrinsics"})
    EXPECT_NE (r.out.find (name), std::string::npos) << name;
}

TEST_F (SimApp, PlaneRecordingIsReadableAndTheSameForTheSameSeed)
{
  const std::string common = "--scene plane --distance 1.5 --tilt-x 20 --frames 4 --effect vertical_stripes "
                             "--effect disparity_quantization --seed 7 --width 320 --height 240 ";
  Result r = run (common + "-j 1 " + (dir_ / "a").string ());
  ASSERT_EQ (r.code, 0) << r.err;
  EXPECT_NE (r.out.find ("disparity_quantization, vertical_stripes"), std::string::npos) << r.out;
  r = run (common + "-j 2 " + (dir_ / "b").string ());
  ASSERT_EQ (r.code, 0) << r.err;
  EXPECT_EQ (leftovers (), std::vector<std::string> ({"a", "b"})) << "no temporary folder is left";

  pcl::texlet::RecordingFolderReader reader ((dir_ / "a").string ());
  ASSERT_EQ (reader.size (), 4u);
  EXPECT_EQ (reader.cameraInfo ().width, 320);
  EXPECT_DOUBLE_EQ (reader.cameraInfo ().fx (), 290.0);
  pcl::texlet::DepthFrame f;
  ASSERT_TRUE (reader.next (f));
  EXPECT_EQ (f.name, "000000");
  // The wall is tilted 20 degrees about the image x axis: depth changes down the image.
  EXPECT_NE (f.depth_mm[10 * 320 + 160], f.depth_mm[230 * 320 + 160]);
  EXPECT_GT (f.depth_mm[120 * 320 + 160], 1400);
  EXPECT_LT (f.depth_mm[120 * 320 + 160], 1600);
  for (int k = 0; k < 4; ++k)
  {
    const std::string name = "depth/00000" + std::to_string (k) + ".png";
    EXPECT_EQ (slurp (dir_ / "a" / name), slurp (dir_ / "b" / name)) << name << ": same seed, same bytes";
  }
  const std::string meta = slurp (dir_ / "a" / "meta.yaml");
  for (const char *needle : {"scene: plane", "tilt_x_deg: 20", "projectors: 1", "seed: 7", "vertical_stripes:",
                             "disparity_quantization: {step_px: 0.125}"})
    EXPECT_NE (meta.find (needle), std::string::npos) << needle << "\n" << meta;
}

TEST_F (SimApp, BoxWithThreeProjectorsRecordsEverySensor)
{
  const Result r = run ("--scene box --projectors 3 --record all --frames 2 --width 160 --height 120 "
                        "--effect interference " + (dir_ / "box").string ());
  ASSERT_EQ (r.code, 0) << r.err;
  for (int k = 0; k < 3; ++k)
  {
    const fs::path rec = dir_ / "box" / ("sensor_" + std::to_string (k));
    pcl::texlet::RecordingFolderReader reader (rec.string ());
    EXPECT_EQ (reader.size (), 2u);
    const std::string meta = slurp (rec / "meta.yaml");
    for (const std::string needle : {std::string ("scene: box"), std::string ("projectors: 3"),
                                     "sensor: " + std::to_string (k), std::string ("box_size_m: [0.128, 0.112, 0.24]"),
                                     std::string ("interference: {noise_gain: 1, dropout_rate: 0.1, blob_px: 4}")})
      EXPECT_NE (meta.find (needle), std::string::npos) << needle << "\n" << meta;
  }
  EXPECT_EQ (leftovers (), std::vector<std::string> ({"box"}));
}

TEST_F (SimApp, PosesPlaceTheSensors)
{
  const std::string identity = " --pose 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1";
  const std::string aside = " --pose 1 0 0 0.2 0 1 0 0 0 0 1 0 0 0 0 1";
  const Result r = run ("--frames 1 --width 160 --height 120 --record all" + identity + aside + " " +
                        (dir_ / "rec").string ());
  ASSERT_EQ (r.code, 0) << r.err;
  const std::string meta = slurp (dir_ / "rec" / "sensor_1" / "meta.yaml");
  EXPECT_NE (meta.find ("sensor_pose: [1, 0, 0, 0.2, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]"), std::string::npos) << meta;
  EXPECT_NE (meta.find ("projectors: 2"), std::string::npos) << meta;
  // A frontal wall seen from 20 cm to the side: the same depths, shifted in the image.
  pcl::texlet::RecordingFolderReader a ((dir_ / "rec" / "sensor_0").string ()), b ((dir_ / "rec" / "sensor_1").string ());
  pcl::texlet::DepthFrame fa, fb;
  ASSERT_TRUE (a.next (fa));
  ASSERT_TRUE (b.next (fb));
  EXPECT_NEAR (fa.depth_mm[60 * 160 + 80], 1500, 10);
  EXPECT_NEAR (fb.depth_mm[60 * 160 + 80], 1500, 10);
}

TEST_F (SimApp, ConfigFileThenEffectsThenSettings)
{
  std::ofstream (dir_ / "effects.yaml") << "base_noise: none\neffects:\n  temporal_drift: {amplitude_px: 0.3}\n"
                                          "  radial: {enabled: false, gain: 0.9}\n";
  const Result r = run ("--config " + (dir_ / "effects.yaml").string () +
                        " --effect radial --set radial.reference_radius_px=200 --frames 1 --width 160 --height 120 " +
                        (dir_ / "rec").string ());
  ASSERT_EQ (r.code, 0) << r.err;
  const std::string meta = slurp (dir_ / "rec" / "meta.yaml");
  for (const char *needle : {"base_noise: none", "temporal_drift: {amplitude_px: 0.3, time_constant_frames: 10}",
                             "radial: {gain: 0.9, reference_radius_px: 200}"})
    EXPECT_NE (meta.find (needle), std::string::npos) << needle << "\n" << meta;
}

TEST_F (SimApp, MeshScene)
{
  // A 30 cm cube as twelve triangles, in millimetres.
  pcl::PointCloud<pcl::PointXYZ> corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back (pcl::PointXYZ ((k & 1) ? 150 : -150, (k & 2) ? 150 : -150, (k & 4) ? 150 : -150));
  pcl::PolygonMesh mesh;
  pcl::toPCLPointCloud2 (corners, mesh.cloud);
  const int tris[12][3] = {{0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}, {0, 4, 5}, {0, 5, 1},
                           {2, 3, 7}, {2, 7, 6}, {0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}};
  for (const auto &t : tris)
  {
    pcl::Vertices v;
    v.vertices.assign (t, t + 3);
    mesh.polygons.push_back (v);
  }
  ASSERT_EQ (pcl::io::savePLYFile ((dir_ / "cube.ply").string (), mesh), 0);
  const Result r = run ("--scene mesh --mesh " + (dir_ / "cube.ply").string () +
                        " --mesh-scale 0.001 --distance 1.2 --tilt-y 30 --frames 1 --width 160 --height 120 --base-noise none " +
                        (dir_ / "rec").string ());
  ASSERT_EQ (r.code, 0) << r.err;
  pcl::texlet::RecordingFolderReader reader ((dir_ / "rec").string ());
  pcl::texlet::DepthFrame f;
  ASSERT_TRUE (reader.next (f));
  // The cube's centre is 1.2 m ahead; the front faces are 15 cm to 21 cm nearer.
  const int centre = f.depth_mm[60 * 160 + 80];
  EXPECT_GT (centre, 990);
  EXPECT_LT (centre, 1060);
  EXPECT_EQ (f.depth_mm[5 * 160 + 5], 0) << "nothing but the cube in the scene";
  EXPECT_NE (slurp (dir_ / "rec" / "meta.yaml").find ("scene: free"), std::string::npos);
}

TEST_F (SimApp, BadInputIsRejectedWithOneLineAndLeavesNothing)
{
  const std::string out = (dir_ / "out").string ();
  expectRejected ("--effect speckle " + out, "unknown effect 'speckle'");
  expectRejected ("--set radial.gain=-2 " + out, "parameter gain must be >= 0");
  expectRejected ("--set radial " + out, "effect.parameter=value");
  expectRejected ("--scene mesh " + out, "--scene mesh needs --mesh");
  expectRejected ("--scene mesh --mesh " + (dir_ / "missing.ply").string () + " " + out, "missing.ply': does not exist");
  expectRejected ("--scene foo " + out, "--scene");
  expectRejected ("--scene box --tilt-x 10 " + out, "--tilt-x");
  expectRejected ("--frames 0 " + out, "--frames");
  expectRejected ("--record 2 " + out, "--record");
  expectRejected ("--width 0 " + out, "image size 0x480");
  expectRejected ("--distance -1 " + out, "distance must be positive");
  expectRejected ("--config " + (dir_ / "none.yaml").string () + " " + out, "none.yaml': does not exist");
  std::ofstream (dir_ / "bad.yaml") << "effects: {radial: {gian: 1}}\n";
  expectRejected ("--config " + (dir_ / "bad.yaml").string () + " " + out, "has no parameter 'gian'");
  expectRejected ("--pose 1 0 0 0 0 2 0 0 0 0 1 0 0 0 0 1 " + out, "the pose must be a finite rigid transform");
  expectRejected ("--projectors 2 --pose 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 " + out, "disagrees with the 1 --pose");
  expectRejected ("", "OUTPUT is required");
  expectRejected ((dir_ / "no" / "such" / "out").string (), "does not exist");
  fs::create_directories (dir_ / "taken");
  expectRejected ((dir_ / "taken").string (), "already exists");
  EXPECT_TRUE (fs::is_empty (dir_ / "taken"));
}
