/*
 * pcl_texlet simulator: the meta.yaml of a simulated recording (docs/sensor_model.md).
 *
 * Keys: generator, seed, first_frame, frames, scene (plane | box | free), scene_parameters,
 * box_size_m (box scenes), mesh (mesh scenes), projectors (active projectors), sensors,
 * sensor (which one recorded), sensor_pose (scene from camera, row-major 4x4),
 * render_camera (the true fx, fy, cx, cy; camera.yaml may carry others under the intrinsics
 * effect), depth_range_m, base_noise (paper | none | custom), projector_shadows, and effects:
 * the active effects, each with all its parameters.
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

/** \brief meta.yaml text for frames first_frame .. first_frame + frames - 1 of sensor \a sensor. */
std::string
simulationMetaYaml (const SceneSetup &setup, const KinectSimulator &simulator, std::size_t sensor,
                    std::uint32_t first_frame, std::uint32_t frames);

} // namespace sim
} // namespace texlet
} // namespace pcl
