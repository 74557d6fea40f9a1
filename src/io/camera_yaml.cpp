#include <pcl_texlet/io/camera_yaml.h>

#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/common/shortest_decimal.h>

#include <pcl/exceptions.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "reader_util.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

using detail::sizeText;

pcl::IOException
cameraYamlError (const std::string &path, const std::string &problem)
{
  return pcl::IOException ("camera.yaml '" + path + "': " + problem);
}

YAML::Node
requiredKey (const YAML::Node &map, const std::string &key, const std::string &path)
{
  const YAML::Node node = map[key];
  if (!node)
    throw cameraYamlError (path, "missing key '" + key + "'");
  return node;
}

template <typename T> T
scalarAs (const YAML::Node &node, const std::string &key, const std::string &kind, const std::string &path)
{
  if (!node.IsScalar ())
    throw cameraYamlError (path, key + " must be " + kind);
  try
  {
    return node.as<T> ();
  }
  catch (const YAML::BadConversion &)
  {
    throw cameraYamlError (path, key + " must be " + kind + " (found '" + node.Scalar () + "')");
  }
}

/** \brief Reads \a key.data of a ROS matrix ({rows, cols, data}) as a list of finite numbers. */
std::vector<double>
matrixData (const YAML::Node &root, const std::string &key, const std::string &path)
{
  const YAML::Node matrix = requiredKey (root, key, path);
  if (!matrix.IsMap ())
    throw cameraYamlError (path, key + " must be a map with rows, cols and data");
  const YAML::Node data = matrix["data"];
  if (!data || !data.IsSequence ())
    throw cameraYamlError (path, key + ".data must be a list of numbers");
  std::vector<double> values;
  for (std::size_t i = 0; i < data.size (); ++i)
  {
    const std::string item = key + ".data[" + std::to_string (i) + "]";
    const double v = scalarAs<double> (data[i], item, "a number", path);
    if (!std::isfinite (v))
      throw cameraYamlError (path, item + " must be finite (found " + data[i].Scalar () + ")");
    values.push_back (v);
  }
  return values;
}

/** \brief rows and cols are redundant with data in ROS files; where present they must agree. */
void
checkMatrixShape (const YAML::Node &root, const std::string &key, int rows, int cols, const std::string &path)
{
  const YAML::Node matrix = root[key];
  const YAML::Node r = matrix["rows"];
  const YAML::Node c = matrix["cols"];
  const int found_rows = r ? scalarAs<int> (r, key + ".rows", "an integer", path) : rows;
  const int found_cols = c ? scalarAs<int> (c, key + ".cols", "an integer", path) : cols;
  if (found_rows != rows || found_cols != cols)
  {
    std::ostringstream msg;
    msg << key << " is declared " << found_rows << "x" << found_cols << " but must be " << rows << "x" << cols;
    throw cameraYamlError (path, msg.str ());
  }
}

/** \brief Optional positive quantity; \a value keeps its default when the key is absent. */
void
optionalPositive (const YAML::Node &root, const std::string &key, double &value, const std::string &path)
{
  const YAML::Node node = root[key];
  if (!node)
    return;
  const double v = scalarAs<double> (node, key, "a number", path);
  if (!(v > 0) || !std::isfinite (v))
    throw cameraYamlError (path, key + " must be positive and finite (found " + node.Scalar () + ")");
  value = v;
}

void
emitMatrix (YAML::Emitter &out, const std::string &key, int rows, int cols, const double *data)
{
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rows" << YAML::Value << rows;
  out << YAML::Key << "cols" << YAML::Value << cols;
  out << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < rows * cols; ++i)
    out << shortestDecimal (data[i]);
  out << YAML::EndSeq << YAML::EndMap;
}

} // namespace

CameraInfo
loadCameraInfoYaml (const std::string &path)
{
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw cameraYamlError (path, "file does not exist");

  YAML::Node root;
  try
  {
    root = YAML::LoadFile (path);
  }
  catch (const YAML::BadFile &)
  {
    throw cameraYamlError (path, "cannot open");
  }
  catch (const YAML::ParserException &e)
  {
    throw cameraYamlError (path, "not valid YAML (line " + std::to_string (e.mark.line + 1) + ", column " +
                                     std::to_string (e.mark.column + 1) + ": " + e.msg + ")");
  }
  if (!root.IsMap ())
    throw cameraYamlError (path, "not a YAML map of camera_info keys");

  CameraInfo info;
  info.width = scalarAs<int> (requiredKey (root, "image_width", path), "image_width", "an integer", path);
  info.height = scalarAs<int> (requiredKey (root, "image_height", path), "image_height", "an integer", path);
  if (info.width <= 0 || info.height <= 0)
    throw cameraYamlError (path, "image_width and image_height must be positive (found " +
                                     sizeText (info.width, info.height) + ")");
  if (info.width > kMaxImageSide || info.height > kMaxImageSide)
    throw cameraYamlError (path, "image_width and image_height must be at most " + std::to_string (kMaxImageSide) +
                                     " (found " + sizeText (info.width, info.height) + ")");

  const std::vector<double> k = matrixData (root, "camera_matrix", path);
  if (k.size () != 9)
    throw cameraYamlError (path, "camera_matrix.data must have 9 numbers (found " + std::to_string (k.size ()) + ")");
  checkMatrixShape (root, "camera_matrix", 3, 3, path);
  std::copy (k.begin (), k.end (), info.K);
  if (!(info.fx () > 0) || !(info.fy () > 0))
  {
    std::ostringstream msg;
    msg << "focal lengths fx and fy must be positive (found fx " << info.fx () << ", fy " << info.fy () << ")";
    throw cameraYamlError (path, msg.str ());
  }

  info.distortion_model = scalarAs<std::string> (requiredKey (root, "distortion_model", path), "distortion_model",
                                                 "a string", path);
  info.D = matrixData (root, "distortion_coefficients", path);
  if (info.distortion_model == "plumb_bob" && info.D.size () != 5)
    throw cameraYamlError (path, "distortion_coefficients.data must have 5 numbers for plumb_bob (found " +
                                     std::to_string (info.D.size ()) + ")");
  if (info.D.size () > 8)
    throw cameraYamlError (path, "distortion_coefficients.data must have at most 8 numbers (found " +
                                     std::to_string (info.D.size ()) + ")");
  checkMatrixShape (root, "distortion_coefficients", 1, static_cast<int> (info.D.size ()), path);

  optionalPositive (root, "baseline_m", info.baseline_m, path);
  optionalPositive (root, "disparity_subpixel", info.disparity_subpixel, path);
  return info;
}

void
saveCameraInfoYaml (const std::string &path, const CameraInfo &info)
{
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "image_width" << YAML::Value << info.width;
  out << YAML::Key << "image_height" << YAML::Value << info.height;
  emitMatrix (out, "camera_matrix", 3, 3, info.K);
  out << YAML::Key << "distortion_model" << YAML::Value << info.distortion_model;
  emitMatrix (out, "distortion_coefficients", 1, static_cast<int> (info.D.size ()), info.D.data ());
  // ROS's camera_calibration_parsers also require these two; for a depth camera they are the
  // identity rectification and K extended by a zero column.
  const double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double P[12] = {info.K[0], info.K[1], info.K[2], 0, info.K[3], info.K[4], info.K[5], 0,
                        info.K[6], info.K[7], info.K[8], 0};
  emitMatrix (out, "rectification_matrix", 3, 3, R);
  emitMatrix (out, "projection_matrix", 3, 4, P);
  out << YAML::Key << "baseline_m" << YAML::Value << shortestDecimal (info.baseline_m);
  out << YAML::Key << "disparity_subpixel" << YAML::Value << shortestDecimal (info.disparity_subpixel);
  out << YAML::EndMap;
  if (!out.good ())
    throw cameraYamlError (path, "cannot format as YAML: " + out.GetLastError ());

  AtomicFile tmp (path);
  {
    std::ofstream file (tmp.temporaryPath (), std::ios::binary);
    if (!file)
      throw cameraYamlError (path, "cannot create '" + tmp.temporaryPath () + "': " + std::strerror (errno));
    file << out.c_str () << '\n';
    file.close ();
    if (!file)
      throw cameraYamlError (path, "cannot write '" + tmp.temporaryPath () + "'");
  }
  tmp.commit ();
}

} // namespace texlet
} // namespace pcl
