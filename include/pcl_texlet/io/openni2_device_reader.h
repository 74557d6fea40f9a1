/*
 * pcl_texlet: a live OpenNI2 device (a physical sensor, or the simulated Kinect of the
 * project's OpenNI2 driver, docs/openni2_device.md) read as a recording of a fixed number of
 * frames, through pcl::io::OpenNI2Grabber.
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

/** \brief The next \a frames depth frames of a live OpenNI2 device.
  *
  * The grabber's depth-image callback copies each frame into a small bounded queue that next ()
  * waits on, at most \a timeout_s seconds. A live device does not wait for its reader: frames
  * that arrive while the queue is full are dropped (droppedFrames () counts them), as a slow
  * consumer of a real sensor drops them. Frame names are the device's frame index, zero-padded to
  * six digits.
  *
  * Intrinsics are what the grabber's own clouds use: the focal length from the depth stream's
  * field of view (width / (2 tan (hFOV / 2))) for both axes and the principal point at the image
  * centre ((width - 1) / 2, (height - 1) / 2); the baseline is the device's
  * (PS1080 emitter-camera distance) where it reports one.
  */
class OpenNI2DeviceReader : public RecordingReader
{
public:
  /** \param uri OpenNI2 device URI; empty: the first device OpenNI2 finds
    * \param frames frames to read (> 0)
    * \param timeout_s longest wait for one frame, seconds (> 0)
    * \throws pcl::BadArgumentException for no frames or a bad timeout.
    * \throws pcl::IOException naming the device with OpenNI2's reason when it cannot be opened,
    *         has no depth stream or no field of view; also when this PCL was built without OpenNI2.
    */
  OpenNI2DeviceReader (const std::string &uri, std::size_t frames, double timeout_s = 5.0);
  ~OpenNI2DeviceReader () override;

  OpenNI2DeviceReader (const OpenNI2DeviceReader &) = delete;
  OpenNI2DeviceReader &
  operator= (const OpenNI2DeviceReader &) = delete;

  /** \brief The frames asked for. */
  std::size_t
  size () const override { return frames_; }

  /** \brief The depth stream's image size and the grabber's intrinsics (above). */
  const CameraInfo &
  cameraInfo () const override { return info_; }

  /** \throws pcl::IOException naming the device when no frame arrives within the timeout, or a
    *         frame's size differs from the stream's.
    */
  bool
  next (DepthFrame &frame) override;

  /** \brief Frames the device delivered while the queue was full. */
  std::size_t
  droppedFrames () const;

private:
  struct Live;
  std::string name_;
  std::size_t frames_;
  double timeout_s_;
  CameraInfo info_;
  std::size_t delivered_ = 0;
  std::unique_ptr<Live> live_;
};

} // namespace texlet
} // namespace pcl
