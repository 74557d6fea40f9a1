/*
 * pcl_texlet tests: small recording folders written the way the library writes them
 * (RecordingFolderWriter), with a depth given per pixel and frame.
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>
#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/io/recording_writer.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

namespace pcl_texlet_test
{

/** \brief A pinhole of \a width x \a height pixels with focal length \a f pixels and the principal
  * point at the image centre ((width - 1) / 2, (height - 1) / 2); no distortion.
  */
inline pcl::texlet::CameraInfo
centredCamera (int width, int height, double f)
{
  pcl::texlet::CameraInfo info;
  info.width = width;
  info.height = height;
  const double K[9] = {f, 0, (width - 1) / 2.0, 0, f, (height - 1) / 2.0, 0, 0, 1};
  std::copy (K, K + 9, info.K);
  return info;
}

/** \brief A small, odd-sized camera (33 x 17) whose every camera.yaml field is set, with values
  * that are not round in decimal: for round trips of the camera and of recording folders.
  */
inline pcl::texlet::CameraInfo
camera33x17 ()
{
  pcl::texlet::CameraInfo info;
  info.width = 33;
  info.height = 17;
  const double K[9] = {570.3422241210938, 0, 16.1, 0, 570.3422241210938, 8.3, 0, 0, 1};
  std::copy (K, K + 9, info.K);
  info.D = {0.1, -0.25, 0.001, -0.002, 1.0 / 3.0};
  info.baseline_m = 0.0752;
  info.disparity_subpixel = 0.0625;
  return info;
}

/** \brief Writes the recording folder \a folder (which must not exist): camera.yaml from \a info
  * and \a frames depth frames 000000, 000001, ... whose depth at pixel (u, v) of frame f is
  * \a depth_mm (u, v, f) millimetres; no colour.
  * \return \a folder
  */
template <typename Depth> std::filesystem::path
writeRecordingFolder (const std::filesystem::path &folder, const pcl::texlet::CameraInfo &info, int frames,
                      Depth depth_mm)
{
  pcl::texlet::RecordingFolderWriter writer (folder.string (), info);
  for (int f = 0; f < frames; ++f)
  {
    pcl::texlet::DepthFrame frame;
    char name[16];
    std::snprintf (name, sizeof (name), "%06d", f);
    frame.name = name;
    frame.width = info.width;
    frame.height = info.height;
    frame.depth_mm.resize (static_cast<std::size_t> (info.width) * info.height);
    for (int v = 0; v < info.height; ++v)
      for (int u = 0; u < info.width; ++u)
        frame.depth_mm[static_cast<std::size_t> (v) * info.width + u] = static_cast<std::uint16_t> (depth_mm (u, v, f));
    writer.writeFrame (frame);
  }
  writer.commit ();
  return folder;
}

} // namespace pcl_texlet_test
