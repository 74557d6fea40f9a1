/*
 * pcl_texlet io: intrinsics.xml, the depth camera's intrinsics as PCL's image grabber writes them.
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>

#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Load the depth intrinsics from an intrinsics.xml written by PCL's image grabber: the
  * five numbers focal_length_x, focal_length_y, principal_point_x, principal_point_y and
  * z_multiplication_factor of its <depth> element. The file holds two top-level elements
  * (<rgb> and <depth>), as PCL writes it, and is parsed like PCL does, with boost::property_tree.
  *
  * The returned CameraInfo has width and height 0 (the file does not store the image size) and no
  * distortion.
  * \throws pcl::IOException naming the file and the problem: missing, not valid XML, no single
  *         <depth> element, a missing, repeated or non-numeric value, a non-positive focal length,
  *         or a z_multiplication_factor other than 0.001 (depth in millimetres).
  */
CameraInfo
loadGrabberIntrinsicsXml (const std::string &path);

} // namespace texlet
} // namespace pcl
