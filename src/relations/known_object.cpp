#include <pcl_texlet/relations/known_object.h>

#include <pcl/exceptions.h>

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

namespace pcl
{
namespace texlet
{

int
KnownObject::faceIndex (const std::string &face_name) const
{
  for (std::size_t i = 0; i < faces.size (); ++i)
    if (faces[i].name == face_name)
      return static_cast<int> (i);
  return -1;
}

KnownObject
boxOnPlate (const Eigen::Vector3d &size_m, double plate_m)
{
  if (!size_m.allFinite () || !(size_m.minCoeff () > 0))
    throw pcl::BadArgumentException ("boxOnPlate: the box's sizes must be positive");
  if (!std::isfinite (plate_m) || !(plate_m > size_m.head<2> ().maxCoeff ()))
    throw pcl::BadArgumentException ("boxOnPlate: the plate (" + std::to_string (plate_m) +
                                     " m) must be larger than the box's footprint");
  const double sx = size_m.x (), sy = size_m.y (), h = size_m.z ();
  KnownObject o;
  std::ostringstream name;
  name << "box " << sx * 1000 << " x " << sy * 1000 << " x " << h * 1000 << " mm on a " << plate_m * 1000
       << " mm plate";
  o.name = name.str ();
  // Table 2 of the paper, in its order.
  o.relations = {{"top vs ground", 0.0, h, h},
                 {"opposite sides (x)", 180.0, sx, sx},
                 {"opposite sides (y)", 180.0, sy, sy},
                 {"same plane", 0.0, 0.0, 0.0},
                 {"orthogonal planes", 90.0, 0.0, h}};
  const Eigen::Vector3d ux = Eigen::Vector3d::UnitX (), uy = Eigen::Vector3d::UnitY (), uz = Eigen::Vector3d::UnitZ ();
  o.faces = {{"ground", Eigen::Vector3d::Zero (), uz, ux, 0.5 * plate_m, 0.5 * plate_m},
             {"top", Eigen::Vector3d (0, 0, h), uz, ux, 0.5 * sx, 0.5 * sy},
             {"side +x", Eigen::Vector3d (0.5 * sx, 0, 0.5 * h), ux, uy, 0.5 * sy, 0.5 * h},
             {"side -x", Eigen::Vector3d (-0.5 * sx, 0, 0.5 * h), -ux, uy, 0.5 * sy, 0.5 * h},
             {"side +y", Eigen::Vector3d (0, 0.5 * sy, 0.5 * h), uy, ux, 0.5 * sx, 0.5 * h},
             {"side -y", Eigen::Vector3d (0, -0.5 * sy, 0.5 * h), -uy, ux, 0.5 * sx, 0.5 * h}};
  return o;
}

KnownObject
paperBoxObject ()
{
  return boxOnPlate (Eigen::Vector3d (0.128, 0.112, 0.240), 0.35);
}

namespace
{

double
number (const YAML::Node &node, const std::string &where)
{
  try
  {
    const double v = node.as<double> ();
    if (std::isfinite (v))
      return v;
  }
  catch (const YAML::Exception &)
  {
  }
  throw pcl::IOException (where + " must be a number");
}

Eigen::Vector3d
vector3 (const YAML::Node &node, const std::string &where)
{
  if (!node || !node.IsSequence () || node.size () != 3)
    throw pcl::IOException (where + " must be a list of 3 numbers");
  return {number (node[0], where), number (node[1], where), number (node[2], where)};
}

} // namespace

KnownObject
loadKnownObjectYaml (const std::string &path)
{
  const std::string where = "object file '" + path + "'";
  if (!std::filesystem::is_regular_file (path))
    throw pcl::IOException (where + ": no such file");
  YAML::Node root;
  try
  {
    root = YAML::LoadFile (path);
  }
  catch (const YAML::Exception &e)
  {
    throw pcl::IOException (where + ": not valid YAML: " + e.what ());
  }
  if (!root.IsMap ())
    throw pcl::IOException (where + ": expected a map with 'box' and/or 'relations' and 'faces'");
  KnownObject o;
  o.name = std::filesystem::path (path).stem ().string ();
  if (root["box"])
  {
    const YAML::Node b = root["box"];
    const Eigen::Vector3d size = 1e-3 * vector3 (b["size_mm"], where + ": box.size_mm");
    if (!b["plate_mm"])
      throw pcl::IOException (where + ": box needs plate_mm (the base plate's side)");
    const double plate = 1e-3 * number (b["plate_mm"], where + ": box.plate_mm");
    try
    {
      o = boxOnPlate (size, plate);
    }
    catch (const pcl::BadArgumentException &e)
    {
      throw pcl::IOException (where + ": " + std::string (e.what ()).substr (2));
    }
  }
  if (root["relations"])
  {
    const YAML::Node list = root["relations"];
    if (!list.IsSequence () || list.size () == 0)
      throw pcl::IOException (where + ": 'relations' must be a non-empty list");
    o.relations.clear ();
    for (std::size_t k = 0; k < list.size (); ++k)
    {
      const YAML::Node r = list[k];
      const std::string item = where + ": relation " + std::to_string (k);
      if (!r.IsMap () || !r["angle_deg"] || !r["distance_mm"])
        throw pcl::IOException (item + " needs angle_deg and distance_mm");
      ExpectedRelation e;
      e.name = r["name"] ? r["name"].as<std::string> () : "relation " + std::to_string (k);
      e.angle_deg = number (r["angle_deg"], item + " angle_deg");
      const YAML::Node d = r["distance_mm"];
      if (d.IsSequence ())
      {
        if (d.size () != 2)
          throw pcl::IOException (item + " distance_mm must be a number or [min, max]");
        e.distance_min_m = 1e-3 * number (d[0], item + " distance_mm");
        e.distance_max_m = 1e-3 * number (d[1], item + " distance_mm");
      }
      else
        e.distance_min_m = e.distance_max_m = 1e-3 * number (d, item + " distance_mm");
      if (e.angle_deg < 0 || e.angle_deg > 180)
        throw pcl::IOException (item + " angle_deg must be between 0 and 180");
      if (e.distance_min_m < 0 || e.distance_max_m < e.distance_min_m)
        throw pcl::IOException (item + " distance_mm must be >= 0 with min <= max");
      o.relations.push_back (e);
    }
  }
  if (root["faces"])
  {
    const YAML::Node list = root["faces"];
    if (!list.IsSequence ())
      throw pcl::IOException (where + ": 'faces' must be a list");
    o.faces.clear ();
    for (std::size_t k = 0; k < list.size (); ++k)
    {
      const YAML::Node f = list[k];
      const std::string item = where + ": face " + std::to_string (k);
      if (!f.IsMap ())
        throw pcl::IOException (item + " must be a map");
      ObjectFace face;
      face.name = f["name"] ? f["name"].as<std::string> () : "face " + std::to_string (k);
      face.centre = 1e-3 * vector3 (f["centre_mm"], item + " centre_mm");
      const Eigen::Vector3d n = vector3 (f["normal"], item + " normal"), u = vector3 (f["axis_u"], item + " axis_u");
      if (!(n.norm () > 1e-9) || !(u.norm () > 1e-9) || std::fabs (n.normalized ().dot (u.normalized ())) > 1e-3)
        throw pcl::IOException (item + ": normal and axis_u must be non-zero and orthogonal");
      face.normal = n.normalized ();
      face.axis_u = u.normalized ();
      const YAML::Node hs = f["half_size_mm"];
      if (!hs || !hs.IsSequence () || hs.size () != 2)
        throw pcl::IOException (item + " half_size_mm must be [along axis_u, along normal x axis_u]");
      face.half_u_m = 1e-3 * number (hs[0], item + " half_size_mm");
      face.half_v_m = 1e-3 * number (hs[1], item + " half_size_mm");
      if (!(face.half_u_m > 0) || !(face.half_v_m > 0))
        throw pcl::IOException (item + " half_size_mm must be positive");
      o.faces.push_back (face);
    }
  }
  if (root["tolerance"])
  {
    const YAML::Node t = root["tolerance"];
    if (t["angle_deg"])
      o.angle_tol_deg = number (t["angle_deg"], where + ": tolerance.angle_deg");
    if (t["distance_mm"])
      o.distance_tol_m = 1e-3 * number (t["distance_mm"], where + ": tolerance.distance_mm");
    if (!(o.angle_tol_deg > 0) || !(o.distance_tol_m > 0))
      throw pcl::IOException (where + ": tolerances must be positive");
  }
  if (o.relations.empty ())
    throw pcl::IOException (where + ": no relations (give 'box' or 'relations')");
  return o;
}

int
labelPoint (const KnownObject &object, const Eigen::Vector3d &point, double max_plane_distance_m, double margin_m)
{
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity ();
  for (std::size_t f = 0; f < object.faces.size (); ++f)
  {
    const ObjectFace &face = object.faces[f];
    const Eigen::Vector3d d = point - face.centre;
    const double off = std::fabs (face.normal.dot (d));
    if (off > max_plane_distance_m || off >= best_distance)
      continue;
    const Eigen::Vector3d axis_v = face.normal.cross (face.axis_u);
    if (std::fabs (face.axis_u.dot (d)) > face.half_u_m + margin_m || std::fabs (axis_v.dot (d)) > face.half_v_m + margin_m)
      continue;
    best = static_cast<int> (f);
    best_distance = off;
  }
  return best;
}

} // namespace texlet
} // namespace pcl
