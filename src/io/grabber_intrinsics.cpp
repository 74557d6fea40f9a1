#include <pcl_texlet/io/grabber_intrinsics.h>

#include <pcl/exceptions.h>

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <system_error>

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

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

} // namespace texlet
} // namespace pcl
