/*
 * pcl_texlet tests: image contents that catch what a reader or writer could get wrong (byte order,
 * rows, channels), from a seed.
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_texlet_test
{

/** \brief Depth values covering 0, 65535 and both bytes of a sample differing (catches swapped
  * byte order), then a scramble of the full 16-bit range.
  */
inline std::vector<std::uint16_t>
depthPattern (int width, int height, unsigned seed)
{
  std::vector<std::uint16_t> depth (static_cast<std::size_t> (width) * height);
  const std::uint16_t fixed[] = {0, 65535, 1, 256, 0x00ff, 0xff00, 0x1234};
  std::uint32_t state = seed * 2654435761u + 1;
  for (std::size_t i = 0; i < depth.size (); ++i)
  {
    state = state * 1664525u + 1013904223u;
    depth[i] = i < sizeof (fixed) / sizeof (fixed[0]) ? fixed[i] : static_cast<std::uint16_t> (state >> 16);
  }
  return depth;
}

/** \brief RGB triplets that differ in every channel and pixel. */
inline std::vector<std::uint8_t>
rgbPattern (int width, int height, unsigned seed)
{
  std::vector<std::uint8_t> rgb (static_cast<std::size_t> (width) * height * 3);
  for (std::size_t i = 0; i < rgb.size (); ++i)
    rgb[i] = static_cast<std::uint8_t> (i * 31 + seed * 7);
  return rgb;
}

} // namespace pcl_texlet_test
