/*
 * pcl_texlet_lab: a recording of any length measured in bounded memory.
 *
 * The lab keeps the frames it measures (it fits on even frames and scores on odd ones), so a
 * 10,000-frame recording cannot go in whole: EvenlySpacedFrames streams through every frame of
 * its source and hands on at most N of them, evenly spaced over the recording, so that slow
 * drifts over the whole recording are still seen. Frames not kept are read and dropped at once.
 */
#pragma once

#include <pcl_texlet/io/recording_reader.h>

#include <pcl/exceptions.h>

#include <algorithm>
#include <cstddef>
#include <utility>

namespace pcl_texlet_app
{

/** \brief Hands on at most \a max_frames frames of \a source: frames round (j size / n) for
  * j = 0 .. n - 1, n = min (max_frames, size), reading (and dropping) the others on the way.
  */
class EvenlySpacedFrames : public pcl::texlet::RecordingReader
{
public:
  EvenlySpacedFrames (pcl::texlet::RecordingReader::Ptr source, std::size_t max_frames)
    : source_ (std::move (source)), kept_ (std::min (max_frames, source_->size ()))
  {
    if (max_frames == 0)
      throw pcl::BadArgumentException ("EvenlySpacedFrames: at most 0 frames");
  }

  std::size_t
  size () const override { return kept_; }

  const pcl::texlet::CameraInfo &
  cameraInfo () const override { return source_->cameraInfo (); }

  bool
  next (pcl::texlet::DepthFrame &frame) override
  {
    while (handed_ < kept_ && source_->next (frame))
    {
      const std::size_t index = read_++;
      if (index >= wanted ())
      {
        ++handed_;
        return true;
      }
    }
    return false;
  }

private:
  /** The source index of the next frame to hand on. */
  std::size_t
  wanted () const { return (2 * handed_ * source_->size () + kept_) / (2 * kept_); }

  pcl::texlet::RecordingReader::Ptr source_;
  std::size_t kept_;
  std::size_t read_ = 0, handed_ = 0;
};

} // namespace pcl_texlet_app
