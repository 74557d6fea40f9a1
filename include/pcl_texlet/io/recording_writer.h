/*
 * pcl_texlet io: writing recording folders (the format: docs/inputs.md) so that no reader ever
 * sees half of one.
 *
 * Everything goes into a hidden temporary folder beside the destination (an AtomicFile), which
 * is renamed onto the destination by commit (); a writer destroyed before commit removes its
 * temporary folder, so a failed or interrupted run leaves no recording behind.
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>
#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/common/atomic_file.h>

#include <optional>
#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Writes one recording folder: camera.yaml at construction, depth frames and
  * meta.yaml as they come, everything visible under the destination only after commit ().
  */
class RecordingFolderWriter
{
public:
  /** \brief Starts a recording at \a folder with the intrinsics \a info (camera.yaml).
    * \throws pcl::IOException if \a folder already exists, its parent folder does not, or the
    *         temporary folder cannot be made.
    * \throws pcl::BadArgumentException for a non-positive image size in \a info.
    */
  RecordingFolderWriter (const std::string &folder, const CameraInfo &info);

  RecordingFolderWriter (const RecordingFolderWriter &) = delete;
  RecordingFolderWriter &
  operator= (const RecordingFolderWriter &) = delete;

  /** \brief Removes the temporary folder unless commit () succeeded. */
  ~RecordingFolderWriter ();

  /** \brief Writes depth/<frame.name>.png, and rgb/<frame.name>.png when the frame has colour.
    * Safe to call from several threads at once for different frames.
    * \throws pcl::BadArgumentException if the frame's size differs from camera.yaml's, its
    *         buffers do not match its size, or its name is empty or not a plain file name.
    * \throws pcl::IOException if the PNG cannot be written.
    */
  void
  writeFrame (const DepthFrame &frame) const;

  /** \brief Writes meta.yaml with the given text. \throws pcl::IOException on failure. */
  void
  writeMeta (const std::string &yaml) const;

  /** \brief Renames the temporary folder onto the destination.
    * \throws pcl::IOException if the rename fails (the temporary folder is then removed).
    */
  void
  commit ();

  /** \brief The destination. */
  const std::string &
  folder () const { return folder_; }

  /** \brief Where the files go until commit (). */
  const std::string &
  temporaryFolder () const { return tmp_->temporaryPath (); }

private:
  std::string folder_;
  CameraInfo info_;
  std::optional<AtomicFile> tmp_; ///< set once the destination is known to be free
  bool committed_ = false;
};

} // namespace texlet
} // namespace pcl
