/*
 * pcl_texlet tests: every frame of a recording reader, in memory.
 */
#pragma once

#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/io/recording_reader.h>

#include <vector>

namespace pcl_texlet_test
{

/** \brief Reads every frame of \a reader (next () until it says the end). */
inline std::vector<pcl::texlet::DepthFrame>
readAll (pcl::texlet::RecordingReader &reader)
{
  std::vector<pcl::texlet::DepthFrame> frames;
  pcl::texlet::DepthFrame frame;
  while (reader.next (frame))
    frames.push_back (frame);
  return frames;
}

} // namespace pcl_texlet_test
