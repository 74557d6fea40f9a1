/*
 * Fuzz target: the multi-sensor extrinsics YAML (loadExtrinsicsYaml) and the simulator's
 * meta.yaml keys the study reads (poseFromMetaYaml), src/relations/extrinsics.cpp. A file
 * that loads must hold rigid poses.
 */
#include "fuzz_input_file.h"

#include <pcl_texlet/relations/extrinsics.h>
#include <pcl/exceptions.h>

#include <cmath>

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  const std::string path = pcl_texlet_fuzz::writeInput ("extrinsics.yaml", data, size);
  try
  {
    for (const auto &s : pcl::texlet::loadExtrinsicsYaml (path))
      if (!s.pose.matrix ().allFinite () || std::abs (s.pose.linear ().determinant () - 1.0) > 1e-3)
        std::abort (); // loaded, yet not rigid
  }
  catch (const pcl::PCLException &)
  {
  }
  try
  {
    Eigen::Isometry3d pose;
    if (pcl::texlet::poseFromMetaYaml (path, pose) && !pose.matrix ().allFinite ())
      std::abort ();
  }
  catch (const pcl::PCLException &)
  {
  }
  return 0;
}
