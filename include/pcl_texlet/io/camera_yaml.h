/*
 * pcl_texlet io: camera.yaml, the intrinsics of a recording folder as a ROS camera_info YAML file.
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>

#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Load a ROS camera_info YAML file.
  * \throws pcl::IOException naming the file and the problem (missing, unreadable YAML,
  *         missing or malformed key, non-positive size or focal length).
  */
CameraInfo
loadCameraInfoYaml (const std::string &path);

/** \brief Write a ROS camera_info YAML file (written to a temporary file, then renamed). */
void
saveCameraInfoYaml (const std::string &path, const CameraInfo &info);

} // namespace texlet
} // namespace pcl
