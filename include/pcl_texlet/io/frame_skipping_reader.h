/*
 * pcl_texlet io: the policy for a bad frame in the middle of a recording (docs/inputs.md, "Bad
 * frames in the middle of a recording").
 *
 * Every reader's next () throws pcl::IOException for a frame it cannot read (unreadable,
 * truncated, wrong bit depth, a size differing from the recording's, a frame an .oni file never
 * delivered) only after moving past it, so that the caller decides. A long recording with one
 * damaged file should not lose the other frames: FrameSkippingReader passes over such frames,
 * reports each through a callback and counts them, so that an app can state the count in its
 * output. Other exceptions (bad arguments, bugs) still propagate.
 */
#pragma once

#include <pcl_texlet/io/recording_reader.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief A RecordingReader that skips the frames its source reader cannot read.
  *
  * Wraps any reader; next () returns the next frame the source reads, calling the warning
  * callback with the source's message for each frame it passes over. The first frame a reader
  * needs for the recording's intrinsics (e.g. PcdFolderReader's) is read when the source is
  * constructed, so a bad first frame there is still an error of the constructor.
  */
class FrameSkippingReader : public RecordingReader
{
public:
  /** \brief Called with the reader's message (naming the file and the problem) per skipped frame. */
  using Warning = std::function<void (const std::string &message)>;

  /** \throws pcl::BadArgumentException if \a source is null. */
  explicit FrameSkippingReader (RecordingReader::Ptr source, Warning warning = Warning ());

  std::size_t
  size () const override { return source_->size (); }

  const CameraInfo &
  cameraInfo () const override { return source_->cameraInfo (); }

  /** \brief The next frame the source can read; false at the end of the recording.
    * \throws pcl::IOException if the source throws more often than it has frames (a reader that
    *         does not move past a bad frame would otherwise make this loop forever).
    */
  bool
  next (DepthFrame &frame) override;

  /** \brief Frames passed over so far. */
  std::size_t
  skipped () const { return skipped_; }

  /** \brief Frames handed out so far. */
  std::size_t
  delivered () const { return delivered_; }

  /** \brief The messages of the first few skipped frames (at most 100, so that memory stays
    * bounded however long the recording).
    */
  const std::vector<std::string> &
  skippedMessages () const { return messages_; }

private:
  RecordingReader::Ptr source_;
  Warning warning_;
  std::size_t skipped_ = 0, delivered_ = 0;
  std::vector<std::string> messages_;
};

} // namespace texlet
} // namespace pcl
