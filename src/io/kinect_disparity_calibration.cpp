#include <pcl_texlet/io/kinect_disparity_calibration.h>

#include <pcl/exceptions.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
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
calibrationError (const std::string &path, const std::string &problem)
{
  return pcl::IOException ("Kinect calibration '" + path + "': " + problem);
}

std::string
namesText (std::initializer_list<const char *> names)
{
  std::string text;
  for (const char *name : names)
    text += (text.empty () ? "'" : ", '") + std::string (name) + "'";
  return text;
}

/** \brief The one of \a names that \a root has, or "" when it has none.
  * \throws pcl::IOException when it has more than one: which of two values is meant is unclear.
  */
std::string
keyOf (const YAML::Node &root, std::initializer_list<const char *> names, const std::string &path)
{
  std::string found;
  for (const char *name : names)
    if (root[name])
    {
      if (!found.empty ())
        throw calibrationError (path, "has both '" + found + "' and '" + name + "'; give only one");
      found = name;
    }
  return found;
}

double
number (const YAML::Node &node, const std::string &what, const std::string &path)
{
  if (!node.IsScalar ())
    throw calibrationError (path, what + " must be a number");
  try
  {
    return node.as<double> ();
  }
  catch (const YAML::BadConversion &)
  {
    throw calibrationError (path, what + " must be a number (found '" + node.Scalar () + "')");
  }
}

/** \brief A matrix: an OpenCV one (a map, usually tagged !!opencv-matrix, of rows, cols, dt and
  * data) or a plain list of numbers (one row). Numbers must be finite.
  */
struct Matrix
{
  int rows = 0;
  int cols = 0;
  std::vector<double> data;
};

Matrix
matrix (const YAML::Node &root, const std::string &key, const std::string &path)
{
  const YAML::Node node = root[key];
  // Node's operator= would write into the node it refers to; the const copies only refer.
  const YAML::Node data = node.IsMap () ? node["data"] : node;
  Matrix m;
  if (node.IsMap ())
  {
    if (!data || !data.IsSequence ())
      throw calibrationError (path, key + " must have data: a list of numbers");
    const YAML::Node rows = node["rows"];
    const YAML::Node cols = node["cols"];
    if (!rows || !cols)
      throw calibrationError (path, key + " must have rows and cols (an OpenCV matrix)");
    const double r = number (rows, key + ".rows", path);
    const double c = number (cols, key + ".cols", path);
    if (!(r >= 0) || !(c >= 0) || r > kMaxImageSide || c > kMaxImageSide || r != std::floor (r) || c != std::floor (c))
      throw calibrationError (path, key + ".rows and .cols must be whole numbers from 0 to " +
                                        std::to_string (kMaxImageSide) + " (found " + rows.Scalar () + " and " +
                                        cols.Scalar () + ")");
    m.rows = static_cast<int> (r);
    m.cols = static_cast<int> (c);
    if (static_cast<std::size_t> (m.rows) * static_cast<std::size_t> (m.cols) != data.size ())
      throw calibrationError (path, key + " is declared " + std::to_string (m.rows) + "x" + std::to_string (m.cols) +
                                        " but its data has " + std::to_string (data.size ()) + " numbers");
  }
  else if (node.IsSequence ())
  {
    m.rows = 1;
    m.cols = static_cast<int> (node.size ());
  }
  else
    throw calibrationError (path, key + " must be a matrix (!!opencv-matrix with rows, cols, data) or a list of numbers");
  m.data.reserve (data.size ());
  for (std::size_t i = 0; i < data.size (); ++i)
  {
    const std::string item = key + ".data[" + std::to_string (i) + "]";
    const double v = number (data[i], item, path);
    if (!std::isfinite (v))
      throw calibrationError (path, item + " must be finite (found " + data[i].Scalar () + ")");
    m.data.push_back (v);
  }
  return m;
}

/** \brief A 1xN or Nx1 matrix (or list) of \a n numbers. */
std::vector<double>
vector (const YAML::Node &root, const std::string &key, std::size_t n, const std::string &path)
{
  const Matrix m = matrix (root, key, path);
  if (m.data.size () != n || (m.rows != 1 && m.cols != 1))
    throw calibrationError (path, key + " must be " + std::to_string (n) + " numbers, a 1x" + std::to_string (n) +
                                      " matrix (found " + std::to_string (m.rows) + "x" + std::to_string (m.cols) + ")");
  return m.data;
}

/** \brief YAML text of \a path without OpenCV's "%YAML:1.0" first line, which yaml-cpp refuses
  * (YAML 1.x spells the directive "%YAML 1.0"); \a stripped_lines counts what went. Nothing
  * else is changed.
  */
std::string
yamlText (const std::string &path, int &stripped_lines)
{
  stripped_lines = 0;
  std::ifstream in (path, std::ios::binary);
  if (!in)
    throw calibrationError (path, "cannot open");
  std::ostringstream text;
  text << in.rdbuf ();
  std::string s = text.str ();
  if (s.rfind ("%YAML", 0) == 0)
  {
    const std::size_t end = s.find ('\n');
    s.erase (0, end == std::string::npos ? s.size () : end + 1);
    stripped_lines = 1; // a "---" after it is now an ordinary document start
  }
  return s;
}

} // namespace

std::uint16_t
KinectDisparityCalibration::depthMm (std::uint16_t d, int u, int v) const
{
  if (d >= kKinectNoDisparity)
    return 0;
  double disparity = d;
  if (!beta.empty ())
  {
    const double b = beta[static_cast<std::size_t> (v) * static_cast<std::size_t> (beta_width) + static_cast<std::size_t> (u)];
    // Herrera's toolbox corrects only where beta is non-zero; exp () of a large exponent is inf.
    if (b != 0)
      disparity += b * std::exp (alpha[0] - alpha[1] * disparity);
  }
  const double z_mm = 1000.0 / (c0 + c1 * disparity);
  if (!(z_mm > 0) || !(z_mm < 65535.5)) // NaN and infinities included
    return 0;
  return static_cast<std::uint16_t> (std::lround (z_mm));
}

KinectDisparityCalibration
loadKinectDisparityCalibration (const std::string &path)
{
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw calibrationError (path, "file does not exist");
  YAML::Node root;
  int stripped_lines = 0;
  try
  {
    root = YAML::Load (yamlText (path, stripped_lines));
  }
  catch (const YAML::ParserException &e)
  {
    throw calibrationError (path, "not valid YAML (line " + std::to_string (e.mark.line + 1 + stripped_lines) +
                                      ", column " + std::to_string (e.mark.column + 1) + ": " + e.msg + ")");
  }
  if (!root.IsMap ())
    throw calibrationError (path, "not a YAML map of calibration keys");

  KinectDisparityCalibration calib;
  CameraInfo &info = calib.info;
  info.width = 0;
  info.height = 0;

  // Intrinsics.
  const std::string k_key = keyOf (root, {"dK", "depth_intrinsics", "camera_matrix", "K"}, path);
  if (k_key.empty ())
    throw calibrationError (path, "missing the depth camera matrix (one of " +
                                      namesText ({"dK", "depth_intrinsics", "camera_matrix", "K"}) + ")");
  const Matrix k = matrix (root, k_key, path);
  if (k.rows != 3 || k.cols != 3)
    throw calibrationError (path, k_key + " must be a 3x3 matrix (found " + std::to_string (k.rows) + "x" +
                                      std::to_string (k.cols) + ")");
  std::copy (k.data.begin (), k.data.end (), info.K);
  if (!(info.fx () > 0) || !(info.fy () > 0))
  {
    std::ostringstream msg;
    msg << k_key << ": focal lengths fx and fy must be positive (found fx " << info.fx () << ", fy " << info.fy () << ")";
    throw calibrationError (path, msg.str ());
  }

  const std::string d_key = keyOf (root, {"dkc", "depth_distortion", "distortion_coefficients", "D"}, path);
  info.distortion_model = "plumb_bob";
  info.D.assign (5, 0.0);
  if (!d_key.empty ())
  {
    const Matrix d = matrix (root, d_key, path);
    if ((d.rows != 1 && d.cols != 1) || d.data.size () < 4)
      throw calibrationError (path, d_key + " must be a row of 4 or 5 distortion coefficients (k1 k2 p1 p2 k3)");
    // OpenCV's longer rational models are accepted only when they reduce to plumb_bob.
    for (std::size_t i = 5; i < d.data.size (); ++i)
      if (d.data[i] != 0)
        throw calibrationError (path, d_key + " has " + std::to_string (d.data.size ()) +
                                          " coefficients and only the 5 of plumb_bob (k1 k2 p1 p2 k3) are supported");
    std::copy (d.data.begin (), d.data.begin () + std::min<std::size_t> (5, d.data.size ()), info.D.begin ());
  }

  // Depth calibration.
  const std::string dc_key = keyOf (root, {"dc", "depth_calibration"}, path);
  if (!dc_key.empty ())
  {
    if (root["c0"] || root["c1"])
      throw calibrationError (path, "has both '" + dc_key + "' and c0/c1; give only one");
    const std::vector<double> dc = vector (root, dc_key, 2, path);
    calib.c0 = dc[0];
    calib.c1 = dc[1];
  }
  else
  {
    if (!root["c0"] || !root["c1"])
      throw calibrationError (path, std::string ("missing the depth calibration: 'dc' or 'depth_calibration' ([c0 c1]), or ") +
                                        "both 'c0' and 'c1' (missing '" + (root["c0"] ? "c1" : "c0") + "')");
    calib.c0 = number (root["c0"], "c0", path);
    calib.c1 = number (root["c1"], "c1", path);
  }
  const std::string c_names = dc_key.empty () ? "c0, c1" : dc_key + " = [c0 c1]";
  if (!std::isfinite (calib.c0) || !std::isfinite (calib.c1))
  {
    std::ostringstream msg;
    msg << c_names << " must be finite (found c0 " << calib.c0 << ", c1 " << calib.c1 << ")";
    throw calibrationError (path, msg.str ());
  }
  if (calib.c1 == 0)
    throw calibrationError (path, c_names + ": c1 is 0, so depth would not depend on disparity");

  // Herrera's disparity distortion: both halves or neither.
  if (root["dc_alpha"] || root["dc_beta"])
  {
    if (!root["dc_alpha"] || !root["dc_beta"])
      throw calibrationError (path, std::string ("has '") + (root["dc_alpha"] ? "dc_alpha" : "dc_beta") +
                                        "' without '" + (root["dc_alpha"] ? "dc_beta" : "dc_alpha") + "'");
    const std::vector<double> alpha = vector (root, "dc_alpha", 2, path);
    calib.alpha[0] = alpha[0];
    calib.alpha[1] = alpha[1];
    Matrix beta = matrix (root, "dc_beta", path);
    if (beta.rows == 0 || beta.cols == 0)
      throw calibrationError (path, "dc_beta must be an image-sized matrix (rows = height, cols = width)");
    calib.beta = std::move (beta.data);
    calib.beta_width = beta.cols;
    calib.beta_height = beta.rows;
  }

  // Image size, optional.
  const bool has_w = static_cast<bool> (root["image_width"]);
  const bool has_h = static_cast<bool> (root["image_height"]);
  if (has_w != has_h)
    throw calibrationError (path, std::string ("has '") + (has_w ? "image_width" : "image_height") + "' without '" +
                                      (has_w ? "image_height" : "image_width") + "'");
  if (has_w)
  {
    const double w = number (root["image_width"], "image_width", path);
    const double h = number (root["image_height"], "image_height", path);
    if (!(w > 0) || !(h > 0) || w > kMaxImageSide || h > kMaxImageSide || w != std::floor (w) || h != std::floor (h))
      throw calibrationError (path, "image_width and image_height must be whole numbers from 1 to " +
                                        std::to_string (kMaxImageSide) + " (found " + root["image_width"].Scalar () +
                                        " and " + root["image_height"].Scalar () + ")");
    info.width = static_cast<int> (w);
    info.height = static_cast<int> (h);
  }

  if (root["baseline_m"])
  {
    const double b = number (root["baseline_m"], "baseline_m", path);
    if (!(b > 0) || !std::isfinite (b))
      throw calibrationError (path, "baseline_m must be positive and finite (found " + root["baseline_m"].Scalar () + ")");
    info.baseline_m = b;
  }
  // One unit of raw disparity, in pixels: 1/z = c0 + c1 d, and disparity in pixels is f b / z.
  info.disparity_subpixel = info.fx () * info.baseline_m * std::fabs (calib.c1);
  return calib;
}

} // namespace texlet
} // namespace pcl
