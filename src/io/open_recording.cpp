#include <pcl_texlet/io/open_recording.h>

#include <pcl_texlet/io/grabber_tiff_reader.h>
#include <pcl_texlet/io/kinect_disparity_reader.h>
#include <pcl_texlet/io/oni_reader.h>
#include <pcl_texlet/io/pcd_folder_reader.h>
#include <pcl_texlet/io/recording_folder_reader.h>

#include <pcl/exceptions.h>

#include <filesystem>
#include <memory>
#include <system_error>

#include "reader_util.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

RecordingKind
recordingKind (const std::string &path)
{
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw pcl::IOException ("recording '" + path + "': does not exist");
  if (fs::is_directory (path, ec))
  {
    const fs::path folder (path);
    if (fs::exists (folder / "camera.yaml", ec) || fs::is_directory (folder / "depth", ec))
      return RecordingKind::recording_folder;
    if (GrabberTiffReader::isGrabberTiffFolder (path))
      return RecordingKind::grabber_tiff_folder;
    if (PcdFolderReader::hasPcdFiles (path))
      return RecordingKind::pcd_folder;
    if (KinectDisparityReader::isKinectDisparityFolder (path))
      return RecordingKind::kinect_disparity_folder;
    throw pcl::IOException ("recording folder '" + path + "': " + (fs::is_empty (folder, ec) ? "is empty" : "is not a recording") +
                            "; expected camera.yaml + depth/*.png (a recording folder), *_depth.tiff + intrinsics.xml "
                            "(PCL's image grabber), *.pcd files or *.pgm + calibration.yml (raw Kinect disparity)");
  }
  const std::string ext = detail::lowerExtension (path);
  if (ext == ".oni")
    return RecordingKind::oni_file;
  if (ext == ".pcd")
    return RecordingKind::pcd_file;
  throw pcl::IOException ("recording '" + path + "': not a recording; expected a folder, an organised .pcd file or an .oni file");
}

RecordingReader::Ptr
openRecording (const std::string &path)
{
  switch (recordingKind (path))
  {
    case RecordingKind::recording_folder:
      return std::make_shared<RecordingFolderReader> (path);
    case RecordingKind::grabber_tiff_folder:
      return std::make_shared<GrabberTiffReader> (path);
    case RecordingKind::pcd_folder:
    case RecordingKind::pcd_file:
      return std::make_shared<PcdFolderReader> (path);
    case RecordingKind::kinect_disparity_folder:
      return std::make_shared<KinectDisparityReader> (path);
    case RecordingKind::oni_file:
      return std::make_shared<OniReader> (path);
  }
  throw pcl::IOException ("recording '" + path + "': unknown kind"); // unreachable: every kind is handled
}

} // namespace texlet
} // namespace pcl
