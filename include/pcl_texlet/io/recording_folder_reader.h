/*
 * pcl_texlet io: the reader of the recording folder format: camera.yaml, PNG depth frames in
 * depth/, optional PNG colour frames in rgb/, optional meta.yaml (docs/inputs.md).
 */
#pragma once

#include <pcl_texlet/io/frame_file_reader.h>

#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Reader of a recording folder: camera.yaml, the PNG frames of depth/ (sorted by name),
  * optional PNG frames of the same names in rgb/.
  */
class RecordingFolderReader : public FrameFileReader
{
public:
  /** \throws pcl::IOException if the folder, camera.yaml or depth/ is missing or empty. */
  explicit RecordingFolderReader (const std::string &folder);

  /** \brief True if \a folder looks like a recording folder (has camera.yaml and depth/). */
  static bool
  isRecordingFolder (const std::string &folder);

protected:
  /** \throws pcl::IOException naming the PNG that cannot be read or whose size differs from
    *         camera.yaml's.
    */
  void
  readFrame (std::size_t index, DepthFrame &frame) override;

private:
  std::string folder_;
};

} // namespace texlet
} // namespace pcl
