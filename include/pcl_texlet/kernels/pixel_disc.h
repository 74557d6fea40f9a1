/*
 * pcl_texlet kernels: the pixel neighbourhood of a texlet, a disc of a radius in pixels.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Number of pixel offsets (du, dv) with du^2 + dv^2 <= radius^2. */
PCL_TEXLET_HD int
pixelDiscSize (int radius)
{
  int n = 0;
  for (int dv = -radius; dv <= radius; ++dv)
    for (int du = -radius; du <= radius; ++du)
      n += (du * du + dv * dv <= radius * radius) ? 1 : 0;
  return n;
}

/** \brief Writes the disc's offsets row by row (dv, then du ascending) into \a du and \a dv,
  * at most \a capacity of them, and returns how many the disc has.
  */
PCL_TEXLET_HD int
pixelDiscOffsets (int radius, int *du, int *dv, int capacity)
{
  int n = 0;
  for (int y = -radius; y <= radius; ++y)
    for (int x = -radius; x <= radius; ++x)
      if (x * x + y * y <= radius * radius)
      {
        if (n < capacity)
        {
          du[n] = x;
          dv[n] = y;
        }
        ++n;
      }
  return n;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
