#include <pcl_texlet/io/pcd_folder_reader.h>

#include <pcl_texlet/camera/camera_estimation.h>
#include <pcl_texlet/camera/valid_point.h>

#include <pcl/common/io.h> // pcl::getFieldIndex
#include <pcl/conversions.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <system_error>
#include <utility>

#include "reader_util.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

using detail::description;

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

} // namespace

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
  size_source_ = "the first frame '" + files_.front () + "' is " + detail::sizeText (info_.width, info_.height);
}

void
PcdFolderReader::readFrame (std::size_t index, DepthFrame &frame)
{
  if (index == 0)
    frame = std::move (first_);
  else
    readPcdFrame (files_[index], frame, nullptr);
  checkSize ("PCD file", files_[index], frame.width, frame.height);
}

std::vector<std::string>
PcdFolderReader::listPcdFiles (const std::string &folder)
{
  return detail::listFiles (folder, [] (const std::string &name) { return detail::lowerExtension (name) == ".pcd"; });
}

} // namespace texlet
} // namespace pcl
