/*
 * pcl_texlet: recordings of organised depth frames (DESIGN.md section 4).
 *
 * A recording is read one frame at a time through RecordingReader, so that long recordings
 * never sit in memory whole. This header holds the interface and the recording-folder format
 * (camera.yaml, PNG depth frames in depth/, optional PNG colour frames in rgb/, optional
 * meta.yaml).
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>
#include <pcl_texlet/camera/depth_frame.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Load a ROS camera_info YAML file.
  * \throws pcl::IOException naming the file and the problem (missing, unreadable YAML,
  *         missing or malformed key, non-positive size or focal length).
  */
CameraInfo
loadCameraInfoYaml (const std::string &path);

/** \brief Write a ROS camera_info YAML file (written to a temporary file, then renamed). */
void
saveCameraInfoYaml (const std::string &path, const CameraInfo &info);

/** \brief Read a 16-bit single-channel PNG (depth in mm).
  * \throws pcl::IOException naming the file and the problem (missing, not a PNG, truncated,
  *         not 16-bit, not single-channel grey).
  */
std::vector<std::uint16_t>
readDepthPng (const std::string &path, int &width, int &height);

/** \brief Write a 16-bit grey PNG (to a temporary file, then renamed). */
void
writeDepthPng (const std::string &path, const std::uint16_t *depth_mm, int width, int height);

/** \brief Read an 8-bit RGB (or RGBA, alpha dropped) PNG into RGB triplets. */
std::vector<std::uint8_t>
readRgbPng (const std::string &path, int &width, int &height);

/** \brief Write an 8-bit RGB PNG from row-major RGB triplets (to a temporary file, then renamed). */
void
writeRgbPng (const std::string &path, const std::uint8_t *rgb, int width, int height);

/** \brief Streaming source of depth frames. */
class RecordingReader
{
public:
  using Ptr = std::shared_ptr<RecordingReader>;
  virtual ~RecordingReader () = default;

  /** \brief Number of frames in the recording. */
  virtual std::size_t
  size () const = 0;

  /** \brief Intrinsics of the depth frames. */
  virtual const CameraInfo &
  cameraInfo () const = 0;

  /** \brief Read the next frame; false at the end.
    * \throws pcl::IOException for a bad frame (unreadable, wrong bit depth, size differing from
    *         camera.yaml), naming the file. Every reader moves past the bad frame before it
    *         throws, so that the caller may go on with the next one (FrameSkippingReader does).
    */
  virtual bool
  next (DepthFrame &frame) = 0;
};

/** \brief Reader of the recording folder format of DESIGN.md section 4:
  * camera.yaml, the PNG frames of depth/ (sorted by name), optional PNG frames of the same
  * names in rgb/.
  */
class RecordingFolderReader : public RecordingReader
{
public:
  /** \throws pcl::IOException if the folder, camera.yaml or depth/ is missing or empty. */
  explicit RecordingFolderReader (const std::string &folder);

  std::size_t
  size () const override { return depth_files_.size (); }

  const CameraInfo &
  cameraInfo () const override { return info_; }

  bool
  next (DepthFrame &frame) override;

  /** \brief True if \a folder looks like a recording folder (has camera.yaml and depth/). */
  static bool
  isRecordingFolder (const std::string &folder);

private:
  std::string folder_;
  CameraInfo info_;
  std::vector<std::string> depth_files_;
  std::size_t next_ = 0;
};

} // namespace texlet
} // namespace pcl
