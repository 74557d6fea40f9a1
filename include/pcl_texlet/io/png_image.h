/*
 * pcl_texlet io: the PNG images of a recording folder: 16-bit grey depth in mm, 8-bit RGB colour.
 */
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Read a 16-bit single-channel PNG (depth in mm).
  * \throws pcl::IOException naming the file and the problem (missing, not a PNG, truncated,
  *         not 16-bit, not single-channel grey).
  */
std::vector<std::uint16_t>
readDepthPng (const std::string &path, int &width, int &height);

/** \brief Write a 16-bit grey PNG (to a temporary file, then renamed). */
void
writeDepthPng (const std::string &path, const std::uint16_t *depth_mm, int width, int height);

/** \brief Read an 8-bit RGB (or RGBA, alpha dropped) PNG into RGB triplets. */
std::vector<std::uint8_t>
readRgbPng (const std::string &path, int &width, int &height);

/** \brief Write an 8-bit RGB PNG from row-major RGB triplets (to a temporary file, then renamed). */
void
writeRgbPng (const std::string &path, const std::uint8_t *rgb, int width, int height);

} // namespace texlet
} // namespace pcl
