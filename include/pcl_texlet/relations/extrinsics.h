/*
 * pcl_texlet multi-sensor: where each sensor stands in the common reference frame.
 *
 * Extrinsics YAML (docs/multi_sensor.md):
 *
 *   sensors:
 *     - name: sensor_0            # the recording folder's name (its last path component)
 *       pose: [1, 0, 0, 0,        # reference frame from the sensor's camera frame, row-major
 *              0, 1, 0, 0,        # 4x4 (camera frame: x right, y down, z forward; metres)
 *              0, 0, 1, 0,
 *              0, 0, 0, 1]
 *     - name: sensor_1
 *       pose: [[...], [...], [...], [...]]   # four rows of four also accepted
 *
 * The simulator's meta.yaml carries the same pose as `sensor_pose` (scene from camera), so a
 * simulated recording needs no extrinsics file: poseFromMetaYaml reads it.
 */
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief One sensor's pose: reference frame from its camera frame. */
struct SensorExtrinsics
{
  std::string name;                                          ///< matches a recording folder's name
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();   ///< reference from camera
};

/** \brief Checks that \a m is a rigid transform (finite, orthonormal rotation with det +1 to
  * 1e-4, last row 0 0 0 1).
  * \throws pcl::BadArgumentException naming \a what and the problem.
  */
Eigen::Isometry3d
rigidPose (const Eigen::Matrix4d &m, const std::string &what);

/** \brief Loads an extrinsics YAML file (format above).
  * \throws pcl::IOException naming the file and the problem: missing, not YAML, no `sensors`
  *         list, a sensor without name or pose, a pose not 16 numbers, not rigid, a repeated name.
  */
std::vector<SensorExtrinsics>
loadExtrinsicsYaml (const std::string &path);

/** \brief Writes an extrinsics YAML file (to a temporary file, then renamed).
  * \throws pcl::IOException if it cannot be written.
  */
void
saveExtrinsicsYaml (const std::string &path, const std::vector<SensorExtrinsics> &sensors);

/** \brief The `sensor_pose` of a simulator's meta.yaml, if it has one.
  * \return false when the file or the key is absent.
  * \throws pcl::IOException naming the file when it is not YAML or the pose is malformed.
  */
bool
poseFromMetaYaml (const std::string &meta_yaml, Eigen::Isometry3d &pose);

/** \brief meta.yaml's `projectors` (active projectors while recording), \a fallback when absent.
  * \throws pcl::IOException naming the file when it is not YAML or the value is not a positive integer.
  */
int
projectorsFromMetaYaml (const std::string &meta_yaml, int fallback = 1);

} // namespace texlet
} // namespace pcl
