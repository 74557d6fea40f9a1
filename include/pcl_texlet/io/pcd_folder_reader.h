/*
 * pcl_texlet io: organised PCD files as a recording: a folder of them, or one file.
 */
#pragma once

#include <pcl_texlet/io/frame_file_reader.h>

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Reader of organised PCD files: every *.pcd file of a folder, sorted by name, or a
  * single .pcd file as a one-frame recording.
  *
  * Each frame's depth is round (z * 1000) mm where z is finite and positive, 0 elsewhere; its
  * colour comes from the cloud's rgb or rgba field when it has one. The frame's name is the
  * file's stem. The intrinsics are recovered from the first cloud with estimatePinholeModel
  * (no distortion), since a PCD file does not store them.
  */
class PcdFolderReader : public FrameFileReader
{
public:
  /** \throws pcl::IOException naming the path when it holds no PCD file, or naming the first
    *         file when it cannot be read, is not organised or carries no camera to recover.
    */
  explicit PcdFolderReader (const std::string &path);

  /** \brief The *.pcd files (any case of the extension) directly in \a folder, sorted by name;
    * empty when there are none or \a folder is not a folder.
    */
  static std::vector<std::string>
  listPcdFiles (const std::string &folder);

  /** \brief True if \a folder directly holds at least one *.pcd file. */
  static bool
  hasPcdFiles (const std::string &folder) { return !listPcdFiles (folder).empty (); }

protected:
  /** \throws pcl::IOException naming the file: unreadable or corrupt PCD, no x/y/z fields,
    *         not organised, a size that differs from the first frame's, a depth beyond 65535 mm.
    */
  void
  readFrame (std::size_t index, DepthFrame &frame) override;

private:
  DepthFrame first_; ///< read in the constructor for the intrinsics, handed out as frame 0
};

} // namespace texlet
} // namespace pcl
