#include <pcl_texlet/io/recording_readers.h>

#include <pcl_texlet/camera/camera_estimation.h>
#include <pcl_texlet/camera/valid_point.h>

#include <pcl/common/io.h> // pcl::getFieldIndex
#include <pcl/conversions.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/pcl_config.h> // HAVE_OPENNI2
#include <pcl/point_types.h>

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>

#include <tiffio.h>

#ifdef HAVE_OPENNI2
#include "grabber_depth_queue.h"

#include <pcl_texlet/io/guarded_openni2_grabber.h>

#include <pcl/io/openni2/openni2_device.h>

#include <OpenNI.h>
#endif

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

std::string
sizeText (int width, int height)
{
  return std::to_string (width) + "x" + std::to_string (height);
}

/** \brief The text of an exception without PCL's "function in file @ line : " prefix, on one line. */
std::string
description (const std::exception &e)
{
  std::string text = e.what ();
  if (text.rfind (": ", 0) == 0)
    text.erase (0, 2);
  else if (const auto cut = text.find (" : "); cut != std::string::npos && dynamic_cast<const pcl::PCLException *> (&e))
    text.erase (0, cut + 3);
  // OpenNI2's messages come with tabs and newlines; the callers report on one line.
  std::string line;
  for (const char c : text)
  {
    if (std::isspace (static_cast<unsigned char> (c)))
    {
      if (!line.empty () && line.back () != ' ')
        line += ' ';
    }
    else
      line += c;
  }
  while (!line.empty () && line.back () == ' ')
    line.pop_back ();
  return line;
}

std::string
lowerExtension (const fs::path &path)
{
  std::string ext = path.extension ().string ();
  std::transform (ext.begin (), ext.end (), ext.begin (), [] (unsigned char c) { return std::tolower (c); });
  return ext;
}

bool
endsWith (const std::string &text, const std::string &suffix)
{
  return text.size () >= suffix.size () && text.compare (text.size () - suffix.size (), suffix.size (), suffix) == 0;
}

/** \brief The regular files of \a folder whose name satisfies \a keep, sorted (one folder, so by name). */
template <typename Keep> std::vector<std::string>
listFiles (const fs::path &folder, Keep keep)
{
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory (folder, ec))
    return files;
  for (fs::directory_iterator it (folder, ec), end; !ec && it != end; it.increment (ec))
  {
    std::error_code type_ec; // a dangling link is skipped, not an error of the listing
    if (keep (it->path ().filename ().string ()) && it->is_regular_file (type_ec))
      files.push_back (it->path ().string ());
  }
  if (ec)
    throw pcl::IOException ("folder '" + folder.string () + "': cannot list its files: " + ec.message ());
  std::sort (files.begin (), files.end ());
  return files;
}

const char *const kDepthTiffSuffix = "_depth.tiff";
const char *const kRgbTiffSuffix = "_rgb.tiff";

std::vector<std::string>
listDepthTiffs (const fs::path &folder)
{
  return listFiles (folder, [] (const std::string &name) { return endsWith (name, kDepthTiffSuffix); });
}

// ---------------------------------------------------------------------------------------------
// PCD

/** \brief Depth in mm (and colour, when PointT has it) of one organised cloud; \a path names it in errors. */
template <typename PointT> void
cloudToFrame (const pcl::PointCloud<PointT> &cloud, const std::string &path, DepthFrame &frame)
{
  frame.width = static_cast<int> (cloud.width);
  frame.height = static_cast<int> (cloud.height);
  frame.depth_mm.assign (cloud.size (), 0);
  constexpr bool colour = pcl::traits::has_color_v<PointT>;
  if constexpr (colour)
    frame.rgb.assign (3 * cloud.size (), 0);
  else
    frame.rgb.clear ();
  for (std::size_t i = 0; i < cloud.size (); ++i)
  {
    const PointT &p = cloud[i];
    if (isValidDepthPoint (p))
    {
      const double mm = std::round (static_cast<double> (p.z) * 1000.0);
      if (mm > std::numeric_limits<std::uint16_t>::max ())
      {
        std::ostringstream msg;
        msg << "PCD file '" << path << "': depth " << p.z << " m at pixel (" << i % cloud.width << ", "
            << i / cloud.width << ") does not fit 16-bit millimetres";
        throw pcl::IOException (msg.str ());
      }
      frame.depth_mm[i] = static_cast<std::uint16_t> (mm);
    }
    if constexpr (colour)
    {
      frame.rgb[3 * i] = p.r;
      frame.rgb[3 * i + 1] = p.g;
      frame.rgb[3 * i + 2] = p.b;
    }
  }
}

/** \brief Reads one organised PCD file into \a frame; with \a info, also recovers the intrinsics. */
void
readPcdFrame (const std::string &path, DepthFrame &frame, CameraInfo *info)
{
  const std::string what = "PCD file '" + path + "': ";
  std::error_code ec;
  if (!fs::is_regular_file (path, ec))
    throw pcl::IOException (what + "does not exist or is not a file");

  // The header is checked first: PCL 1.13's PCDReader::read crashes on a text file whose
  // "header" has no points, which readHeader accepts.
  pcl::PCLPointCloud2 blob;
  {
    Eigen::Vector4f origin;
    Eigen::Quaternionf orientation;
    int version = 0, data_type = 0;
    unsigned int offset = 0;
    if (pcl::PCDReader ().readHeader (path, blob, origin, orientation, version, data_type, offset) != 0)
      throw pcl::IOException (what + "cannot read it: not a PCD file, or a corrupt header");
  }
  if (pcl::getFieldIndex (blob, "x") < 0 || pcl::getFieldIndex (blob, "y") < 0 || pcl::getFieldIndex (blob, "z") < 0)
    throw pcl::IOException (what + "cannot read it: not a PCD file with x, y, z fields");
  if (blob.width == 0 || blob.height == 0)
    throw pcl::IOException (what + "holds no points");
  if (blob.height <= 1)
    throw pcl::IOException (what + "is not an organised cloud (" + std::to_string (blob.width) + "x" +
                            std::to_string (blob.height) + "): a depth frame needs the pixel grid");
  if (pcl::PCDReader ().read (path, blob) != 0)
    throw pcl::IOException (what + "cannot read its points: corrupt or truncated data");
  if (blob.data.size () != std::size_t (blob.point_step) * blob.width * blob.height)
    throw pcl::IOException (what + "holds " + std::to_string (blob.data.size ()) + " bytes of points, expected " +
                            std::to_string (std::size_t (blob.point_step) * blob.width * blob.height) +
                            ": truncated or corrupt");

  const auto convert = [&] (auto &cloud) {
    pcl::fromPCLPointCloud2 (blob, cloud);
    cloudToFrame (cloud, path, frame);
    if (!info)
      return;
    double K[9];
    try
    {
      const PinholeModel camera = estimatePinholeModel (cloud);
      const double k[9] = {camera.fx (), 0, camera.cx (), 0, camera.fy (), camera.cy (), 0, 0, 1};
      std::copy (k, k + 9, K);
    }
    catch (const pcl::PCLException &e)
    {
      throw pcl::IOException (what + "cannot recover the intrinsics from it (" + description (e) + ")");
    }
    *info = CameraInfo ();
    info->width = frame.width;
    info->height = frame.height;
    std::copy (K, K + 9, info->K);
  };
  if (pcl::getFieldIndex (blob, "rgb") >= 0 || pcl::getFieldIndex (blob, "rgba") >= 0)
  {
    pcl::PointCloud<pcl::PointXYZRGBA> cloud;
    convert (cloud);
  }
  else
  {
    pcl::PointCloud<pcl::PointXYZ> cloud;
    convert (cloud);
  }
  frame.name = fs::path (path).stem ().string ();
}

// ---------------------------------------------------------------------------------------------
// TIFF
//
// libtiff reports through handlers; the per-file handlers of TIFFOpenExt keep the first error's
// text for the exception, instead of libtiff's default of printing it to stderr.

struct TiffMessages
{
  std::string error;
};

int
tiffErrorHandler (TIFF *, void *user_data, const char *module, const char *format, va_list args)
{
  TiffMessages *messages = static_cast<TiffMessages *> (user_data);
  if (messages->error.empty ())
  {
    char text[512];
    std::vsnprintf (text, sizeof (text), format, args);
    messages->error = (module && *module ? std::string (module) + ": " : std::string ()) + text;
  }
  return 1; // handled: libtiff's global handler stays silent
}

/** \brief Warnings (unknown tags, odd but readable files) do not make the pixels wrong. */
int
tiffWarningHandler (TIFF *, void *, const char *, const char *, va_list)
{
  return 1;
}

/** \brief An open TIFF file, closed on destruction, with the messages of its handlers. */
class TiffFile
{
public:
  TiffFile (const std::string &path, const std::string &what) : path_ (path), what_ (what)
  {
    std::error_code ec;
    if (!fs::exists (path, ec))
      throw error ("file does not exist");
    TIFFOpenOptions *options = TIFFOpenOptionsAlloc ();
    if (!options)
      throw error ("libtiff could not allocate its options");
    TIFFOpenOptionsSetErrorHandlerExtR (options, tiffErrorHandler, &messages_);
    TIFFOpenOptionsSetWarningHandlerExtR (options, tiffWarningHandler, nullptr);
    tiff_ = TIFFOpenExt (path.c_str (), "r", options);
    TIFFOpenOptionsFree (options);
    if (!tiff_)
      throw error ("not a TIFF file, or truncated or unreadable (" + libtiffText () + ")");
  }

  TiffFile (const TiffFile &) = delete;
  TiffFile &
  operator= (const TiffFile &) = delete;

  ~TiffFile ()
  {
    if (tiff_)
      TIFFClose (tiff_);
  }

  TIFF *
  get () const { return tiff_; }

  pcl::IOException
  error (const std::string &problem) const
  {
    return pcl::IOException (what_ + " '" + path_ + "': " + problem);
  }

  std::string
  libtiffText () const
  {
    return "libtiff: " + (messages_.error.empty () ? std::string ("no message") : messages_.error);
  }

  /** \brief Image size, checked to be positive and small enough to allocate. */
  void
  size (std::uint32_t &width, std::uint32_t &height) const
  {
    if (!TIFFGetField (tiff_, TIFFTAG_IMAGEWIDTH, &width) || !TIFFGetField (tiff_, TIFFTAG_IMAGELENGTH, &height))
      throw error ("has no image width or length tag");
    // 2^28 pixels (16k x 16k) is far beyond any depth camera; it keeps the allocation sane.
    if (width == 0 || height == 0 || std::uint64_t (width) * height > (std::uint64_t (1) << 28))
      throw error ("has an image size of " + std::to_string (width) + "x" + std::to_string (height));
  }

private:
  std::string path_;
  std::string what_;
  TiffMessages messages_;
  TIFF *tiff_ = nullptr;
};

enum class TiffKind { depth, rgb };

template <typename T> std::vector<T>
readTiff (const std::string &path, TiffKind kind, int &width, int &height)
{
  const TiffFile file (path, kind == TiffKind::depth ? "depth TIFF" : "RGB TIFF");
  TIFF *tiff = file.get ();
  std::uint32_t w = 0, h = 0;
  file.size (w, h);
  std::uint16_t bits = 0, samples = 0, format = 0, planar = 0, photometric = 0;
  TIFFGetFieldDefaulted (tiff, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted (tiff, TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted (tiff, TIFFTAG_SAMPLEFORMAT, &format);
  TIFFGetFieldDefaulted (tiff, TIFFTAG_PLANARCONFIG, &planar);
  if (!TIFFGetField (tiff, TIFFTAG_PHOTOMETRIC, &photometric))
    throw file.error ("has no photometric interpretation tag");

  const std::string found = "found " + std::to_string (bits) + "-bit with " + std::to_string (samples) +
                            " sample" + (samples == 1 ? "" : "s") + " per pixel";
  std::size_t channels = 1;
  if (kind == TiffKind::depth)
  {
    if (bits != 16 || samples != 1)
      throw file.error ("expected 16-bit depth with 1 sample per pixel, " + found);
    if (format != SAMPLEFORMAT_UINT || photometric != PHOTOMETRIC_MINISBLACK)
      throw file.error ("expected unsigned grey samples (0 = black), found sample format " + std::to_string (format) +
                        " and photometric interpretation " + std::to_string (photometric));
  }
  else
  {
    if (bits != 8 || (samples != 3 && samples != 4))
      throw file.error ("expected 8-bit RGB or RGBA (3 or 4 samples per pixel), " + found);
    if (format != SAMPLEFORMAT_UINT || photometric != PHOTOMETRIC_RGB)
      throw file.error ("expected unsigned RGB samples, found sample format " + std::to_string (format) +
                        " and photometric interpretation " + std::to_string (photometric));
    channels = samples;
  }
  if (TIFFIsTiled (tiff))
    throw file.error ("is tiled; only strip TIFFs (as PCL's grabber writes them) are supported");
  if (channels > 1 && planar != PLANARCONFIG_CONTIG)
    throw file.error ("stores its colour planes separately; only interleaved RGB is supported");

  const std::size_t row_samples = std::size_t (w) * channels;
  if (TIFFScanlineSize64 (tiff) != row_samples * sizeof (T))
    throw file.error ("has rows of " + std::to_string (TIFFScanlineSize64 (tiff)) + " bytes, expected " +
                      std::to_string (row_samples * sizeof (T)));
  std::vector<T> row (row_samples);
  const std::size_t out_channels = kind == TiffKind::depth ? 1 : 3;
  std::vector<T> pixels (std::size_t (w) * h * out_channels);
  for (std::uint32_t y = 0; y < h; ++y)
  {
    // libtiff hands 16-bit samples over in host byte order whatever the file's.
    if (TIFFReadScanline (tiff, row.data (), y) < 0)
      throw file.error ("cannot decode row " + std::to_string (y) + " of " + std::to_string (h) +
                        ": truncated or corrupt (" + file.libtiffText () + ")");
    T *out = pixels.data () + std::size_t (y) * w * out_channels;
    if (channels == out_channels)
      std::copy (row.begin (), row.end (), out);
    else
      for (std::uint32_t x = 0; x < w; ++x) // RGBA: alpha dropped
        std::copy_n (row.data () + std::size_t (x) * channels, 3, out + std::size_t (x) * 3);
  }
  width = static_cast<int> (w);
  height = static_cast<int> (h);
  return pixels;
}

// ---------------------------------------------------------------------------------------------
// intrinsics.xml

pcl::IOException
intrinsicsError (const std::string &path, const std::string &problem)
{
  return pcl::IOException ("intrinsics.xml '" + path + "': " + problem);
}

/** \brief The one <name> child of \a depth as a finite number; nothing else may stand in its text. */
double
intrinsicsValue (const boost::property_tree::ptree &depth, const std::string &name, const std::string &path)
{
  const std::size_t count = depth.count (name);
  if (count != 1)
    throw intrinsicsError (path, "<depth> must hold one <" + name + "> (found " + std::to_string (count) + ")");
  const boost::property_tree::ptree &node = depth.get_child (name);
  if (!node.empty ())
    throw intrinsicsError (path, "<depth><" + name + "> must hold a number, not elements");
  std::string text = node.data ();
  const auto blank = [] (unsigned char c) { return std::isspace (c) != 0; };
  text.erase (text.begin (), std::find_if_not (text.begin (), text.end (), blank));
  text.erase (std::find_if_not (text.rbegin (), text.rend (), blank).base (), text.end ());
  // strtod rather than std::from_chars: libstdc++ 12 has no floating-point from_chars.
  char *end = nullptr;
  errno = 0;
  const double value = text.empty () ? 0.0 : std::strtod (text.c_str (), &end);
  if (text.empty () || end != text.c_str () + text.size () || errno == ERANGE || !std::isfinite (value))
    throw intrinsicsError (path, "<depth><" + name + "> must be a finite number (found '" + node.data () + "')");
  return value;
}

} // namespace

// ---------------------------------------------------------------------------------------------
// PcdFolderReader

PcdFolderReader::PcdFolderReader (const std::string &path)
{
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw pcl::IOException ("PCD recording '" + path + "': does not exist");
  if (fs::is_directory (path, ec))
  {
    files_ = listPcdFiles (path);
    if (files_.empty ())
      throw pcl::IOException ("PCD folder '" + path + "': holds no PCD files (*.pcd)");
  }
  else
    files_.push_back (path);
  readPcdFrame (files_.front (), first_, &info_);
}

bool
PcdFolderReader::next (DepthFrame &frame)
{
  if (next_ >= files_.size ())
    return false;
  // Advance before reading, so a caller that catches a bad frame's exception can go on past it.
  const std::string path = files_[next_++];
  DepthFrame result;
  if (next_ == 1)
    result = std::move (first_);
  else
    readPcdFrame (path, result, nullptr);
  if (result.width != info_.width || result.height != info_.height)
    throw pcl::IOException ("PCD file '" + path + "' is " + sizeText (result.width, result.height) +
                            " but the first frame '" + files_.front () + "' is " + sizeText (info_.width, info_.height));
  frame = std::move (result);
  return true;
}

std::vector<std::string>
PcdFolderReader::listPcdFiles (const std::string &folder)
{
  return listFiles (folder, [] (const std::string &name) { return lowerExtension (name) == ".pcd"; });
}

// ---------------------------------------------------------------------------------------------
// Grabber TIFF frames

CameraInfo
loadGrabberIntrinsicsXml (const std::string &path)
{
  std::error_code ec;
  if (!fs::is_regular_file (path, ec))
    throw intrinsicsError (path, "file does not exist");
  boost::property_tree::ptree tree;
  try
  {
    boost::property_tree::read_xml (path, tree);
  }
  catch (const boost::property_tree::xml_parser_error &e)
  {
    throw intrinsicsError (path, "not valid XML (line " + std::to_string (e.line ()) + ": " + e.message () + ")");
  }
  const std::size_t depths = tree.count ("depth");
  if (depths != 1)
    throw intrinsicsError (path, "must hold one top-level <depth> element (found " + std::to_string (depths) + ")");
  const boost::property_tree::ptree &depth = tree.get_child ("depth");

  CameraInfo info;
  info.width = 0;
  info.height = 0;
  const double fx = intrinsicsValue (depth, "focal_length_x", path);
  const double fy = intrinsicsValue (depth, "focal_length_y", path);
  const double cx = intrinsicsValue (depth, "principal_point_x", path);
  const double cy = intrinsicsValue (depth, "principal_point_y", path);
  const double z_factor = intrinsicsValue (depth, "z_multiplication_factor", path);
  if (!(fx > 0) || !(fy > 0))
  {
    std::ostringstream msg;
    msg << "focal lengths must be positive (found focal_length_x " << fx << ", focal_length_y " << fy << ")";
    throw intrinsicsError (path, msg.str ());
  }
  // The depth TIFFs are read as millimetres; any other unit would silently scale every depth.
  if (std::abs (z_factor - 0.001) > 1e-12)
  {
    std::ostringstream msg;
    msg << "z_multiplication_factor is " << z_factor << "; only 0.001 (depth TIFFs in millimetres) is supported";
    throw intrinsicsError (path, msg.str ());
  }
  const double K[9] = {fx, 0, cx, 0, fy, cy, 0, 0, 1};
  std::copy (K, K + 9, info.K);
  return info;
}

std::vector<std::uint16_t>
readDepthTiff (const std::string &path, int &width, int &height)
{
  return readTiff<std::uint16_t> (path, TiffKind::depth, width, height);
}

std::vector<std::uint8_t>
readRgbTiff (const std::string &path, int &width, int &height)
{
  return readTiff<std::uint8_t> (path, TiffKind::rgb, width, height);
}

GrabberTiffReader::GrabberTiffReader (const std::string &folder)
{
  const std::string what = "grabber TIFF folder '" + folder + "': ";
  std::error_code ec;
  if (!fs::exists (folder, ec))
    throw pcl::IOException (what + "does not exist");
  if (!fs::is_directory (folder, ec))
    throw pcl::IOException (what + "is not a folder");

  // PCL's grabber layout (intrinsics.xml beside tiff/), or the TIFF folder itself.
  std::vector<fs::path> xml_candidates;
  const fs::path root (folder);
  depth_files_ = listDepthTiffs (root / "tiff");
  if (!depth_files_.empty ())
    xml_candidates = {root / "intrinsics.xml"};
  else
  {
    depth_files_ = listDepthTiffs (root);
    fs::path absolute = fs::absolute (root, ec).lexically_normal ();
    if (absolute.filename ().empty ()) // "tiff/": the parent of "tiff", not of its trailing separator
      absolute = absolute.parent_path ();
    xml_candidates = {root / "intrinsics.xml", absolute.parent_path () / "intrinsics.xml"};
  }
  if (depth_files_.empty ())
    throw pcl::IOException (what + "holds no depth frames (*" + kDepthTiffSuffix + "), neither directly nor in tiff/");

  const auto xml = std::find_if (xml_candidates.begin (), xml_candidates.end (),
                                 [&] (const fs::path &p) { return fs::is_regular_file (p, ec); });
  if (xml == xml_candidates.end ())
  {
    std::string looked;
    for (const fs::path &p : xml_candidates)
      looked += (looked.empty () ? "'" : " and '") + p.lexically_normal ().string () + "'";
    throw pcl::IOException (what + "has no intrinsics.xml (looked for " + looked + ")");
  }
  info_ = loadGrabberIntrinsicsXml (xml->string ());

  // intrinsics.xml does not store the image size; the first frame sets it for all.
  first_depth_file_ = depth_files_.front ();
  const TiffFile first (first_depth_file_, "depth TIFF");
  std::uint32_t width = 0, height = 0;
  first.size (width, height);
  info_.width = static_cast<int> (width);
  info_.height = static_cast<int> (height);
}

bool
GrabberTiffReader::next (DepthFrame &frame)
{
  if (next_ >= depth_files_.size ())
    return false;
  // Advance before reading, so a caller that catches a bad frame's exception can go on past it.
  const std::string depth_path = depth_files_[next_++];
  const auto checkSize = [&] (const std::string &path, const char *what, int width, int height) {
    if (width != info_.width || height != info_.height)
      throw pcl::IOException (std::string (what) + " '" + path + "' is " + sizeText (width, height) +
                              " but the first depth frame '" + first_depth_file_ + "' is " +
                              sizeText (info_.width, info_.height));
  };

  DepthFrame result;
  const std::string file_name = fs::path (depth_path).filename ().string ();
  result.name = file_name.substr (0, file_name.size () - std::string (kDepthTiffSuffix).size ());
  result.depth_mm = readDepthTiff (depth_path, result.width, result.height);
  checkSize (depth_path, "depth TIFF", result.width, result.height);

  const fs::path rgb_path = fs::path (depth_path).parent_path () / (result.name + kRgbTiffSuffix);
  std::error_code ec;
  if (fs::exists (rgb_path, ec))
  {
    int width = 0, height = 0;
    result.rgb = readRgbTiff (rgb_path.string (), width, height);
    checkSize (rgb_path.string (), "RGB TIFF", width, height);
  }
  frame = std::move (result);
  return true;
}

bool
GrabberTiffReader::isGrabberTiffFolder (const std::string &folder)
{
  return !listDepthTiffs (fs::path (folder) / "tiff").empty () || !listDepthTiffs (folder).empty ();
}

// ---------------------------------------------------------------------------------------------
// .oni playback
//
// What was found on Debian 12 (OpenNI2 2.2.0.33, PCL 1.13), and why playback works as it does:
// - OpenNI2's OniFile driver drops every frame of a stream whose recording has no cropping
//   property (PlayerStream asks for it per frame and returns when it is missing). OpenNI2's
//   Recorder writes that property only for streams that support cropping, which the Dummy
//   device does not: its recordings open, report their frame count and play back no frame.
// - An OpenNI2 stream holds only its newest frame: one that is not read before the next arrives
//   is lost. The grabber's file device plays in real time with repeat on, and as fast as possible
//   (speed 0) is worse: its listener loses a frame whenever it falls behind the player. So the
//   player runs in manual mode (speed -1), where it releases one record (one frame of one
//   stream) per "poke", and OpenNI2 pokes only inside OpenNI::waitForAnyStream.
// - waitForAnyStream pokes again each time its thread is woken and none of the streams waited on
//   holds a frame, and OpenNI2 wakes a waiting thread for a frame of any stream of the process,
//   also for one delivered before the wait began (one event per thread, left set). A wait that
//   began with that event set, or that woke for the grabber's copy of a depth frame before its
//   own, poked twice and released two records; the second depth frame then replaced the first in
//   the grabber's stream before its listener read it. That is how the previous reader (a stream
//   that was never started, poked with zero-millisecond waits) lost 12 to 29 of the 30 frames of
//   data/simulated/box_qvga.oni.
// - So the reader waits on streams of its own, one per sensor of the file (started: a record
//   needs a poke whenever any stream of its sensor exists, so every record released must be
//   seen), created before the grabber's so that each frame reaches them first. Before each wait
//   it clears its thread's event (a wait on no stream, zero milliseconds, pokes nothing), and it
//   waits again only once the grabber's callback has delivered the depth frame of the last
//   record. One wait, one poke, one record: each depth frame reaches the grabber's stream alone.
//   (A frame of another OpenNI2 device streaming in the same process can still wake the wait
//   early; the frame indices are checked, so that shows as an error, not as silently lost frames.)
// - Opening the same file with openni::Device reaches the grabber's device (OpenNI2 shares open
//   devices by URI and counts references): repeat is switched off and manual mode on through it.
// - Every thread that calls libOpenNI2 (each grabber's stream listener does) leaves an error
//   buffer that libOpenNI2 never frees and later asks pthread_kill about, which faults once glibc
//   has unmapped that thread's stack: a process that plays files one after another needs glibc to
//   keep them mapped (docs/openni2_device.md, "Stopping a grabber"). The reader's own streams have
//   no listener, so they add no such thread; it reads them with readFrame.

#ifdef HAVE_OPENNI2

/** \brief How long OpenNI2's file player gets, once every stream of a file is stopped, to finish
  * a walk of its stream list in which it may have been preempted (several scheduling periods of a
  * loaded machine; the player itself turns every 10 ms).
  */
constexpr std::chrono::milliseconds kOniFilePlayerSettle {50};

/** \brief The grabber, the reader's own handle on its device and streams, and the queue between. */
struct OniReader::Playback
{
  bool openni_initialised = false;
  openni::Device control;     ///< the file again (the grabber's device): playback control
  openni::VideoStream depth;  ///< the reader's depth stream: sees each depth record first
  openni::VideoStream colour; ///< created when the file has colour, to see its records
  openni::VideoStream ir;     ///< created when the file has IR, to see its records
  GrabberDepthQueue queue {2}; ///< one frame per record released, so one at most; the rest is slack
  std::unique_ptr<GuardedOpenNI2Grabber> grabber;

  ~Playback ()
  {
    queue.close ();
    if (grabber)
    {
      try
      {
        grabber->stop (); // waits for its callbacks in flight
      }
      catch (...)
      {} // nothing to report from a destructor; the streams are destroyed below either way
    }
    // Every stream stopped, and the player given time to finish a walk, before any is destroyed.
    // OpenNI2's player thread walks its list of streams without its lock, and destroying the
    // last stream of a sensor unlinks and frees its entry, also without the lock. At the end of a
    // file (repeat off) the player walks in a busy loop while any stream is started; preempted
    // in that walk, it resumed on freed memory once the streams were gone (core dumps: the
    // player faulting in the walk while this thread waited in PlayerDevice::close for it to
    // exit; 3 of 30 runs of the round-trip tests under load). With no stream started it walks
    // once per 10 ms, right after waking, and sleeps in between; the pause below lets a walk
    // that was preempted before the streams stopped run to its end first. (Repeat on would park
    // the player instead, but its rewind rewrites the file's stream properties, freeing the old
    // values while the grabber's callback reads them: a crash in getDepthFocalLength, 1 of 60.)
    for (openni::VideoStream *stream : {&depth, &colour, &ir})
      if (stream->isValid ())
        stream->stop ();
    std::this_thread::sleep_for (kOniFilePlayerSettle);
    for (openni::VideoStream *stream : {&depth, &colour, &ir})
      if (stream->isValid ())
        stream->destroy ();
    grabber.reset ();
    if (control.isValid ())
      control.close ();
    if (openni_initialised)
      openni::OpenNI::shutdown ();
  }

  /** \brief The reader's started streams, depth first. */
  std::vector<openni::VideoStream *>
  watchers ()
  {
    std::vector<openni::VideoStream *> streams;
    for (openni::VideoStream *stream : {&depth, &colour, &ir})
      if (stream->isValid ())
        streams.push_back (stream);
    return streams;
  }

  /** \brief Releases records one at a time until one is a depth frame, and returns the grabber's
    * copy of it.
    * \throws pcl::IOException naming frame \a number of \a size when it does not come within
    *         \a timeout_s seconds, or the grabber's frame is not the released one.
    */
  GrabbedDepthFrame
  take (const std::string &what, double timeout_s, std::size_t number, std::size_t size);
};

namespace
{

/** \brief Clears the calling thread's OpenNI2 wake-up event (set by any frame of any stream since
  * its last wait), so that the next wait pokes a manual-mode player once: a wait on no stream
  * for zero milliseconds consumes the event and pokes no device.
  */
void
clearOpenNI2WakeUp ()
{
  openni::VideoStream *none[] = {nullptr};
  int ready = -1;
  openni::OpenNI::waitForAnyStream (none, 1, &ready, 0);
}

} // namespace

GrabbedDepthFrame
OniReader::Playback::take (const std::string &what, double timeout_s, std::size_t number, std::size_t size)
{
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline =
      Clock::now () + std::chrono::duration_cast<Clock::duration> (std::chrono::duration<double> (timeout_s));
  const auto lost = [&] {
    std::ostringstream msg;
    msg << what << "frame " << number << " of " << size << " did not arrive within " << timeout_s
        << " s (truncated or corrupt recording?)";
    return pcl::IOException (msg.str ());
  };
  std::vector<openni::VideoStream *> streams = watchers ();
  for (;;)
  {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds> (deadline - Clock::now ()).count ();
    if (left <= 0)
      throw lost ();
    clearOpenNI2WakeUp ();
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream (streams.data (), static_cast<int> (streams.size ()), &ready,
                                          static_cast<int> (left)) != openni::STATUS_OK ||
        ready < 0)
      throw lost ();
    openni::VideoFrameRef record;
    if (streams[ready]->readFrame (&record) != openni::STATUS_OK || !record.isValid ())
      throw pcl::IOException (what + "cannot read frame " + std::to_string (number) + " of " + std::to_string (size) +
                              " (" + openni::OpenNI::getExtendedError () + ")");
    if (streams[ready] != &depth)
      continue; // a colour or IR record: the reader plays depth only
    const unsigned index = static_cast<unsigned> (record.getFrameIndex ());
    record.release ();
    // The grabber's stream received the same record right after the reader's; its callback
    // copies it into the queue. No record is released before it is there.
    GrabbedDepthFrame frame;
    if (!queue.pop (frame, deadline))
      throw pcl::IOException (what + "the grabber did not deliver depth frame " + std::to_string (index) + " within " +
                              std::to_string (timeout_s) + " s");
    if (frame.index != index)
      throw pcl::IOException (what + "the grabber delivered depth frame " + std::to_string (frame.index) +
                              " where OpenNI2 played frame " + std::to_string (index));
    return frame;
  }
}

OniReader::OniReader (const std::string &file, double timeout_s) : file_ (file), timeout_s_ (timeout_s)
{
  const std::string what = ".oni file '" + file + "': ";
  if (!(timeout_s > 0) || !std::isfinite (timeout_s))
    throw pcl::BadArgumentException (what + "the frame timeout must be positive and finite");
  std::error_code ec;
  // Checked here: for a path that does not exist the grabber would open any connected camera.
  if (!fs::exists (file, ec))
    throw pcl::IOException (what + "does not exist");
  if (!fs::is_regular_file (file, ec))
    throw pcl::IOException (what + "is not a file");
  if (lowerExtension (file) != ".oni")
    throw pcl::IOException (what + "is not an .oni file (OpenNI2 plays only files named *.oni)");

  playback_ = std::make_unique<Playback> ();
  Playback &p = *playback_;
  p.openni_initialised = openni::OpenNI::initialize () == openni::STATUS_OK;
  if (!p.openni_initialised)
    throw pcl::IOException (what + "cannot initialise OpenNI2 (" + description (std::runtime_error (openni::OpenNI::getExtendedError ())) + ")");
  const auto openniError = [] { return description (std::runtime_error (openni::OpenNI::getExtendedError ())); };
  if (p.control.open (file.c_str ()) != openni::STATUS_OK)
    throw pcl::IOException (what + "OpenNI2 cannot play it: not an .oni recording, or truncated or corrupt (" +
                            openniError () + ")");
  if (!p.control.isFile ())
    throw pcl::IOException (what + "OpenNI2 did not open it as a recording");
  if (!p.control.hasSensor (openni::SENSOR_DEPTH) || p.depth.create (p.control, openni::SENSOR_DEPTH) != openni::STATUS_OK)
    throw pcl::IOException (what + "cannot open its depth stream (" + openniError () + ")");
  OniCropping cropping;
  if (p.depth.getProperty (ONI_STREAM_PROPERTY_CROPPING, &cropping) != openni::STATUS_OK)
    throw pcl::IOException (what + "its depth stream was recorded without the cropping property, and OpenNI2's "
                                   "OniFile driver plays no frame of such a stream (recordings of OpenNI2's Dummy "
                                   "device are like this)");
  const openni::VideoMode mode = p.depth.getVideoMode ();
  if (mode.getPixelFormat () != openni::PIXEL_FORMAT_DEPTH_1_MM)
    throw pcl::IOException (what + "depth pixel format " + std::to_string (mode.getPixelFormat ()) +
                            " is not millimetres (PIXEL_FORMAT_DEPTH_1_MM)");
  if (mode.getResolutionX () <= 0 || mode.getResolutionY () <= 0)
    throw pcl::IOException (what + "depth stream has no image size");
  if (p.control.hasSensor (openni::SENSOR_COLOR) && p.colour.create (p.control, openni::SENSOR_COLOR) != openni::STATUS_OK)
    throw pcl::IOException (what + "cannot open its colour stream (" + openniError () + ")");
  if (p.control.hasSensor (openni::SENSOR_IR) && p.ir.create (p.control, openni::SENSOR_IR) != openni::STATUS_OK)
    throw pcl::IOException (what + "cannot open its IR stream (" + openniError () + ")");

  // The grabber's streams come after the reader's, so each frame reaches the reader's first.
  try
  {
    p.grabber = std::make_unique<GuardedOpenNI2Grabber> (file);
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (what + "OpenNI2 cannot play it: not an .oni recording, or truncated or corrupt (" +
                            description (e) + ")");
  }
  int frames = 0;
  float focal = 0;
  try
  {
    const pcl::io::openni2::OpenNI2Device::Ptr device = p.grabber->getDevice ();
    frames = device->getDepthFrameCount ();
    focal = device->getDepthFocalLength ();
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (what + "cannot read its depth stream (" + description (e) + ")");
  }
  if (frames <= 0)
    throw pcl::IOException (what + "has no depth frame count (" + std::to_string (frames) +
                            "): not a finalised recording (was its recorder stopped?)");
  if (!(focal > 0) || !std::isfinite (focal))
    throw pcl::IOException (what + "its depth stream has no field of view, so no focal length");
  info_.width = mode.getResolutionX ();
  info_.height = mode.getResolutionY ();
  const double f = focal;
  const double K[9] = {f, 0, (info_.width - 1) / 2.0, 0, f, (info_.height - 1) / 2.0, 0, 0, 1};
  std::copy (K, K + 9, info_.K);
  size_ = static_cast<std::size_t> (frames);

  // After the grabber's device set real-time speed, before any stream starts the player.
  openni::PlaybackControl *control = p.control.getPlaybackControl ();
  if (!control || control->setRepeatEnabled (false) != openni::STATUS_OK || control->setSpeed (-1.0f) != openni::STATUS_OK)
    throw pcl::IOException (what + "cannot switch playback to manual without repeat (" + openniError () + ")");
  for (openni::VideoStream *stream : p.watchers ())
    if (stream->start () != openni::STATUS_OK)
      throw pcl::IOException (what + "cannot start playback (" + openniError () + ")");
  try
  {
    p.queue.connect (*p.grabber);
    p.grabber->start ();
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (what + "cannot start playback (" + description (e) + ")");
  }
}

bool
OniReader::next (DepthFrame &frame)
{
  if (delivered_ >= size_)
    return false;
  const std::string what = ".oni file '" + file_ + "': ";
  const std::size_t number = ++delivered_; // a frame that fails is given up, like a bad frame of the other readers
  GrabbedDepthFrame item = playback_->take (what, timeout_s_, number, size_);
  if (delivered_ == size_)
    playback_.reset (); // the last frame: OpenNI2's player, at the end of the file, would spin until closed

  // OpenNI2's recorder numbers frames 1, 2, 3, ...: a gap means playback lost frames.
  const unsigned previous = last_index_;
  last_index_ = item.index;
  if (item.index != previous + 1)
    throw pcl::IOException (what + "frame index " + std::to_string (item.index) + " followed " + std::to_string (previous) +
                            ": playback lost or reordered frames");
  if (!item.error.empty ())
    throw pcl::IOException (what + "cannot copy depth frame " + std::to_string (item.index) + " (" +
                            description (std::runtime_error (item.error)) + ")");
  if (item.width != info_.width || item.height != info_.height)
    throw pcl::IOException (what + "frame " + std::to_string (item.index) + " is " + sizeText (item.width, item.height) +
                            " but the depth stream is " + sizeText (info_.width, info_.height));
  const std::size_t expected_bytes = std::size_t (item.width) * item.height * sizeof (std::uint16_t);
  if (item.bytes < 0 || std::size_t (item.bytes) < expected_bytes)
    throw pcl::IOException (what + "frame " + std::to_string (item.index) + " holds " + std::to_string (item.bytes) +
                            " bytes of depth, expected " + std::to_string (expected_bytes) + ": corrupt recording");
  item.moveInto (frame);
  return true;
}

#else // HAVE_OPENNI2

struct OniReader::Playback
{};

OniReader::OniReader (const std::string &file, double timeout_s) : file_ (file), timeout_s_ (timeout_s)
{
  throw pcl::IOException (".oni file '" + file + "': cannot play it: this PCL was built without OpenNI2");
}

bool
OniReader::next (DepthFrame &)
{
  return false;
}

#endif // HAVE_OPENNI2

OniReader::~OniReader () = default;

// ---------------------------------------------------------------------------------------------

RecordingKind
recordingKind (const std::string &path)
{
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw pcl::IOException ("recording '" + path + "': does not exist");
  if (fs::is_directory (path, ec))
  {
    const fs::path folder (path);
    if (fs::exists (folder / "camera.yaml", ec) || fs::is_directory (folder / "depth", ec))
      return RecordingKind::recording_folder;
    if (GrabberTiffReader::isGrabberTiffFolder (path))
      return RecordingKind::grabber_tiff_folder;
    if (PcdFolderReader::hasPcdFiles (path))
      return RecordingKind::pcd_folder;
    throw pcl::IOException ("recording folder '" + path + "': " + (fs::is_empty (folder, ec) ? "is empty" : "is not a recording") +
                            "; expected camera.yaml + depth/*.png (a recording folder), *_depth.tiff + intrinsics.xml "
                            "(PCL's image grabber) or *.pcd files");
  }
  const std::string ext = lowerExtension (path);
  if (ext == ".oni")
    return RecordingKind::oni_file;
  if (ext == ".pcd")
    return RecordingKind::pcd_file;
  throw pcl::IOException ("recording '" + path + "': not a recording; expected a folder, an organised .pcd file or an .oni file");
}

RecordingReader::Ptr
openRecording (const std::string &path)
{
  switch (recordingKind (path))
  {
    case RecordingKind::recording_folder:
      return std::make_shared<RecordingFolderReader> (path);
    case RecordingKind::grabber_tiff_folder:
      return std::make_shared<GrabberTiffReader> (path);
    case RecordingKind::pcd_folder:
    case RecordingKind::pcd_file:
      return std::make_shared<PcdFolderReader> (path);
    case RecordingKind::oni_file:
      return std::make_shared<OniReader> (path);
  }
  throw pcl::IOException ("recording '" + path + "': unknown kind"); // unreachable: every kind is handled
}

} // namespace texlet
} // namespace pcl
