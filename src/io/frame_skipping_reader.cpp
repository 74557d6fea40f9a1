#include <pcl_texlet/io/frame_skipping_reader.h>

#include <pcl/exceptions.h>

#include <utility>

namespace pcl
{
namespace texlet
{

namespace
{
/** Messages kept for skippedMessages (); the count goes on past it. */
constexpr std::size_t kKeptMessages = 100;
} // namespace

FrameSkippingReader::FrameSkippingReader (RecordingReader::Ptr source, Warning warning)
  : source_ (std::move (source)), warning_ (std::move (warning))
{
  if (!source_)
    throw pcl::BadArgumentException ("FrameSkippingReader: no source reader");
}

bool
FrameSkippingReader::next (DepthFrame &frame)
{
  for (;;)
  {
    try
    {
      if (!source_->next (frame))
        return false;
      ++delivered_;
      return true;
    }
    catch (const pcl::IOException &e)
    {
      ++skipped_;
      // PCL prefixes the text with ": " when no function is named.
      std::string message = e.what ();
      if (message.rfind (": ", 0) == 0)
        message.erase (0, 2);
      // Each call of a well-behaved reader moves one frame on: more failures than frames mean
      // one that does not, which must not spin here.
      if (skipped_ + delivered_ > source_->size ())
        throw pcl::IOException ("recording: more bad frames than the " + std::to_string (source_->size ()) +
                                " frames it has; the reader does not move past them (last: " + message + ")");
      if (messages_.size () < kKeptMessages)
        messages_.push_back (message);
      if (warning_)
        warning_ (message);
    }
  }
}

} // namespace texlet
} // namespace pcl
