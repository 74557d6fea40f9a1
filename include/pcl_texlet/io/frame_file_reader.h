/*
 * pcl_texlet io: what the readers of a recording stored as one file per frame share: the
 * sorted list of frame files, the intrinsics, the place in the list, and the size check.
 */
#pragma once

#include <pcl_texlet/io/recording_reader.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Base of the readers whose recording is a list of frame files, read in list order.
  *
  * A derived reader fills files_ and info_ in its constructor and reads one file in readFrame ();
  * next () moves past a file before reading it, so that a caller that catches a bad frame's
  * exception goes on with the next one.
  */
class FrameFileReader : public RecordingReader
{
public:
  std::size_t
  size () const override { return files_.size (); }

  const CameraInfo &
  cameraInfo () const override { return info_; }

  bool
  next (DepthFrame &frame) override;

  /** \brief The frame files, in the order next () reads them. */
  const std::vector<std::string> &
  files () const { return files_; }

protected:
  /** \brief Reads frame \a index (files_[index]) into \a frame.
    * \throws pcl::IOException naming the file for a bad frame.
    */
  virtual void
  readFrame (std::size_t index, DepthFrame &frame) = 0;

  /** \brief Checks that the image \a path (a \a what: "depth PNG", "RGB TIFF", ...) is
    * \a width x \a height pixels, the recording's size.
    * \throws pcl::IOException "<what> '<path>' is WxH but <size_source_>" otherwise.
    */
  void
  checkSize (const std::string &what, const std::string &path, int width, int height) const;

  /** \brief How one image format is read: its names in messages and its readers. */
  struct ImageFormat
  {
    const char *depth_what; ///< e.g. "depth PNG"
    std::vector<std::uint16_t> (*read_depth) (const std::string &path, int &width, int &height);
    const char *rgb_what;   ///< e.g. "RGB PNG"
    std::vector<std::uint8_t> (*read_rgb) (const std::string &path, int &width, int &height);
  };

  /** \brief Reads the depth image \a depth_path into \a frame, and the colour image \a rgb_path
    * where it exists, both in \a format and checked with checkSize.
    */
  void
  readImages (const ImageFormat &format, const std::string &depth_path, const std::string &rgb_path,
              DepthFrame &frame) const;

  std::vector<std::string> files_; ///< the frame files, in reading order
  CameraInfo info_;                ///< the recording's intrinsics and image size
  std::string size_source_;        ///< where the size comes from, for checkSize's message

private:
  std::size_t next_ = 0;
};

} // namespace texlet
} // namespace pcl
