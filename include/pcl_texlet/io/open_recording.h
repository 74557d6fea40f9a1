/*
 * pcl_texlet io: which reader a path needs, and opening it (the formats: docs/inputs.md).
 */
#pragma once

#include <pcl_texlet/io/recording_reader.h>

#include <string>

namespace pcl
{
namespace texlet
{

/** \brief What kind of recording a path is, judged from names only (no file is read). */
enum class RecordingKind
{
  recording_folder,    ///< camera.yaml and/or depth/: RecordingFolderReader
  grabber_tiff_folder, ///< *_depth.tiff files, directly or in tiff/: GrabberTiffReader
  pcd_folder,          ///< *.pcd files: PcdFolderReader
  kinect_disparity_folder, ///< *.pgm files and/or calibration.yml (or .yaml, calib.yml, calib.yaml):
                           ///< KinectDisparityReader
  pcd_file,            ///< one .pcd file: PcdFolderReader, one frame
  oni_file             ///< one .oni file: OniReader
};

/** \brief The kind of recording \a path is, checked in the order of RecordingKind; a folder
  * with either half of a recording folder counts as one, so that its reader names the other half.
  * \throws pcl::IOException naming the path when it does not exist or is none of these.
  */
RecordingKind
recordingKind (const std::string &path);

/** \brief Opens the reader for the recordingKind () of \a path.
  * \throws pcl::IOException naming the path when it is no recording (or does not exist), or the
  *         reader's own exception.
  */
RecordingReader::Ptr
openRecording (const std::string &path);

} // namespace texlet
} // namespace pcl
