/*
 * pcl_texlet kernels: hexagonal grid of texlet centres in the image (paper, Sect. 3).
 *
 * Rows are spacing*sqrt(3)/2 apart and every odd row is shifted by half a spacing, so each
 * centre has six neighbours at (nearly) the same pixel distance. A centre is found from its
 * index alone, so a GPU thread needs no table.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace kernels
{

struct HexGrid
{
  int width = 0, height = 0; ///< image size, pixels
  int spacing = 0;           ///< distance between neighbouring centres in a row, pixels
  int rows = 0;              ///< number of rows that fit in the image
  int cols_even = 0;         ///< centres in rows 0, 2, 4, ...
  int cols_odd = 0;          ///< centres in rows 1, 3, 5, ... (shifted by spacing/2)

  /** \brief Total number of centres. */
  PCL_TEXLET_HD int
  size () const
  {
    return ((rows + 1) / 2) * cols_even + (rows / 2) * cols_odd;
  }
};

PCL_TEXLET_HD double
hexRowStep (int spacing) { return spacing * 0.86602540378443864676; } // sqrt(3)/2

PCL_TEXLET_HD double
hexFirstColumn (int spacing, int row) { return 0.5 * spacing + ((row & 1) ? 0.5 * spacing : 0.0); }

PCL_TEXLET_HD int
hexRowPixel (int spacing, int row) { return static_cast<int> (std::floor (0.5 * spacing + row * hexRowStep (spacing))); }

/** \brief Grid for an image of \a width x \a height with \a spacing >= 2 pixels (closer rows
  * than sqrt(3) px would fall on the same pixel row). Counts follow the placement exactly.
  */
PCL_TEXLET_HD HexGrid
makeHexGrid (int width, int height, int spacing)
{
  HexGrid g;
  g.width = width;
  g.height = height;
  g.spacing = spacing;
  if (width <= 0 || height <= 0 || spacing < 2)
    return g;
  while (hexRowPixel (spacing, g.rows) < height)
    ++g.rows;
  for (int parity = 0; parity < 2; ++parity)
  {
    const int x0 = static_cast<int> (std::floor (hexFirstColumn (spacing, parity)));
    (parity ? g.cols_odd : g.cols_even) = x0 >= width ? 0 : (width - x0 + spacing - 1) / spacing;
  }
  return g;
}

/** \brief Pixel (u, v) of centre \a index (0 <= index < g.size()), row by row. */
PCL_TEXLET_HD void
hexCentre (const HexGrid &g, int index, int &u, int &v)
{
  const int pair = g.cols_even + g.cols_odd;
  int row = 2 * (index / pair);
  int col = index % pair;
  if (col >= g.cols_even)
  {
    col -= g.cols_even;
    ++row;
  }
  u = static_cast<int> (std::floor (hexFirstColumn (g.spacing, row))) + col * g.spacing;
  v = hexRowPixel (g.spacing, row);
}

/** \brief Pixel offset of hexagonal neighbour \a k (0..5, 60 degrees apart, counter-clockwise
  * as seen with the image's v axis pointing down) at \a distance pixels.
  */
PCL_TEXLET_HD void
hexNeighbourOffset (int k, int distance, int &du, int &dv)
{
  // cos and sin of k * 60 degrees, exact values.
  const double c[6] = {1.0, 0.5, -0.5, -1.0, -0.5, 0.5};
  const double s[6] = {0.0, 0.86602540378443864676, 0.86602540378443864676, 0.0,
                       -0.86602540378443864676, -0.86602540378443864676};
  du = static_cast<int> (std::lround (distance * c[k]));
  dv = -static_cast<int> (std::lround (distance * s[k]));
}

/** \brief The ring of normal averaging: the centre (0, 0) at index 0 and its six hexagonal
  * neighbours at \a distance pixels (hexNeighbourOffset()) at 1..6.
  */
PCL_TEXLET_HD void
hexRingOffsets (int distance, int du[7], int dv[7])
{
  du[0] = dv[0] = 0;
  for (int k = 1; k < 7; ++k)
    hexNeighbourOffset (k - 1, distance, du[k], dv[k]);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
