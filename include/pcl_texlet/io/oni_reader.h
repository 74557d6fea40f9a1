/*
 * pcl_texlet io: .oni recordings, played back through PCL's OpenNI2 grabber.
 */
#pragma once

#include <pcl_texlet/io/recording_reader.h>

#include <cstddef>
#include <memory>
#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Reader of .oni recordings, played back through pcl::io::OpenNI2Grabber.
  *
  * Every depth frame of the file comes out once, in file order, unchanged: the grabber's
  * depth-image callback copies each frame into a small queue that next () takes it from.
  * OpenNI2's player runs in manual mode with repeat off, on the same (reference-counted) OpenNI2
  * device the grabber opened, and next () releases the file's records one at a time, each only
  * after the grabber has delivered the previous depth frame, so that OpenNI2 never replaces a
  * frame the grabber has not read (docs/openni2_device.md, "Playing .oni files through PCL's
  * grabber"). A slow caller holds the player, it loses nothing. Every wait is bounded by
  * \a timeout_s seconds, so that a file OpenNI2 cannot play never hangs the caller.
  *
  * Frames are checked to be consecutive; their names are the 1-based frame index, zero-padded to
  * six digits. Only the depth stream is read (no colour). After the last frame the playback is
  * closed.
  *
  * Intrinsics: an .oni file stores the depth stream's field of view, not a calibration, so the
  * focal length is the grabber's (width / (2 tan (hFOV / 2))) for both axes and the principal
  * point is the image centre ((width - 1) / 2, (height - 1) / 2), as the grabber's own point
  * clouds use them: OpenNI's flaws (docs/camera_models.md) stay until a calibration replaces them.
  */
class OniReader : public RecordingReader
{
public:
  /** \throws pcl::IOException naming the file when it is missing, not an .oni file OpenNI2 can
    *         open, has no depth stream, no frame count (not finalised), no cropping property (such
    *         recordings play back no frame in OpenNI2 2.2), no field of view, or depth not in mm;
    *         also when this PCL was built without OpenNI2.
    */
  explicit OniReader (const std::string &file, double timeout_s = 5.0);
  ~OniReader () override;

  OniReader (const OniReader &) = delete;
  OniReader &
  operator= (const OniReader &) = delete;

  /** \brief The depth frames the file holds (its recorder's count). */
  std::size_t
  size () const override { return size_; }

  /** \brief The depth stream's image size and the grabber's focal length (above). */
  const CameraInfo &
  cameraInfo () const override { return info_; }

  /** \throws pcl::IOException naming the file when a frame does not arrive within the timeout or
    *         arrives out of order.
    */
  bool
  next (DepthFrame &frame) override;

private:
  struct Playback;
  std::string file_;
  double timeout_s_;
  CameraInfo info_;
  std::size_t size_ = 0;
  std::size_t delivered_ = 0;
  unsigned last_index_ = 0; ///< frame index of the last frame taken
  std::unique_ptr<Playback> playback_;
};

} // namespace texlet
} // namespace pcl
