/*
 * Fuzz target: the recording reader's PNG frames (src/io/recording.cpp, readDepthPng and readRgbPng
 * through libpng) and RecordingFolderReader reading the input as the frame of a one-frame
 * recording folder (camera.yaml of 8 x 6 pixels, written once). A frame that reads must hold
 * width x height samples.
 *
 * Every chunk's CRC is recomputed before the file is written (a mutated chunk would otherwise
 * nearly always fail libpng's CRC check, and the fuzzer would never get past it); a CRC error is
 * still covered by the seed corpus and by test_recording.
 */
#include "fuzz_input_file.h"

#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/png_image.h>
#include <pcl_texlet/io/recording_folder_reader.h>
#include <pcl/exceptions.h>

#include <cstdlib>
#include <vector>

#include <zlib.h>

namespace
{

/** The recording folder, with camera.yaml and an empty depth/, made on the first call. */
const std::string &
recordingFolder ()
{
  static const std::string folder = [] {
    const std::string f = pcl_texlet_fuzz::scratchFolder () + "/recording";
    const std::string cmd = "mkdir -p '" + f + "/depth'";
    if (std::system (cmd.c_str ()) != 0)
      std::abort ();
    pcl::texlet::CameraInfo info;
    info.width = 8, info.height = 6;
    info.K[0] = info.K[4] = 10.0, info.K[2] = 4.0, info.K[5] = 3.0;
    pcl::texlet::saveCameraInfoYaml (f + "/camera.yaml", info);
    return f;
  }();
  return folder;
}

/** The input with the CRC of each complete chunk after the signature recomputed. */
std::vector<std::uint8_t>
withChunkCrcsFixed (const std::uint8_t *data, std::size_t size)
{
  std::vector<std::uint8_t> png (data, data + size);
  std::size_t at = 8; // after the signature
  while (at + 12 <= png.size ())
  {
    const std::size_t length = (std::size_t (png[at]) << 24) | (std::size_t (png[at + 1]) << 16) |
                               (std::size_t (png[at + 2]) << 8) | png[at + 3];
    if (length > png.size () - at - 12)
      break;
    const uLong crc = crc32 (0L, png.data () + at + 4, static_cast<uInt> (length + 4));
    std::uint8_t *out = png.data () + at + 8 + length;
    out[0] = std::uint8_t (crc >> 24), out[1] = std::uint8_t (crc >> 16), out[2] = std::uint8_t (crc >> 8), out[3] = std::uint8_t (crc);
    at += length + 12;
  }
  return png;
}

} // namespace

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  const std::vector<std::uint8_t> png = withChunkCrcsFixed (data, size);
  data = png.data ();
  const std::string path = pcl_texlet_fuzz::writeInput ("frame.png", data, size);
  int w = -1, h = -1;
  try
  {
    const auto depth = pcl::texlet::readDepthPng (path, w, h);
    if (w <= 0 || h <= 0 || depth.size () != static_cast<std::size_t> (w) * h)
      std::abort ();
  }
  catch (const pcl::PCLException &)
  {
  }
  try
  {
    const auto rgb = pcl::texlet::readRgbPng (path, w, h);
    if (w <= 0 || h <= 0 || rgb.size () != 3 * static_cast<std::size_t> (w) * h)
      std::abort ();
  }
  catch (const pcl::PCLException &)
  {
  }
  const std::string folder = recordingFolder ();
  pcl_texlet_fuzz::writeInput ("recording/depth/000000.png", data, size);
  try
  {
    pcl::texlet::RecordingFolderReader reader (folder);
    pcl::texlet::DepthFrame frame;
    if (!reader.next (frame))
      std::abort (); // the folder holds one frame
    if (frame.width != 8 || frame.height != 6 || frame.depth_mm.size () != 48)
      std::abort ();
  }
  catch (const pcl::PCLException &)
  {
  }
  return 0;
}
