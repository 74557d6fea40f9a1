/*
 * Fuzz target: a recording's camera.yaml (ROS camera_info, src/io/recording.cpp) and the camera
 * model built from it (PinholeModel::fromCameraInfo): a file that loads must give a model that
 * projects and back-projects without crashing, or a clear exception.
 */
#include "fuzz_input_file.h"

#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/io/camera_yaml.h>
#include <pcl/exceptions.h>

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  const std::string path = pcl_texlet_fuzz::writeInput ("camera.yaml", data, size);
  try
  {
    const pcl::texlet::CameraInfo info = pcl::texlet::loadCameraInfoYaml (path);
    const pcl::texlet::PinholeModel camera = pcl::texlet::PinholeModel::fromCameraInfo (info);
    double x, y, u, v;
    camera.pixelToRay (0.0, 0.0, x, y);
    camera.pixelToRay (info.width - 1.0, info.height - 1.0, x, y);
    camera.project (0.1, -0.2, 1.5, u, v);
    (void) camera.principalPointDistance (u, v);
  }
  catch (const pcl::PCLException &)
  {
  }
  return 0;
}
