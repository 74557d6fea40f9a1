#include <pcl_texlet/io/kinect_disparity_reader.h>

#include <pcl_texlet/io/pgm_image.h>

#include <pcl/exceptions.h>

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

/** \brief Byte-swaps \a samples where more of them are 11-bit disparities (at most 2047) that
  * way: a frame written in little-endian order. Valid disparities read in the wrong order are
  * mostly above 2047 (760 is 02 F8, read F8 02), so the right order wins by far; a tie (a frame
  * of zeros) keeps the specification's order.
  */
void
undoLittleEndian (std::vector<std::uint16_t> &samples)
{
  const auto swapped = [] (std::uint16_t s) { return static_cast<std::uint16_t> ((s >> 8) | (s << 8)); };
  std::size_t as_read = 0, as_swapped = 0;
  for (const std::uint16_t s : samples)
  {
    as_read += s <= kKinectNoDisparity;
    as_swapped += swapped (s) <= kKinectNoDisparity;
  }
  if (as_swapped > as_read)
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
