#include <pcl_texlet/io/recording_writer.h>

#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/png_image.h>

#include <pcl/exceptions.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

RecordingFolderWriter::RecordingFolderWriter (const std::string &folder, const CameraInfo &info)
  : folder_ (folder), info_ (info)
{
  const std::string what = "recording folder '" + folder + "': ";
  if (info.width <= 0 || info.height <= 0)
    throw pcl::BadArgumentException (what + "the image size " + std::to_string (info.width) + "x" +
                                     std::to_string (info.height) + " must be positive");
  std::error_code ec;
  const fs::path target = fs::absolute (folder, ec);
  if (folder.empty () || ec)
    throw pcl::IOException (what + "not a usable path");
  if (fs::exists (target, ec))
    throw pcl::IOException (what + "already exists (a recording is never written over another)");
  const fs::path parent = target.parent_path ();
  if (!fs::is_directory (parent, ec))
    throw pcl::IOException (what + "the folder that should hold it, '" + parent.string () + "', does not exist");
  tmp_.emplace (target.string ());
  const fs::path tmp (tmp_->temporaryPath ());
  fs::remove_all (tmp, ec); // a leftover of an earlier process with this id
  if (!fs::create_directory (tmp, ec) || !fs::create_directory (tmp / "depth", ec))
    throw pcl::IOException (what + "cannot create the temporary folder '" + tmp.string () + "': " + ec.message ());
  saveCameraInfoYaml ((tmp / "camera.yaml").string (), info_);
}

RecordingFolderWriter::~RecordingFolderWriter () = default;

void
RecordingFolderWriter::writeFrame (const DepthFrame &frame) const
{
  const std::string what = "recording folder '" + folder_ + "': frame '" + frame.name + "': ";
  if (committed_)
    throw pcl::BadArgumentException (what + "the recording is already committed");
  if (frame.name.empty () || frame.name.find ('/') != std::string::npos || frame.name == "." || frame.name == "..")
    throw pcl::BadArgumentException (what + "the name must be a plain file name");
  if (frame.width != info_.width || frame.height != info_.height ||
      frame.depth_mm.size () != static_cast<std::size_t> (frame.width) * frame.height)
    throw pcl::BadArgumentException (what + "is " + std::to_string (frame.width) + "x" + std::to_string (frame.height) +
                                     " with " + std::to_string (frame.depth_mm.size ()) + " depth values, camera.yaml says " +
                                     std::to_string (info_.width) + "x" + std::to_string (info_.height));
  if (!frame.rgb.empty () && frame.rgb.size () != 3 * frame.depth_mm.size ())
    throw pcl::BadArgumentException (what + "its RGB buffers do not match its size (" + std::to_string (frame.rgb.size ()) +
                                     " bytes for " + std::to_string (frame.width) + "x" + std::to_string (frame.height) + ")");
  writeDepthPng ((fs::path (tmp_->temporaryPath ()) / "depth" / (frame.name + ".png")).string (), frame.depth_mm.data (), frame.width,
                 frame.height);
  if (!frame.rgb.empty ())
  {
    std::error_code ec;
    fs::create_directories (fs::path (tmp_->temporaryPath ()) / "rgb", ec); // safe when several threads race to make it
    writeRgbPng ((fs::path (tmp_->temporaryPath ()) / "rgb" / (frame.name + ".png")).string (), frame.rgb.data (), frame.width,
                 frame.height);
  }
}

void
RecordingFolderWriter::writeMeta (const std::string &yaml) const
{
  const std::string path = (fs::path (tmp_->temporaryPath ()) / "meta.yaml").string ();
  std::ofstream file (path, std::ios::binary);
  if (!file)
    throw pcl::IOException ("meta.yaml '" + path + "': cannot create: " + std::strerror (errno));
  file << yaml;
  file.close ();
  if (!file)
    throw pcl::IOException ("meta.yaml '" + path + "': cannot write");
}

void
RecordingFolderWriter::commit ()
{
  if (committed_)
    return;
  std::error_code ec;
  const fs::path target (tmp_->path ());
  // rename(2) onto an existing empty folder would succeed; someone may have made one meanwhile.
  if (fs::exists (target, ec))
    throw pcl::IOException ("recording folder '" + folder_ + "': appeared while writing; not replaced");
  tmp_->commit ();
  committed_ = true;
}

} // namespace texlet
} // namespace pcl
