/*
 * pcl_texlet_bench: the frame the timing studies run on: an organised PCD file or a simulated scene.
 */
#pragma once

#include "methods.h"
#include "options.h"

#include <pcl_texlet/camera/camera_model.h>

#include <string>

namespace pcl_texlet_bench
{

/** The input: an organised PCD (as XYZ) with a pinhole estimated from it once, or a scene. */
struct Input
{
  std::string description;
  Cloud::Ptr cloud;
  pcl::texlet::CameraModel::ConstPtr camera;
};

/** \brief The scene of --scene, or INPUT with a pinhole estimated from it.
  * \throws pcl_texlet_app::InputError naming the input when it cannot be read, is not organised or
  *         carries no camera.
  */
Input
loadInput (const Options &o);

} // namespace pcl_texlet_bench
