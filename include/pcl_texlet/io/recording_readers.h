/*
 * pcl_texlet: the other recording formats of DESIGN.md section 4, read through the streaming
 * RecordingReader interface of recording.h, and a writer of the recording-folder format.
 *
 * - a folder of organised PCD files (or one organised PCD file),
 * - the TIFF frames and intrinsics.xml that PCL's image grabber writes,
 * - .oni files, played through pcl::io::OpenNI2Grabber,
 * - openRecording (), which picks the reader from what a path is.
 *
 * Every reader hands out one frame per next () call; none holds more than a few frames.
 */
#pragma once

#include <pcl_texlet/io/recording.h>

#include <cstddef>
#include <cstdint>
#include <memory>
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
class PcdFolderReader : public RecordingReader
{
public:
  /** \throws pcl::IOException naming the path when it holds no PCD file, or naming the first
    *         file when it cannot be read, is not organised or carries no camera to recover.
    */
  explicit PcdFolderReader (const std::string &path);

  std::size_t
  size () const override { return files_.size (); }

  const CameraInfo &
  cameraInfo () const override { return info_; }

  /** \throws pcl::IOException naming the file: unreadable or corrupt PCD, no x/y/z fields,
    *         not organised, a size that differs from the first frame's, a depth beyond 65535 mm.
    */
  bool
  next (DepthFrame &frame) override;

  /** \brief The PCD files, in the order next () reads them. */
  const std::vector<std::string> &
  files () const { return files_; }

  /** \brief The *.pcd files (any case of the extension) directly in \a folder, sorted by name;
    * empty when there are none or \a folder is not a folder.
    */
  static std::vector<std::string>
  listPcdFiles (const std::string &folder);

  /** \brief True if \a folder directly holds at least one *.pcd file. */
  static bool
  hasPcdFiles (const std::string &folder) { return !listPcdFiles (folder).empty (); }

private:
  std::vector<std::string> files_;
  CameraInfo info_;
  std::size_t next_ = 0;
  DepthFrame first_; ///< read in the constructor for the intrinsics, handed out by the first next ()
};

/** \brief Load the depth intrinsics from an intrinsics.xml written by PCL's image grabber: the
  * five numbers focal_length_x, focal_length_y, principal_point_x, principal_point_y and
  * z_multiplication_factor of its <depth> element. The file holds two top-level elements
  * (<rgb> and <depth>), as PCL writes it, and is parsed like PCL does, with boost::property_tree.
  *
  * The returned CameraInfo has width and height 0 (the file does not store the image size) and no
  * distortion.
  * \throws pcl::IOException naming the file and the problem: missing, not valid XML, no single
  *         <depth> element, a missing, repeated or non-numeric value, a non-positive focal length,
  *         or a z_multiplication_factor other than 0.001 (depth in millimetres).
  */
CameraInfo
loadGrabberIntrinsicsXml (const std::string &path);

/** \brief Read a 16-bit single-channel (grey) TIFF: depth in millimetres, 0 = no reading.
  * \throws pcl::IOException naming the file and the problem (missing, not a TIFF, truncated or
  *         corrupt, not 16-bit, not one sample per pixel, tiled or planar layout).
  */
std::vector<std::uint16_t>
readDepthTiff (const std::string &path, int &width, int &height);

/** \brief Read an 8-bit RGB (or RGBA, alpha dropped) TIFF into row-major RGB triplets.
  * \throws pcl::IOException naming the file and the problem, as readDepthTiff.
  */
std::vector<std::uint8_t>
readRgbTiff (const std::string &path, int &width, int &height);

/** \brief Reader of the frames PCL's image grabber writes (pcl_openni2_image / ImageGrabber):
  * <folder>/intrinsics.xml and <folder>/tiff/frame_<stamp>_depth.tiff (16-bit depth in mm), with
  * optional frame_<stamp>_rgb.tiff (8-bit RGB) beside each.
  *
  * The folder given may also be the one that holds the TIFFs; intrinsics.xml is then looked for
  * in it and in its parent. Frames are read in name order; a frame's name is "frame_<stamp>".
  * The image size is the first depth TIFF's.
  */
class GrabberTiffReader : public RecordingReader
{
public:
  /** \throws pcl::IOException naming the folder when it holds no *_depth.tiff or no
    *         intrinsics.xml, or naming the file that cannot be read.
    */
  explicit GrabberTiffReader (const std::string &folder);

  std::size_t
  size () const override { return depth_files_.size (); }

  const CameraInfo &
  cameraInfo () const override { return info_; }

  /** \throws pcl::IOException naming the file: unreadable, truncated, wrong bit depth or samples
    *         per pixel, or a size that differs from the first depth frame's.
    */
  bool
  next (DepthFrame &frame) override;

  /** \brief True if \a folder holds *_depth.tiff files, directly or in tiff/. */
  static bool
  isGrabberTiffFolder (const std::string &folder);

private:
  std::vector<std::string> depth_files_;
  std::string first_depth_file_; ///< the file that set the image size, named in size errors
  CameraInfo info_;
  std::size_t next_ = 0;
};

/** \brief Reader of .oni recordings, played back through pcl::io::OpenNI2Grabber.
  *
  * Every depth frame of the file comes out once, in file order, unchanged: the grabber's
  * depth-image callback copies each frame into a small queue that next () takes it from.
  * OpenNI2's player runs in manual mode with repeat off, on the same (reference-counted) OpenNI2
  * device the grabber opened, and next () releases the file's records one at a time, each only
  * after the grabber has delivered the previous depth frame, so that OpenNI2 never replaces a
  * frame the grabber has not read (see the notes in recording_readers.cpp). A slow caller holds
  * the player, it loses nothing. Every wait is bounded by \a timeout_s seconds, so that a file
  * OpenNI2 cannot play never hangs the caller.
  *
  * Frames are checked to be consecutive; their names are the 1-based frame index, zero-padded to
  * six digits. Only the depth stream is read (no colour). After the last frame the playback is
  * closed.
  *
  * Intrinsics: an .oni file stores the depth stream's field of view, not a calibration, so the
  * focal length is the grabber's (width / (2 tan (hFOV / 2))) for both axes and the principal
  * point is the image centre ((width - 1) / 2, (height - 1) / 2), as the grabber's own point
  * clouds use them: the OpenNI flaws of DESIGN.md section 2 stay until a calibration replaces them.
  */
class OniReader : public RecordingReader
{
public:
  /** \throws pcl::IOException naming the file when it is missing, not an .oni file OpenNI2 can
    *         open, has no depth stream, no frame count (not finalised), no cropping property (such
    *         recordings play back no frame in OpenNI2 2.2), no field of view, or depth not in mm;
    *         also when this PCL was built without OpenNI2.
    */
  explicit OniReader (const std::string &file, double timeout_s = 5.0);
  ~OniReader () override;

  OniReader (const OniReader &) = delete;
  OniReader &
  operator= (const OniReader &) = delete;

  std::size_t
  size () const override { return size_; }

  const CameraInfo &
  cameraInfo () const override { return info_; }

  /** \throws pcl::IOException naming the file when a frame does not arrive within the timeout or
    *         arrives out of order.
    */
  bool
  next (DepthFrame &frame) override;

private:
  struct Playback;
  std::string file_;
  double timeout_s_;
  CameraInfo info_;
  std::size_t size_ = 0;
  std::size_t delivered_ = 0;
  unsigned last_index_ = 0; ///< frame index of the last frame taken
  std::unique_ptr<Playback> playback_;
};

/** \brief What kind of recording a path is, judged from names only (no file is read). */
enum class RecordingKind
{
  recording_folder,    ///< camera.yaml and/or depth/: RecordingFolderReader
  grabber_tiff_folder, ///< *_depth.tiff files, directly or in tiff/: GrabberTiffReader
  pcd_folder,          ///< *.pcd files: PcdFolderReader
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
