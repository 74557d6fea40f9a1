/*
 * pcl_texlet io: the TIFF images PCL's image grabber writes: 16-bit grey depth in mm, 8-bit RGB.
 */
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Read a 16-bit single-channel (grey) TIFF: depth in millimetres, 0 = no reading.
  * \throws pcl::IOException naming the file and the problem (missing, not a TIFF, truncated or
  *         corrupt, not 16-bit, not one sample per pixel, tiled or planar layout).
  */
std::vector<std::uint16_t>
readDepthTiff (const std::string &path, int &width, int &height);

/** \brief Read an 8-bit RGB (or RGBA, alpha dropped) TIFF into row-major RGB triplets.
  * \throws pcl::IOException naming the file and the problem, as readDepthTiff.
  */
std::vector<std::uint8_t>
readRgbTiff (const std::string &path, int &width, int &height);

} // namespace texlet
} // namespace pcl
