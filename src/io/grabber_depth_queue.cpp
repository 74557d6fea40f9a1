#include "grabber_depth_queue.h"

#ifdef HAVE_OPENNI2

#include <pcl/io/image_depth.h>

#include <cstdio>
#include <functional>
#include <utility>

namespace pcl
{
namespace texlet
{

void
GrabbedDepthFrame::moveInto (DepthFrame &frame)
{
  char name[16];
  std::snprintf (name, sizeof (name), "%06u", index);
  frame.name = name;
  frame.width = width;
  frame.height = height;
  frame.depth_mm = std::move (depth_mm);
  frame.rgb.clear ();
}

void
GrabberDepthQueue::connect (pcl::io::OpenNI2Grabber &grabber)
{
  grabber.registerCallback (std::function<void (const pcl::io::DepthImage::Ptr &)> (
      [this] (const pcl::io::DepthImage::Ptr &image) { push (*image); }));
}

void
GrabberDepthQueue::push (const pcl::io::DepthImage &image)
{
  GrabbedDepthFrame frame;
  frame.index = image.getFrameID ();
  try
  {
    frame.width = static_cast<int> (image.getWidth ());
    frame.height = static_cast<int> (image.getHeight ());
    frame.bytes = image.getDataSize ();
    frame.depth_mm.resize (std::size_t (frame.width) * frame.height);
    image.fillDepthImageRaw (frame.width, frame.height, frame.depth_mm.data ());
  }
  catch (const std::exception &e)
  {
    frame.depth_mm.clear ();
    frame.error = e.what ();
  }
  {
    std::lock_guard<std::mutex> lock (mutex_);
    if (closed_ || frames_.size () >= capacity_)
    {
      ++dropped_;
      return;
    }
    frames_.push_back (std::move (frame));
  }
  arrived_.notify_one ();
}

bool
GrabberDepthQueue::pop (GrabbedDepthFrame &frame, std::chrono::steady_clock::time_point deadline)
{
  std::unique_lock<std::mutex> lock (mutex_);
  if (!arrived_.wait_until (lock, deadline, [this] { return !frames_.empty (); }))
    return false;
  frame = std::move (frames_.front ());
  frames_.pop_front ();
  return true;
}

std::size_t
GrabberDepthQueue::dropped () const
{
  std::lock_guard<std::mutex> lock (mutex_);
  return dropped_;
}

void
GrabberDepthQueue::close ()
{
  std::lock_guard<std::mutex> lock (mutex_);
  closed_ = true;
}

} // namespace texlet
} // namespace pcl

#endif // HAVE_OPENNI2
