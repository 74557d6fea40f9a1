#include <pcl_texlet/io/kinect_disparity_reader.h>

#include <pcl_texlet/io/pgm_image.h>

#include <pcl/exceptions.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <system_error>

#include "reader_util.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

/** \brief Reads \a samples little-endian where they must be: some sample above 2047 (no 11-bit
  * disparity) while every byte-swapped one is at most 2047. A frame of valid big-endian
  * disparities never has the first; a frame with any invalid pixel (2047 is FF 07) swapped
  * has it, so the test decides every frame that holds a pixel without a reading.
  */
void
undoLittleEndian (std::vector<std::uint16_t> &samples)
{
  const auto swapped = [] (std::uint16_t s) { return static_cast<std::uint16_t> ((s >> 8) | (s << 8)); };
  const bool above = std::any_of (samples.begin (), samples.end (), [] (std::uint16_t s) { return s > kKinectNoDisparity; });
  if (!above || !std::all_of (samples.begin (), samples.end (),
                              [&] (std::uint16_t s) { return swapped (s) <= kKinectNoDisparity; }))
    return;
  for (std::uint16_t &s : samples)
    s = swapped (s);
}

bool
isPgm (const std::string &name)
{
  return detail::lowerExtension (name) == ".pgm";
}

} // namespace

const std::vector<std::string> &
KinectDisparityReader::kinectCalibrationNames ()
{
  static const std::vector<std::string> names = {"calibration.yml", "calibration.yaml", "calib.yml", "calib.yaml"};
  return names;
}

std::vector<std::string>
KinectDisparityReader::listDisparityPgms (const std::string &folder)
{
  std::vector<std::string> files = detail::listFiles (folder, [] (const std::string &name) {
    return isPgm (name) && name.size () > 6 && detail::endsWith (name.substr (0, name.size () - 4), "-d");
  });
  if (files.empty ())
    files = detail::listFiles (folder, isPgm);
  return files;
}

bool
KinectDisparityReader::isKinectDisparityFolder (const std::string &folder)
{
  std::error_code ec;
  for (const std::string &name : kinectCalibrationNames ())
    if (fs::is_regular_file (fs::path (folder) / name, ec))
      return true;
  return !detail::listFiles (folder, isPgm).empty ();
}

KinectDisparityReader::KinectDisparityReader (const std::string &folder, const std::string &calibration_path)
{
  const std::string what = "Kinect disparity folder '" + folder + "': ";
  detail::requireFolder (folder, what);

  std::string calibration = calibration_path;
  if (calibration.empty ())
  {
    std::error_code ec;
    for (const std::string &name : kinectCalibrationNames ())
      if (fs::is_regular_file (fs::path (folder) / name, ec))
      {
        calibration = (fs::path (folder) / name).string ();
        break;
      }
    if (calibration.empty ())
    {
      std::string names;
      for (const std::string &name : kinectCalibrationNames ())
        names += (names.empty () ? "" : ", ") + name;
      throw pcl::IOException (what + "has no calibration file (looked for " + names + ")");
    }
  }

  files_ = listDisparityPgms (folder);
  if (files_.empty ())
    throw pcl::IOException (what + "holds no raw disparity frames (*.pgm)");

  calib_ = loadKinectDisparityCalibration (calibration);
  info_ = calib_.info;
  if (info_.width > 0)
    size_source_ = "the calibration says " + detail::sizeText (info_.width, info_.height) + " ('" + calibration + "')";
  else
  {
    // Herrera's toolbox does not store the depth image size; the first frame sets it for all.
    readPgm16 (files_.front (), info_.width, info_.height);
    size_source_ = "the first frame '" + files_.front () + "' is " + detail::sizeText (info_.width, info_.height);
  }
  if (!calib_.beta.empty () && (calib_.beta_width != info_.width || calib_.beta_height != info_.height))
    throw pcl::IOException ("Kinect calibration '" + calibration + "': dc_beta is " + std::to_string (calib_.beta_height) +
                            "x" + std::to_string (calib_.beta_width) + " (rows x cols) but the frames are " +
                            detail::sizeText (info_.width, info_.height) + " (width x height)");
}

void
KinectDisparityReader::readFrame (std::size_t index, DepthFrame &frame)
{
  const std::string &path = files_[index];
  frame.name = fs::path (path).stem ().string ();
  std::vector<std::uint16_t> disparity = readPgm16 (path, frame.width, frame.height);
  checkSize ("raw disparity PGM", path, frame.width, frame.height);
  undoLittleEndian (disparity);
  frame.depth_mm.resize (disparity.size ());
  for (int v = 0; v < frame.height; ++v)
    for (int u = 0; u < frame.width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * static_cast<std::size_t> (frame.width) + static_cast<std::size_t> (u);
      frame.depth_mm[i] = calib_.depthMm (disparity[i], u, v);
    }
}

} // namespace texlet
} // namespace pcl
