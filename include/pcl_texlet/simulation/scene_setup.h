/*
 * pcl_texlet simulator: ready-made scenes with their sensors, as the paper used them.
 *
 * - plane: a wall at a distance, tilted about the image's x and y axes (the noise model's
 *   experiment, Sect. 2.2);
 * - box: a 128 x 112 x 240 mm box on a table seen by up to three sensors in a triangle (the
 *   interference experiment, Sect. 4 and Table 2);
 * - free: a mesh loaded from a file, placed like the wall.
 * Frames: plane and mesh scenes use the first sensor's camera frame as the scene frame (x right,
 * y down, z forward); the box scene has the table in z = 0 with z up and the box centred on the
 * origin.
 */
#pragma once

#include <pcl_texlet/simulation/depth_sensor.h>
#include <pcl_texlet/simulation/scene.h>
#include <pcl_texlet/simulation/triangle_mesh.h>

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief A scene, where its sensors stand, and what meta.yaml says about it. */
struct SceneSetup
{
  Scene::ConstPtr scene;
  std::vector<Eigen::Isometry3d> sensor_poses; ///< scene from camera
  std::string kind;                                          ///< "plane", "box" or "free" (meta.yaml scene)
  std::vector<std::pair<std::string, double>> parameters;    ///< e.g. distance_m, tilt_x_deg (meta.yaml)
  Eigen::Vector3d box_size_m = Eigen::Vector3d::Constant (std::numeric_limits<double>::quiet_NaN ()); ///< box only
  std::string mesh_path;                                     ///< free (mesh) scenes only

  /** \brief One sensor per pose, each a copy of \a model with that pose. */
  std::vector<DepthSensor>
  sensors (const DepthSensor &model) const;
};

/** \brief Pose (scene from camera) of a camera at \a eye looking at \a target with the image's
  * up direction (-y) as close to \a up as possible.
  * \throws pcl::BadArgumentException if eye and target coincide or the view is along \a up.
  */
Eigen::Isometry3d
lookAt (const Eigen::Vector3d &eye, const Eigen::Vector3d &target, const Eigen::Vector3d &up);

/** \brief The paper's test object (Table 2): opposite sides 128 mm and 112 mm apart, top
  * 240 mm above the ground.
  */
Eigen::Vector3d
paperBoxSize ();

/** \brief An infinite wall through (0, 0, distance) of the first sensor's frame with the normal
  * Rx(tilt_x_deg) Ry(tilt_y_deg) (0, 0, -1): tilted about the image's x and y axes.
  * Sensor 0 is at the origin looking along +z; the others stand beside it along x, alternately
  * right and left, spacing_m apart (0.3, -0.3, 0.6, ...), all looking at (0, 0, distance).
  * \throws pcl::BadArgumentException for a distance <= 0, |tilt| >= 90 degrees, sensors < 1,
  *         spacing <= 0.
  */
SceneSetup
planeSetup (double distance_m, double tilt_x_deg, double tilt_y_deg, int sensors = 1, double spacing_m = 0.3);

/** \brief A box of \a box_size_m (x, y, height) standing centred on a square table of side
  * table_size_m in z = 0. Sensors look at the box's centre from distance_m away, elevation_deg
  * above the horizontal, at azimuths 120 degrees apart for up to three sensors (the paper's
  * triangle; sensor 0 on the -y side) and 360 / n degrees apart for more.
  * \throws pcl::BadArgumentException for non-positive sizes or distance, an elevation outside
  *         (0, 90) degrees, sensors < 1, or a table smaller than the box.
  */
SceneSetup
boxSetup (double distance_m, double elevation_deg, int sensors = 1, const Eigen::Vector3d &box_size_m = paperBoxSize (),
          double table_size_m = 1.5);

/** \brief \a mesh moved so that the centre of its bounds is at (0, 0, distance) of the first
  * sensor's frame and turned about that centre like the wall of planeSetup; sensors as there.
  * \throws pcl::BadArgumentException as planeSetup.
  */
SceneSetup
meshSetup (const TriangleMeshSurface &mesh, double distance_m, double tilt_x_deg, double tilt_y_deg, int sensors = 1,
           double spacing_m = 0.3, const std::string &mesh_path = "");

} // namespace sim
} // namespace texlet
} // namespace pcl
