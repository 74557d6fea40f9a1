#include <pcl_texlet/io/frame_file_reader.h>

#include <pcl/exceptions.h>

#include <filesystem>
#include <system_error>
#include <utility>

#include "reader_util.h"

namespace pcl
{
namespace texlet
{

bool
FrameFileReader::next (DepthFrame &frame)
{
  if (next_ >= files_.size ())
    return false;
  // Advance before reading, so a caller that catches a bad frame's exception can go on past it.
  const std::size_t index = next_++;
  DepthFrame result;
  readFrame (index, result);
  frame = std::move (result);
  return true;
}

void
FrameFileReader::checkSize (const std::string &what, const std::string &path, int width, int height) const
{
  if (width != info_.width || height != info_.height)
    throw pcl::IOException (what + " '" + path + "' is " + detail::sizeText (width, height) + " but " + size_source_);
}

void
FrameFileReader::readImages (const ImageFormat &format, const std::string &depth_path, const std::string &rgb_path,
                             DepthFrame &frame) const
{
  frame.depth_mm = format.read_depth (depth_path, frame.width, frame.height);
  checkSize (format.depth_what, depth_path, frame.width, frame.height);
  std::error_code ec;
  if (std::filesystem::exists (rgb_path, ec))
  {
    int width = 0, height = 0;
    frame.rgb = format.read_rgb (rgb_path, width, height);
    checkSize (format.rgb_what, rgb_path, width, height);
  }
}

} // namespace texlet
} // namespace pcl
