/*
 * pcl_texlet: recordings of organised depth frames (DESIGN.md section 4).
 *
 * A recording is read one frame at a time through RecordingReader, so that long recordings
 * never sit in memory whole. This header holds the interface and the recording-folder format
 * (camera.yaml, PNG depth frames in depth/, optional PNG colour frames in rgb/, optional
 * meta.yaml).
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief The largest image side the readers accept, pixels: beyond any depth sensor's, so a
  * larger size in a header or camera.yaml is corruption, refused before memory is allocated.
  */
constexpr int kMaxImageSide = 16384;

/** \brief Intrinsics of a depth image, as in a ROS camera_info YAML file (camera.yaml). */
struct CameraInfo
{
  int width = 0;                     ///< image_width, pixels
  int height = 0;                    ///< image_height, pixels
  double K[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};  ///< camera_matrix.data, row-major: fx 0 cx 0 fy cy 0 0 1
  std::string distortion_model = "plumb_bob"; ///< distortion_model
  std::vector<double> D = std::vector<double> (5, 0.0); ///< distortion_coefficients.data (k1 k2 p1 p2 k3)
  double baseline_m = 0.075;         ///< projector-camera baseline in metres (optional key)
  double disparity_subpixel = 0.125; ///< disparity quantisation step in pixels (optional key)

  double fx () const { return K[0]; }
  double fy () const { return K[4]; }
  double cx () const { return K[2]; }
  double cy () const { return K[5]; }
};

/** \brief Load a ROS camera_info YAML file.
  * \throws pcl::IOException naming the file and the problem (missing, unreadable YAML,
  *         missing or malformed key, non-positive size or focal length).
  */
CameraInfo
loadCameraInfoYaml (const std::string &path);

/** \brief Write a ROS camera_info YAML file (written to a temporary file, then renamed). */
void
saveCameraInfoYaml (const std::string &path, const CameraInfo &info);

/** \brief One depth frame: depth in millimetres (0 = no reading), optional 8-bit RGB. */
struct DepthFrame
{
  std::string name;                  ///< file stem, e.g. "000012"
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> depth_mm; ///< row-major, width*height
  std::vector<std::uint8_t> rgb;       ///< row-major RGB triplets, 3*width*height, or empty
};

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
