/*
 * Fuzz target: the intrinsics.xml of PCL's image grabber (loadGrabberIntrinsicsXml,
 * src/io/recording_readers.cpp), parsed with boost::property_tree, and the pinhole built from it.
 */
#include "fuzz_input_file.h"

#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/io/grabber_intrinsics.h>
#include <pcl/exceptions.h>

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  const std::string path = pcl_texlet_fuzz::writeInput ("intrinsics.xml", data, size);
  try
  {
    const pcl::texlet::CameraInfo info = pcl::texlet::loadGrabberIntrinsicsXml (path);
    const pcl::texlet::PinholeModel camera = pcl::texlet::PinholeModel::fromCameraInfo (info);
    double x, y;
    camera.pixelToRay (1.0, 2.0, x, y);
  }
  catch (const pcl::PCLException &)
  {
  }
  return 0;
}
