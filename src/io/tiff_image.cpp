#include <pcl_texlet/io/tiff_image.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tiff_file.h"

namespace pcl
{
namespace texlet
{

namespace
{

using detail::TiffFile;

enum class TiffKind { depth, rgb };

template <typename T> std::vector<T>
readTiff (const std::string &path, TiffKind kind, int &width, int &height)
{
  const TiffFile file (path, kind == TiffKind::depth ? "depth TIFF" : "RGB TIFF");
  TIFF *tiff = file.get ();
  std::uint32_t w = 0, h = 0;
  file.size (w, h);
  std::uint16_t bits = 0, samples = 0, format = 0, planar = 0, photometric = 0;
  TIFFGetFieldDefaulted (tiff, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted (tiff, TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted (tiff, TIFFTAG_SAMPLEFORMAT, &format);
  TIFFGetFieldDefaulted (tiff, TIFFTAG_PLANARCONFIG, &planar);
  if (!TIFFGetField (tiff, TIFFTAG_PHOTOMETRIC, &photometric))
    throw file.error ("has no photometric interpretation tag");

  const std::string found = "found " + std::to_string (bits) + "-bit with " + std::to_string (samples) +
                            " sample" + (samples == 1 ? "" : "s") + " per pixel";
  std::size_t channels = 1;
  if (kind == TiffKind::depth)
  {
    if (bits != 16 || samples != 1)
      throw file.error ("expected 16-bit depth with 1 sample per pixel, " + found);
    if (format != SAMPLEFORMAT_UINT || photometric != PHOTOMETRIC_MINISBLACK)
      throw file.error ("expected unsigned grey samples (0 = black), found sample format " + std::to_string (format) +
                        " and photometric interpretation " + std::to_string (photometric));
  }
  else
  {
    if (bits != 8 || (samples != 3 && samples != 4))
      throw file.error ("expected 8-bit RGB or RGBA (3 or 4 samples per pixel), " + found);
    if (format != SAMPLEFORMAT_UINT || photometric != PHOTOMETRIC_RGB)
      throw file.error ("expected unsigned RGB samples, found sample format " + std::to_string (format) +
                        " and photometric interpretation " + std::to_string (photometric));
    channels = samples;
  }
  if (TIFFIsTiled (tiff))
    throw file.error ("is tiled; only strip TIFFs (as PCL's grabber writes them) are supported");
  if (channels > 1 && planar != PLANARCONFIG_CONTIG)
    throw file.error ("stores its colour planes separately; only interleaved RGB is supported");

  const std::size_t row_samples = std::size_t (w) * channels;
  if (TIFFScanlineSize64 (tiff) != row_samples * sizeof (T))
    throw file.error ("has rows of " + std::to_string (TIFFScanlineSize64 (tiff)) + " bytes, expected " +
                      std::to_string (row_samples * sizeof (T)));
  std::vector<T> row (row_samples);
  const std::size_t out_channels = kind == TiffKind::depth ? 1 : 3;
  std::vector<T> pixels (std::size_t (w) * h * out_channels);
  for (std::uint32_t y = 0; y < h; ++y)
  {
    // libtiff hands 16-bit samples over in host byte order whatever the file's.
    if (TIFFReadScanline (tiff, row.data (), y) < 0)
      throw file.error ("cannot decode row " + std::to_string (y) + " of " + std::to_string (h) +
                        ": truncated or corrupt (" + file.libtiffText () + ")");
    T *out = pixels.data () + std::size_t (y) * w * out_channels;
    if (channels == out_channels)
      std::copy (row.begin (), row.end (), out);
    else
      for (std::uint32_t x = 0; x < w; ++x) // RGBA: alpha dropped
        std::copy_n (row.data () + std::size_t (x) * channels, 3, out + std::size_t (x) * 3);
  }
  width = static_cast<int> (w);
  height = static_cast<int> (h);
  return pixels;
}

} // namespace

std::vector<std::uint16_t>
readDepthTiff (const std::string &path, int &width, int &height)
{
  return readTiff<std::uint16_t> (path, TiffKind::depth, width, height);
}

std::vector<std::uint8_t>
readRgbTiff (const std::string &path, int &width, int &height)
{
  return readTiff<std::uint8_t> (path, TiffKind::rgb, width, height);
}

} // namespace texlet
} // namespace pcl
