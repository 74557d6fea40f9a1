/*
 * pcl_texlet (internal): the depth frames PCL's OpenNI2Grabber delivers, copied on its callback
 * thread into a small bounded queue that a reader takes them from. Shared by OpenNI2DeviceReader
 * (live devices) and OniReader (.oni playback).
 */
#pragma once

#include <pcl_texlet/camera/depth_frame.h>

#include <pcl/pcl_config.h> // HAVE_OPENNI2

#ifdef HAVE_OPENNI2

#include <pcl/io/openni2_grabber.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief One depth image of the grabber, copied out of OpenNI2's frame buffer. */
struct GrabbedDepthFrame
{
  unsigned index = 0; ///< the device's frame index
  int width = 0;
  int height = 0;
  int bytes = 0;      ///< what OpenNI2 delivered
  std::vector<std::uint16_t> depth_mm;
  std::string error;  ///< non-empty when the image could not be copied: then only index is set

  /** \brief Moves the pixels into \a frame, named by the frame index zero-padded to six digits. */
  void
  moveInto (DepthFrame &frame);
};

/** \brief A bounded queue of the grabber's depth frames; pushing never blocks the grabber.
  *
  * A frame that arrives while the queue is full, or after close (), is dropped and counted.
  */
class GrabberDepthQueue
{
public:
  explicit GrabberDepthQueue (std::size_t capacity) : capacity_ (capacity) {}

  /** \brief Registers push () as \a grabber's depth-image callback; the queue must outlive its
    * callbacks (stop the grabber first).
    */
  void
  connect (pcl::io::OpenNI2Grabber &grabber);

  /** \brief Runs on the grabber's callback thread: copies \a image and queues it. */
  void
  push (const pcl::io::DepthImage &image);

  /** \brief Waits until \a deadline for the oldest frame; false when none came. */
  bool
  pop (GrabbedDepthFrame &frame, std::chrono::steady_clock::time_point deadline);

  /** \brief Frames dropped: the queue was full or closed. */
  std::size_t
  dropped () const;

  /** \brief Drops every frame from now on (a reader that is going away). */
  void
  close ();

private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::deque<GrabbedDepthFrame> frames_;
  std::size_t dropped_ = 0;
  bool closed_ = false;
};

} // namespace texlet
} // namespace pcl

#endif // HAVE_OPENNI2
