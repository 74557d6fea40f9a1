/*
 * pcl_texlet io: the streaming interface every recording is read through, one frame at a time,
 * so that a long recording never sits in memory whole (the formats: docs/inputs.md).
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>
#include <pcl_texlet/camera/depth_frame.h>

#include <cstddef>
#include <memory>

namespace pcl
{
namespace texlet
{

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

} // namespace texlet
} // namespace pcl
