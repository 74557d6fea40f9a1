/*
 * pcl_texlet kernels: the pixel neighbourhood of a texlet, a disc of a radius in pixels, and
 * its valid points in an organised frame.
 *
 * A frame is read through an accessor (see kernels/texlet_stages.h for the whole concept);
 * the disc needs of it: int width () and height (), point (u, v) and point (index) (the point
 * at a pixel and at its linear index v * width + u, with members x, y, z), and
 * valid (point) (whether that point has a depth reading).
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <cstddef>

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

/** \brief The disc of a texlet: its offsets in disc order (pixelDiscOffsets()) and, for a
  * frame of a known width, the same offsets as linear ones (dv * width + du), which let discs
  * that lie inside the frame be read without bounds checks.
  */
struct PixelDisc
{
  const int *du = nullptr, *dv = nullptr;
  const std::ptrdiff_t *linear = nullptr; ///< null: every disc pixel is bounds-checked
  int size = 0;                           ///< number of offsets
  int radius = 0;                         ///< pixels
};

/** \brief Disc entry \a o of the texlet centred on (cu, cv): calls take (point, index) with its
  * point and linear index if it lies in the frame and has a depth reading. \return whether it did
  */
template <typename Frame, typename Take> PCL_TEXLET_HD bool
visitDiscPixel (const Frame &frame, const PixelDisc &disc, int cu, int cv, int o, Take &&take)
{
  const int u = cu + disc.du[o], v = cv + disc.dv[o];
  if (u < 0 || v < 0 || u >= frame.width () || v >= frame.height ())
    return false;
  const auto &p = frame.point (u, v);
  if (!frame.valid (p))
    return false;
  take (p, v * frame.width () + u);
  return true;
}

/** \brief Calls take (point, index) for each pixel of the disc around (cu, cv) that lies in the
  * frame and has a depth reading, in disc order.
  */
template <typename Frame, typename Take> PCL_TEXLET_HD void
forEachDiscPoint (const Frame &frame, const PixelDisc &disc, int cu, int cv, Take &&take)
{
  const int r = disc.radius;
  if (disc.linear && cu >= r && cv >= r && cu + r < frame.width () && cv + r < frame.height ())
  {
    // Inside the frame: no bounds checks, pixels by their linear offsets.
    const std::ptrdiff_t centre = static_cast<std::ptrdiff_t> (cv) * frame.width () + cu;
    for (int o = 0; o < disc.size; ++o)
    {
      const std::ptrdiff_t index = centre + disc.linear[o];
      const auto &p = frame.point (index);
      if (frame.valid (p))
        take (p, static_cast<int> (index));
    }
  }
  else
    for (int o = 0; o < disc.size; ++o)
      visitDiscPixel (frame, disc, cu, cv, o, take);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
