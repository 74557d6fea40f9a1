/*
 * pcl_texlet camera: one depth image in millimetres, with optional colour.
 */
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief One depth frame: depth in millimetres (0 = no reading), optional 8-bit RGB. */
struct DepthFrame
{
  std::string name;                  ///< file stem, e.g. "000012"
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> depth_mm; ///< row-major, width*height
  std::vector<std::uint8_t> rgb;       ///< row-major RGB triplets, 3*width*height, or empty
};

} // namespace texlet
} // namespace pcl
