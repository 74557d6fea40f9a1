#include <pcl_texlet/io/recording_folder_reader.h>

#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/png_image.h>

#include <pcl/exceptions.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "reader_util.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

RecordingFolderReader::RecordingFolderReader (const std::string &folder) : folder_ (folder)
{
  const std::string what = "recording folder '" + folder + "': ";
  detail::requireFolder (folder, what);

  const std::string camera_yaml = (fs::path (folder) / "camera.yaml").string ();
  info_ = loadCameraInfoYaml (camera_yaml);
  size_source_ = "camera.yaml says " + detail::sizeText (info_.width, info_.height) + " ('" + camera_yaml + "')";

  const fs::path depth_dir = fs::path (folder) / "depth";
  std::error_code ec;
  if (!fs::is_directory (depth_dir, ec))
    throw pcl::IOException (what + "has no depth/ subfolder");
  for (fs::directory_iterator it (depth_dir, ec), end; !ec && it != end; it.increment (ec))
    if (it->path ().extension () == ".png" && it->is_regular_file ())
      files_.push_back (it->path ().string ());
  if (ec)
    throw pcl::IOException (what + "cannot list depth/: " + ec.message ());
  if (files_.empty ())
    throw pcl::IOException (what + "depth/ is empty (no .png files)");
  // All in one folder, so sorting the paths sorts by file name.
  std::sort (files_.begin (), files_.end ());
}

void
RecordingFolderReader::readFrame (std::size_t index, DepthFrame &frame)
{
  static const ImageFormat png = {"depth PNG", readDepthPng, "RGB PNG", readRgbPng};
  frame.name = fs::path (files_[index]).stem ().string ();
  readImages (png, files_[index], (fs::path (folder_) / "rgb" / (frame.name + ".png")).string (), frame);
}

bool
RecordingFolderReader::isRecordingFolder (const std::string &folder)
{
  std::error_code ec;
  return fs::is_regular_file (fs::path (folder) / "camera.yaml", ec) && fs::is_directory (fs::path (folder) / "depth", ec);
}

} // namespace texlet
} // namespace pcl
