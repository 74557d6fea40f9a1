#include <pcl_texlet/io/grabber_tiff_reader.h>

#include <pcl_texlet/io/grabber_intrinsics.h>
#include <pcl_texlet/io/tiff_image.h>

#include <pcl/exceptions.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <system_error>
#include <vector>

#include "reader_util.h"
#include "tiff_file.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

const char *const kDepthTiffSuffix = "_depth.tiff";
const char *const kRgbTiffSuffix = "_rgb.tiff";

std::vector<std::string>
listDepthTiffs (const fs::path &folder)
{
  return detail::listFiles (folder, [] (const std::string &name) { return detail::endsWith (name, kDepthTiffSuffix); });
}

} // namespace

GrabberTiffReader::GrabberTiffReader (const std::string &folder)
{
  const std::string what = "grabber TIFF folder '" + folder + "': ";
  detail::requireFolder (folder, what);
  std::error_code ec;

  // PCL's grabber layout (intrinsics.xml beside tiff/), or the TIFF folder itself.
  std::vector<fs::path> xml_candidates;
  const fs::path root (folder);
  files_ = listDepthTiffs (root / "tiff");
  if (!files_.empty ())
    xml_candidates = {root / "intrinsics.xml"};
  else
  {
    files_ = listDepthTiffs (root);
    fs::path absolute = fs::absolute (root, ec).lexically_normal ();
    if (absolute.filename ().empty ()) // "tiff/": the parent of "tiff", not of its trailing separator
      absolute = absolute.parent_path ();
    xml_candidates = {root / "intrinsics.xml", absolute.parent_path () / "intrinsics.xml"};
  }
  if (files_.empty ())
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
  const detail::TiffFile first (files_.front (), "depth TIFF");
  std::uint32_t width = 0, height = 0;
  first.size (width, height);
  info_.width = static_cast<int> (width);
  info_.height = static_cast<int> (height);
  size_source_ = "the first depth frame '" + files_.front () + "' is " + detail::sizeText (info_.width, info_.height);
}

void
GrabberTiffReader::readFrame (std::size_t index, DepthFrame &frame)
{
  static const ImageFormat tiff = {"depth TIFF", readDepthTiff, "RGB TIFF", readRgbTiff};
  const fs::path depth_path (files_[index]);
  const std::string file_name = depth_path.filename ().string ();
  frame.name = file_name.substr (0, file_name.size () - std::string (kDepthTiffSuffix).size ());
  readImages (tiff, files_[index], (depth_path.parent_path () / (frame.name + kRgbTiffSuffix)).string (), frame);
}

bool
GrabberTiffReader::isGrabberTiffFolder (const std::string &folder)
{
  return !listDepthTiffs (fs::path (folder) / "tiff").empty () || !listDepthTiffs (folder).empty ();
}

} // namespace texlet
} // namespace pcl
