#include <pcl_texlet/simulation/scene_setup.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{
namespace sim
{

namespace
{

double
radians (double degrees)
{
  return degrees * M_PI / 180.0;
}

void
check (bool ok, const std::string &what, double value, const std::string &rule)
{
  if (ok && std::isfinite (value))
    return;
  std::ostringstream msg;
  msg << what << " must be " << rule << " (got " << value << ")";
  throw pcl::BadArgumentException (msg.str ());
}

void
checkRowOfSensors (const std::string &scene, double distance_m, double tilt_x_deg, double tilt_y_deg, int sensors,
                   double spacing_m)
{
  check (distance_m > 0, scene + " scene: the distance", distance_m, "positive");
  check (std::fabs (tilt_x_deg) < 90, scene + " scene: tilt x", tilt_x_deg, "between -90 and 90 degrees");
  check (std::fabs (tilt_y_deg) < 90, scene + " scene: tilt y", tilt_y_deg, "between -90 and 90 degrees");
  check (sensors >= 1, scene + " scene: the number of sensors", sensors, "at least 1");
  check (spacing_m > 0, scene + " scene: the sensor spacing", spacing_m, "positive");
}

/** Rx(tilt_x) Ry(tilt_y): the tilt of a target about the first camera's image axes. */
Eigen::Matrix3d
tilt (double tilt_x_deg, double tilt_y_deg)
{
  return (Eigen::AngleAxisd (radians (tilt_x_deg), Eigen::Vector3d::UnitX ()) *
          Eigen::AngleAxisd (radians (tilt_y_deg), Eigen::Vector3d::UnitY ()))
      .toRotationMatrix ();
}

/** Sensor 0 at the origin; the others beside it along x (right, left, right, ...), all aimed at
  * the target on the first camera's axis. The first camera's frame has y down, so up is -y.
  */
std::vector<Eigen::Isometry3d>
rowOfSensors (int sensors, double spacing_m, double distance_m)
{
  const Eigen::Vector3d target (0, 0, distance_m), up (0, -1, 0);
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < sensors; ++k)
  {
    const double side = (k % 2 == 1) ? 1.0 : -1.0;
    const double x = side * spacing_m * ((k + 1) / 2);
    poses.push_back (lookAt (Eigen::Vector3d (x, 0, 0), target, up));
  }
  return poses;
}

} // namespace

std::vector<DepthSensor>
SceneSetup::sensors (const DepthSensor &model) const
{
  std::vector<DepthSensor> out;
  for (const auto &pose : sensor_poses)
  {
    DepthSensor s = model;
    s.pose = pose;
    out.push_back (s);
  }
  return out;
}

Eigen::Isometry3d
lookAt (const Eigen::Vector3d &eye, const Eigen::Vector3d &target, const Eigen::Vector3d &up)
{
  const Eigen::Vector3d forward = target - eye;
  if (!(forward.norm () > 1e-12) || !eye.allFinite () || !target.allFinite ())
    throw pcl::BadArgumentException ("lookAt: the eye and the target must be finite and apart");
  const Eigen::Vector3d z = forward.normalized ();
  const Eigen::Vector3d right = z.cross (up);
  if (!(right.norm () > 1e-9))
    throw pcl::BadArgumentException ("lookAt: the view direction is parallel to the up direction");
  const Eigen::Vector3d x = right.normalized ();
  const Eigen::Vector3d y = z.cross (x); // image down
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
  pose.linear ().col (0) = x;
  pose.linear ().col (1) = y;
  pose.linear ().col (2) = z;
  pose.translation () = eye;
  return pose;
}

Eigen::Vector3d
paperBoxSize ()
{
  return {0.128, 0.112, 0.240};
}

SceneSetup
planeSetup (double distance_m, double tilt_x_deg, double tilt_y_deg, int sensors, double spacing_m)
{
  checkRowOfSensors ("plane", distance_m, tilt_x_deg, tilt_y_deg, sensors, spacing_m);
  auto scene = std::make_shared<Scene> ();
  scene->add (std::make_shared<PlaneSurface> (Eigen::Vector3d (0, 0, distance_m),
                                              tilt (tilt_x_deg, tilt_y_deg) * Eigen::Vector3d (0, 0, -1)));
  SceneSetup setup;
  setup.scene = scene;
  setup.sensor_poses = rowOfSensors (sensors, spacing_m, distance_m);
  setup.kind = "plane";
  setup.parameters = {{"distance_m", distance_m}, {"tilt_x_deg", tilt_x_deg}, {"tilt_y_deg", tilt_y_deg}};
  if (sensors > 1)
    setup.parameters.emplace_back ("sensor_spacing_m", spacing_m);
  return setup;
}

SceneSetup
boxSetup (double distance_m, double elevation_deg, int sensors, const Eigen::Vector3d &box_size_m, double table_size_m)
{
  check (distance_m > 0, "box scene: the distance", distance_m, "positive");
  check (elevation_deg > 0 && elevation_deg < 90, "box scene: the elevation", elevation_deg,
         "between 0 and 90 degrees (exclusive)");
  check (sensors >= 1, "box scene: the number of sensors", sensors, "at least 1");
  check (box_size_m.allFinite () && box_size_m.minCoeff () > 0, "box scene: the smallest box edge",
         box_size_m.minCoeff (), "positive");
  check (table_size_m > box_size_m.head<2> ().maxCoeff (), "box scene: the table size", table_size_m,
         "larger than the box's footprint");

  const Eigen::Vector3d centre (0, 0, 0.5 * box_size_m.z ());
  auto scene = std::make_shared<Scene> ();
  scene->add (std::make_shared<RectangleSurface> (Eigen::Vector3d::Zero (), Eigen::Vector3d::UnitZ (),
                                                  Eigen::Vector3d::UnitX (), 0.5 * table_size_m, 0.5 * table_size_m));
  Eigen::Isometry3d box_pose = Eigen::Isometry3d::Identity ();
  box_pose.translation () = centre;
  scene->add (std::make_shared<BoxSurface> (box_pose, box_size_m));

  SceneSetup setup;
  setup.scene = scene;
  // Up to three sensors keep the paper's triangle, so 1, 2, 3 active sensors are subsets of it.
  const double step = sensors <= 3 ? 120.0 : 360.0 / sensors;
  const double el = radians (elevation_deg);
  for (int k = 0; k < sensors; ++k)
  {
    const double az = radians (-90.0 + k * step);
    const Eigen::Vector3d eye =
        centre + distance_m * Eigen::Vector3d (std::cos (el) * std::cos (az), std::cos (el) * std::sin (az), std::sin (el));
    setup.sensor_poses.push_back (lookAt (eye, centre, Eigen::Vector3d::UnitZ ()));
  }
  setup.kind = "box";
  setup.parameters = {{"distance_m", distance_m}, {"elevation_deg", elevation_deg}, {"table_size_m", table_size_m}};
  setup.box_size_m = box_size_m;
  return setup;
}

SceneSetup
meshSetup (const TriangleMeshSurface &mesh, double distance_m, double tilt_x_deg, double tilt_y_deg, int sensors,
           double spacing_m, const std::string &mesh_path)
{
  checkRowOfSensors ("mesh", distance_m, tilt_x_deg, tilt_y_deg, sensors, spacing_m);
  // p -> R (p - c) + (0, 0, distance): the mesh's centre onto the first camera's axis.
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity ();
  placement.linear () = tilt (tilt_x_deg, tilt_y_deg);
  placement.translation () = Eigen::Vector3d (0, 0, distance_m) - placement.linear () * mesh.bounds ().center ();
  auto scene = std::make_shared<Scene> ();
  scene->add (std::make_shared<TriangleMeshSurface> (mesh.transformed (placement)));
  SceneSetup setup;
  setup.scene = scene;
  setup.sensor_poses = rowOfSensors (sensors, spacing_m, distance_m);
  setup.kind = "free";
  setup.parameters = {{"distance_m", distance_m}, {"tilt_x_deg", tilt_x_deg}, {"tilt_y_deg", tilt_y_deg},
                      {"triangles", static_cast<double> (mesh.triangleCount ())}};
  if (sensors > 1)
    setup.parameters.emplace_back ("sensor_spacing_m", spacing_m);
  setup.mesh_path = mesh_path;
  return setup;
}

} // namespace sim
} // namespace texlet
} // namespace pcl
