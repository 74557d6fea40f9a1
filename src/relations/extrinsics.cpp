#include <pcl_texlet/relations/extrinsics.h>

#include <pcl_texlet/common/atomic_file.h>

#include <pcl/exceptions.h>

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>

namespace pcl
{
namespace texlet
{

namespace
{

YAML::Node
loadYaml (const std::string &path, const std::string &what)
{
  if (!std::filesystem::is_regular_file (path))
    throw pcl::IOException (what + " '" + path + "': no such file");
  try
  {
    return YAML::LoadFile (path);
  }
  catch (const YAML::Exception &e)
  {
    throw pcl::IOException (what + " '" + path + "': not valid YAML: " + e.what ());
  }
}

/** 16 numbers, flat or as four rows of four. */
Eigen::Matrix4d
matrixFromNode (const YAML::Node &node, const std::string &where)
{
  std::vector<double> v;
  try
  {
    if (!node.IsSequence ())
      throw std::runtime_error ("not a list");
    for (const auto &item : node)
    {
      if (item.IsSequence ())
        for (const auto &x : item)
          v.push_back (x.as<double> ());
      else
        v.push_back (item.as<double> ());
    }
  }
  catch (const std::exception &)
  {
    throw pcl::IOException (where + ": the pose must be 16 numbers (row-major 4x4)");
  }
  if (v.size () != 16)
    throw pcl::IOException (where + ": the pose must be 16 numbers (row-major 4x4), got " + std::to_string (v.size ()));
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i)
    m (i / 4, i % 4) = v[i];
  return m;
}

} // namespace

Eigen::Isometry3d
rigidPose (const Eigen::Matrix4d &m, const std::string &what)
{
  if (!m.allFinite ())
    throw pcl::BadArgumentException (what + ": the pose has non-finite entries");
  if (!(m.row (3) - Eigen::RowVector4d (0, 0, 0, 1)).isZero (1e-9))
    throw pcl::BadArgumentException (what + ": the pose's last row must be 0 0 0 1");
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3> ();
  const double orth = (r.transpose () * r - Eigen::Matrix3d::Identity ()).cwiseAbs ().maxCoeff ();
  if (orth > 1e-4 || std::fabs (r.determinant () - 1.0) > 1e-4)
  {
    std::ostringstream msg;
    msg << what << ": the pose's rotation is not orthonormal with determinant +1 (|R^T R - I| = " << orth
        << ", det = " << r.determinant () << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
  Eigen::Isometry3d pose (m);
  return pose;
}

std::vector<SensorExtrinsics>
loadExtrinsicsYaml (const std::string &path)
{
  const std::string what = "extrinsics file";
  const YAML::Node root = loadYaml (path, what);
  const std::string where = what + " '" + path + "'";
  if (!root.IsMap () || !root["sensors"] || !root["sensors"].IsSequence () || root["sensors"].size () == 0)
    throw pcl::IOException (where + ": needs a non-empty list 'sensors'");
  std::vector<SensorExtrinsics> out;
  std::set<std::string> names;
  std::size_t k = 0;
  for (const auto &s : root["sensors"])
  {
    const std::string item = where + ", sensor " + std::to_string (k++);
    if (!s.IsMap () || !s["name"] || !s["pose"])
      throw pcl::IOException (item + ": needs 'name' and 'pose'");
    SensorExtrinsics e;
    try
    {
      e.name = s["name"].as<std::string> ();
    }
    catch (const YAML::Exception &)
    {
      throw pcl::IOException (item + ": 'name' must be a string");
    }
    if (e.name.empty ())
      throw pcl::IOException (item + ": 'name' is empty");
    if (!names.insert (e.name).second)
      throw pcl::IOException (where + ": sensor '" + e.name + "' appears twice");
    const Eigen::Matrix4d m = matrixFromNode (s["pose"], item + " ('" + e.name + "')");
    try
    {
      e.pose = rigidPose (m, item + " ('" + e.name + "')");
    }
    catch (const pcl::BadArgumentException &ex)
    {
      const std::string msg = ex.what ();
      throw pcl::IOException (msg.rfind (": ", 0) == 0 ? msg.substr (2) : msg);
    }
    out.push_back (e);
  }
  return out;
}

void
saveExtrinsicsYaml (const std::string &path, const std::vector<SensorExtrinsics> &sensors)
{
  std::ostringstream out;
  out << "# pcl_texlet extrinsics: reference frame from each sensor's camera frame (x right, y down,\n"
         "# z forward), row-major 4x4, metres\nsensors:\n";
  out << std::setprecision (17);
  for (const auto &s : sensors)
  {
    out << "  - name: \"" << s.name << "\"\n    pose: [";
    for (int i = 0; i < 16; ++i)
      out << (i ? ", " : "") << (s.pose.matrix () (i / 4, i % 4) + 0.0);
    out << "]\n";
  }
  writeFileAtomically (path, out.str ());
}

bool
poseFromMetaYaml (const std::string &meta_yaml, Eigen::Isometry3d &pose)
{
  if (!std::filesystem::is_regular_file (meta_yaml))
    return false;
  const YAML::Node root = loadYaml (meta_yaml, "meta.yaml");
  if (!root.IsMap () || !root["sensor_pose"])
    return false;
  const std::string where = "meta.yaml '" + meta_yaml + "' sensor_pose";
  const Eigen::Matrix4d m = matrixFromNode (root["sensor_pose"], where);
  try
  {
    pose = rigidPose (m, where);
  }
  catch (const pcl::BadArgumentException &ex)
  {
    const std::string msg = ex.what ();
    throw pcl::IOException (msg.rfind (": ", 0) == 0 ? msg.substr (2) : msg);
  }
  return true;
}

int
projectorsFromMetaYaml (const std::string &meta_yaml, int fallback)
{
  if (!std::filesystem::is_regular_file (meta_yaml))
    return fallback;
  const YAML::Node root = loadYaml (meta_yaml, "meta.yaml");
  if (!root.IsMap () || !root["projectors"])
    return fallback;
  int n = 0;
  try
  {
    n = root["projectors"].as<int> ();
  }
  catch (const YAML::Exception &)
  {
    n = 0;
  }
  if (n < 1)
    throw pcl::IOException ("meta.yaml '" + meta_yaml + "': 'projectors' must be a positive integer");
  return n;
}

} // namespace texlet
} // namespace pcl
