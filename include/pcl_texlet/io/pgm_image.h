/*
 * pcl_texlet io: 16-bit binary PGM images, the files libfreenect and Herrera's Kinect calibration
 * toolbox keep raw Kinect disparity in (docs/inputs.md, "Raw Kinect disparity folder").
 */
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Read a 16-bit binary PGM (magic "P5", maxval 256 to 65535, e.g. 65535 or 2047): its
  * samples as stored, two bytes each, most significant byte first as the PGM specification says
  * (no swapping, no scaling to maxval). Comments in the header are skipped; anything after the
  * first image is ignored.
  * \throws pcl::IOException naming the file and the problem: missing or unreadable, not a PGM,
  *         not binary (P2), 8-bit (maxval below 256), a size that is not positive or beyond
  *         kMaxImageSide (checked before allocating), truncated pixel data.
  */
std::vector<std::uint16_t>
readPgm16 (const std::string &path, int &width, int &height);

} // namespace texlet
} // namespace pcl
