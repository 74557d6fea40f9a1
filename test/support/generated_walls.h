/*
 * pcl_texlet tests: wall recordings of the independent generator (test/generators/
 * independent_walls.py), measured for the model lab. The test target defines PYTHON3 and
 * GENERATOR (test/CMakeLists.txt).
 */
#pragma once

#include "app_run.h"
#include "temp_dir.h"
#include "wall_pose.h"

#include <pcl_texlet/lab/recording_measurement.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace pcl_texlet_test
{

/** \brief One wall recording of the generator for each of \a poses, \a frames frames of \a width
  * x \a height pixels (0: 3/4 \a width), with \a effects (each an --effect argument; none: a
  * clean wall) hidden, measured.
  * Wall k has seed \a seed + 37 k; one sensor made them all: its own draws (the distortion map)
  * come from \a seed.
  */
inline std::vector<pcl::texlet::lab::RecordingMeasurement::ConstPtr>
generatedWalls (const std::vector<WallPose> &poses, const std::vector<std::string> &effects, int seed, int frames,
                int width, int height = 0)
{
  if (height <= 0)
    height = width * 3 / 4;
  TempDir dir;
  std::vector<pcl::texlet::lab::RecordingMeasurement::ConstPtr> out;
  for (std::size_t k = 0; k < poses.size (); ++k)
  {
    const WallPose &p = poses[k];
    const std::string folder = (dir.path () / ("wall_" + std::to_string (k))).string ();
    std::string args = folder + " --width " + std::to_string (width) + " --height " + std::to_string (height) +
                             " --frames " + std::to_string (frames) + " --seed " + std::to_string (seed + 37 * static_cast<int> (k)) +
                             " --distance " + std::to_string (p.distance_m) + " --tilt-x " + std::to_string (p.tilt_x_deg) +
                             " --tilt-y " + std::to_string (p.tilt_y_deg) + " --projectors " + std::to_string (p.projectors) +
                             " --sensor-seed " + std::to_string (seed);
    for (const auto &effect : effects)
      args += " --effect " + effect;
    const AppResult r = runCommand (std::string (PYTHON3) + " " + GENERATOR + " " + args, dir.path ());
    EXPECT_EQ (r.code, 0) << r.err;
    out.push_back (pcl::texlet::lab::measureRecording (folder));
  }
  return out;
}

} // namespace pcl_texlet_test
