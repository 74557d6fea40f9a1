/*
 * The disparity lattice from depth values (lab/disparity_lattice.h), against lattices of known
 * constant: closed-form values, the simulator's quantised frames, and walls of the independent
 * generator (test/generators/independent_walls.py) whose lattice differs from camera.yaml's.
 */
#include "support/app_run.h"
#include "support/temp_dir.h"

#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/png_image.h>
#include <pcl_texlet/io/tiff_image.h>
#include <pcl_texlet/lab/disparity_lattice.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pcl::texlet;

namespace
{

// camera.yaml's constant for f = 576 px, b = 0.075 m, 1/8 px: 1000 * 43.2 / 0.125 mm.
constexpr double kCameraConstantMm = 345600.0;

/** Whole-millimetre depths of the lattice C / (k + phase) from \a near_mm to \a far_mm, each
  * lattice point \a repeats times (a wall's pixels), with a few lattice points left out.
  */
std::vector<std::uint16_t>
latticeDepths (double c, double phase, double near_mm, double far_mm, unsigned seed)
{
  std::mt19937 rng (seed);
  std::bernoulli_distribution keep (0.8);
  std::vector<std::uint16_t> out;
  for (int k = static_cast<int> (c / far_mm); k <= static_cast<int> (c / near_mm); ++k)
    if (keep (rng))
      out.insert (out.end (), 3, static_cast<std::uint16_t> (std::lround (c / (k + phase))));
  return out;
}

class LatticeScale : public ::testing::TestWithParam<double>
{};

TEST_P (LatticeScale, ConstantAndPhaseOfClosedFormDepthsAreRecovered)
{
  // The lattice differs from camera.yaml's by 5 to 28 % either way (a real Kinect's is about
  // 1.22 times what its calibrated f b implies).
  const double c = GetParam () * kCameraConstantMm, phase = 0.3;
  const lab::DisparityLattice l = lab::fitDisparityLattice (latticeDepths (c, phase, 800, 3500, 7), kCameraConstantMm);
  ASSERT_TRUE (l.found) << "coherence " << l.coherence;
  EXPECT_NEAR (l.constant_mm / c, 1.0, 1e-3); // the whole-mm rounding limits it
  EXPECT_NEAR (l.phase, phase, 0.05);
  EXPECT_GT (l.coherence, 0.9);
  EXPECT_EQ (l.camera_constant_mm, kCameraConstantMm);
}

INSTANTIATE_TEST_SUITE_P (FiveToTwentyEightPercent, LatticeScale, ::testing::Values (0.75, 0.95, 1.05, 1.22, 1.28));

TEST (DisparityLattice, TheCoarsestLatticeIsTakenNotItsMultiple)
{
  // C = 0.72 camera: 2 C = 1.44 camera is inside the search range and fits every value too.
  const double c = 0.72 * kCameraConstantMm;
  const lab::DisparityLattice l = lab::fitDisparityLattice (latticeDepths (c, 0.0, 700, 3000, 3), kCameraConstantMm);
  ASSERT_TRUE (l.found);
  EXPECT_NEAR (l.constant_mm / c, 1.0, 1e-3);
}

TEST (DisparityLattice, EveryMillimetreIsNoLattice)
{
  std::vector<std::uint16_t> all;
  for (int z = 600; z <= 4000; ++z)
    all.push_back (static_cast<std::uint16_t> (z));
  const lab::DisparityLattice l = lab::fitDisparityLattice (all, kCameraConstantMm);
  EXPECT_FALSE (l.found) << "C " << l.constant_mm << " coherence " << l.coherence;
  EXPECT_LT (l.coherence, 0.3);
}

TEST (DisparityLattice, BadInputIsNamed)
{
  EXPECT_THROW (lab::fitDisparityLattice (std::vector<std::uint16_t>{1000, 1010}, 0.0), pcl::BadArgumentException);
  EXPECT_THROW (lab::fitDisparityLattice (std::vector<std::uint16_t>{1000, 1010}, std::nan ("")),
                pcl::BadArgumentException);
  EXPECT_THROW (lab::fitDisparityLattice (std::vector<lab::RecordingMeasurement::ConstPtr>{}), pcl::BadArgumentException);
  // Too few values, or none: no lattice, and no crash.
  EXPECT_FALSE (lab::fitDisparityLattice (std::vector<std::uint16_t>{}, kCameraConstantMm).found);
  EXPECT_FALSE (lab::fitDisparityLattice (std::vector<std::uint16_t> (100, 0), kCameraConstantMm).found);
  EXPECT_FALSE (lab::fitDisparityLattice (std::vector<std::uint16_t>{1000, 1100, 1200}, kCameraConstantMm).found);
}

TEST (DisparityLattice, SimulatedQuantisedWallsSitOnTheCamerasLattice)
{
  // The simulator quantises disparity in camera.yaml's steps: the lattice is the camera's.
  std::vector<lab::RecordingMeasurement::ConstPtr> recordings;
  const double distances[3] = {0.9, 1.6, 2.4};
  for (int k = 0; k < 3; ++k)
  {
    const sim::SceneSetup setup = sim::planeSetup (distances[k], 4, 20, 1);
    sim::SimulationSettings settings;
    settings.seed = 40 + k;
    sim::setEffectEnabled (settings.effects, "disparity_quantization", true);
    sim::KinectSimulator simulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (160, 120)), settings);
    recordings.push_back (lab::measureFrames (simulator.simulate (0, 0, 4), simulator.cameraInfo (0), "wall", "scene: plane\n"));
  }
  const lab::DisparityLattice l = lab::fitDisparityLattice (recordings);
  ASSERT_TRUE (l.found) << "coherence " << l.coherence;
  EXPECT_NEAR (l.constant_mm / l.camera_constant_mm, 1.0, 1e-3);
}

/** Depth values of three walls (0.9, 1.7, 2.6 m) of the independent generator with \a effect
  * ("" for none), and camera.yaml's lattice constant.
  */
std::vector<std::uint16_t>
generatedWalls (const pcl_texlet_test::TempDir &dir, const std::string &name, const std::string &effect,
                double &camera_constant)
{
  std::vector<std::uint16_t> depths;
  const double distances[3] = {0.9, 1.7, 2.6};
  for (int k = 0; k < 3; ++k)
  {
    const fs::path out = dir.path () / (name + "_" + std::to_string (k));
    const std::string args = out.string () + " --width 96 --height 72 --frames 3 --seed " + std::to_string (900 + k) +
                             " --distance " + std::to_string (distances[k]) + " --tilt-y " + std::to_string (10 * k) +
                             (effect.empty () ? "" : " --effect " + effect);
    const auto r = pcl_texlet_test::runCommand (std::string (PYTHON3) + " " + GENERATOR + " " + args, dir.path ());
    EXPECT_EQ (r.code, 0) << r.err;
    const CameraInfo camera = loadCameraInfoYaml ((out / "camera.yaml").string ());
    camera_constant = 1000.0 * camera.fb () / camera.disparity_subpixel;
    for (const auto &frame : fs::directory_iterator (out / "depth"))
    {
      int w = 0, h = 0;
      const std::vector<std::uint16_t> d = readDepthPng (frame.path ().string (), w, h);
      depths.insert (depths.end (), d.begin (), d.end ());
    }
  }
  return depths;
}

TEST (DisparityLattice, IndependentGeneratorsLatticeIsRecoveredWithinOnePercent)
{
  // Walls of the independent generator, quantised on a lattice 1.15 or 0.9 times camera.yaml's.
  pcl_texlet_test::TempDir dir;
  for (const double scale : {1.15, 0.9})
  {
    double camera_constant = 0.0;
    const std::vector<std::uint16_t> depths = generatedWalls (
        dir, "walls_" + std::to_string (static_cast<int> (100 * scale)), "disparity_quantization:lattice_scale=" + std::to_string (scale),
        camera_constant);
    const lab::DisparityLattice l = lab::fitDisparityLattice (depths, camera_constant);
    ASSERT_TRUE (l.found) << "scale " << scale << ": coherence " << l.coherence;
    EXPECT_NEAR (l.constant_mm / (scale * camera_constant), 1.0, 0.01) << "scale " << scale;
  }
}

TEST (DisparityLattice, RealKinectFramesSitOnALatticeCameraYamlDoesNotImply)
{
  // The bundled frames (PCL's grabber, f = 525 px assumed, b = 0.075 m): every distinct depth is
  // on one lattice, within its millimetre rounding, about 8.5 % coarser than camera.yaml implies
  // (docs/model_lab.md, "The disparity lattice").
  const fs::path tiff = fs::path (DATA_DIR) / "kinect" / "grabber_sequence" / "tiff";
  std::vector<std::uint16_t> depths;
  for (const auto &frame : fs::directory_iterator (tiff))
    if (frame.path ().string ().find ("_depth.tiff") != std::string::npos)
    {
      int w = 0, h = 0;
      const std::vector<std::uint16_t> d = readDepthTiff (frame.path ().string (), w, h);
      depths.insert (depths.end (), d.begin (), d.end ());
    }
  ASSERT_EQ (depths.size (), 3u * 640 * 480);
  const lab::DisparityLattice l = lab::fitDisparityLattice (depths, 1000.0 * 525.0 * 0.075 / 0.125);
  ASSERT_TRUE (l.found) << "coherence " << l.coherence << " residual ratio " << l.residual_ratio;
  EXPECT_LT (l.residual_ratio, 2.0);
  EXPECT_NEAR (l.constant_mm / l.camera_constant_mm, 1.085, 0.005);
}

TEST (DisparityLattice, IndependentGeneratorsUnquantisedWallsHaveNone)
{
  // Noise added in depth and whole millimetres written: no lattice, however few the values.
  pcl_texlet_test::TempDir dir;
  double camera_constant = 0.0;
  const std::vector<std::uint16_t> depths = generatedWalls (dir, "clean", "", camera_constant);
  const lab::DisparityLattice l = lab::fitDisparityLattice (depths, camera_constant);
  EXPECT_FALSE (l.found) << "C " << l.constant_mm << " coherence " << l.coherence << " from " << l.values << " values";
}

} // namespace
