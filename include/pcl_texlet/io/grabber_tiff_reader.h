/*
 * pcl_texlet io: the frames PCL's image grabber writes (TIFF images and intrinsics.xml) as a
 * recording.
 */
#pragma once

#include <pcl_texlet/io/frame_file_reader.h>

#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Reader of the frames PCL's image grabber writes (pcl_openni2_image / ImageGrabber):
  * <folder>/intrinsics.xml and <folder>/tiff/frame_<stamp>_depth.tiff (16-bit depth in mm), with
  * optional frame_<stamp>_rgb.tiff (8-bit RGB) beside each.
  *
  * The folder given may also be the one that holds the TIFFs; intrinsics.xml is then looked for
  * in it and in its parent. Frames are read in name order; a frame's name is "frame_<stamp>".
  * The image size is the first depth TIFF's.
  */
class GrabberTiffReader : public FrameFileReader
{
public:
  /** \throws pcl::IOException naming the folder when it holds no *_depth.tiff or no
    *         intrinsics.xml, or naming the file that cannot be read.
    */
  explicit GrabberTiffReader (const std::string &folder);

  /** \brief True if \a folder holds *_depth.tiff files, directly or in tiff/. */
  static bool
  isGrabberTiffFolder (const std::string &folder);

protected:
  /** \throws pcl::IOException naming the file: unreadable, truncated, wrong bit depth or samples
    *         per pixel, or a size that differs from the first depth frame's.
    */
  void
  readFrame (std::size_t index, DepthFrame &frame) override;
};

} // namespace texlet
} // namespace pcl
