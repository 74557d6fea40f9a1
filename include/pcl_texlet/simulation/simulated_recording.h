/*
 * pcl_texlet simulator: a simulated recording written as a recording folder
 * (docs/sensor_model.md section 2): camera.yaml, depth/000000.png ..., meta.yaml.
 */
#pragma once

#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <cstdint>
#include <string>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief Simulates frames first_frame .. first_frame + frames - 1 of sensor \a sensor and
  * writes them to \a folder, in parallel over frames (the simulator's thread count), through a
  * temporary folder renamed at the end: on any failure no recording is left.
  * \throws pcl::BadArgumentException for no frames or a frame number that would overflow.
  * \throws pcl::IOException if \a folder exists or cannot be written.
  */
void
writeSimulatedRecording (const KinectSimulator &simulator, const SceneSetup &setup, std::size_t sensor,
                         std::uint32_t first_frame, std::uint32_t frames, const std::string &folder);

} // namespace sim
} // namespace texlet
} // namespace pcl
