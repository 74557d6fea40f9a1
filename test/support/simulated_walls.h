/*
 * pcl_texlet tests: wall recordings of the project's own simulator, measured for the model lab.
 */
#pragma once

#include "wall_pose.h"

#include <pcl_texlet/lab/recording_measurement.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace pcl_texlet_test
{

/** \brief One simulated wall recording for each of \a poses, \a frames frames of \a width x 3/4
  * \a width pixels, with \a effects switched on (none: the paper's base noise); wall k has seed
  * \a seed + 101 k. With depth_distortion all share \a seed (one sensor's map) and differ in
  * their frame numbers. \a stripe_period: frames one layout of vertical stripes lasts (0: the
  * effect's default).
  */
inline std::vector<pcl::texlet::lab::RecordingMeasurement::ConstPtr>
simulatedWalls (const std::vector<WallPose> &poses, const std::vector<std::string> &effects, std::uint32_t seed,
                int frames, int width, int stripe_period = 0)
{
  namespace sim = pcl::texlet::sim;
  auto has = [&] (const char *name) { return std::find (effects.begin (), effects.end (), name) != effects.end (); };
  std::vector<pcl::texlet::lab::RecordingMeasurement::ConstPtr> out;
  for (std::size_t k = 0; k < poses.size (); ++k)
  {
    const WallPose &p = poses[k];
    const sim::SceneSetup setup = sim::planeSetup (p.distance_m, p.tilt_x_deg, p.tilt_y_deg, p.projectors);
    sim::SimulationSettings settings;
    settings.seed = seed + 101 * static_cast<std::uint32_t> (k);
    std::uint32_t first_frame = 0;
    for (const auto &effect : effects)
      sim::setEffectEnabled (settings.effects, effect, true);
    if (has ("depth_distortion"))
    {
      settings.seed = seed;
      first_frame = 1000 * static_cast<std::uint32_t> (k);
    }
    if (has ("vertical_stripes") && stripe_period > 0)
      sim::setEffectParameter (settings.effects, "vertical_stripes", "period_frames", stripe_period);
    sim::KinectSimulator simulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (width, width * 3 / 4)), settings);
    const auto recorded = simulator.simulate (0, first_frame, frames);
    std::ostringstream meta;
    meta << "scene: plane\nprojectors: " << simulator.activeProjectors () << "\n";
    out.push_back (pcl::texlet::lab::measureFrames (recorded, simulator.cameraInfo (0), "wall_" + std::to_string (k),
                                                    meta.str ()));
  }
  return out;
}

} // namespace pcl_texlet_test
