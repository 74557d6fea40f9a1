/*
 * pcl_texlet io: a folder of raw 11-bit Kinect disparity images (16-bit PGM, as libfreenect and
 * Herrera's Kinect calibration toolbox write them) with their depth calibration, as a recording
 * (docs/inputs.md, "Raw Kinect disparity folder").
 */
#pragma once

#include <pcl_texlet/io/frame_file_reader.h>
#include <pcl_texlet/io/kinect_disparity_calibration.h>

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Reader of a raw Kinect disparity folder: 16-bit binary PGM files of raw disparity d,
  * one per frame, and a calibration YAML (loadKinectDisparityCalibration) in the folder.
  *
  * The frames are the folder's *-d.pgm files when it has any (the toolbox's naming, whose colour
  * images lie beside them as *-c1.pgm), else all its *.pgm files, read in name order; a frame's
  * name is the file's stem. Each pixel's depth is KinectDisparityCalibration::depthMm: rounded
  * millimetres of z = 1 / (c0 + c1 d), 0 (no reading) for d >= 2047 and where z is not positive,
  * not finite or above 65535 mm.
  *
  * Samples are big-endian as the PGM specification says. libfreenect's recorder writes them in
  * the host's (little-endian) order instead; like the toolbox's read_disparity, which swaps a
  * frame whose samples exceed 11 bits only when swapped, a frame is read byte-swapped when more
  * of its samples are at most 2047 that way.
  *
  * The image size is the calibration's image_width x image_height when it gives them, else the
  * first frame's; every frame must have it.
  */
class KinectDisparityReader : public FrameFileReader
{
public:
  /** \brief Opens \a folder with the calibration \a calibration_path, or when that is empty the
    * folder's calibration file (kinectCalibrationNames (), the first present).
    * \throws pcl::IOException naming the folder when it does not exist, holds no *.pgm file or
    *         no calibration file, or naming the file with the problem (the calibration's keys,
    *         the first frame when it gives the size and cannot be read, dc_beta of another size).
    */
  explicit KinectDisparityReader (const std::string &folder, const std::string &calibration_path = "");

  /** \brief The calibration's file names looked for in the folder, in order. */
  static const std::vector<std::string> &
  kinectCalibrationNames ();

  /** \brief The frame files of \a folder: its *-d.pgm files if any, else its *.pgm files, sorted. */
  static std::vector<std::string>
  listDisparityPgms (const std::string &folder);

  /** \brief True if \a folder holds *.pgm files or a calibration file (either half, so that the
    * reader names the other).
    */
  static bool
  isKinectDisparityFolder (const std::string &folder);

  /** \brief The calibration the depths are computed with. */
  const KinectDisparityCalibration &
  calibration () const { return calib_; }

protected:
  /** \throws pcl::IOException naming the PGM: unreadable, not P5, 8-bit, truncated, or of a
    *         size differing from the recording's.
    */
  void
  readFrame (std::size_t index, DepthFrame &frame) override;

private:
  KinectDisparityCalibration calib_;
};

} // namespace texlet
} // namespace pcl
