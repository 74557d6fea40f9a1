/*
 * pcl_texlet multi-sensor: a test object of known geometry, the relations its texlets must
 * show (the paper's Table 2) and, optionally, its faces, to tell which face a texlet lies on.
 *
 * Object YAML (docs/multi_sensor.md), all lengths in millimetres:
 *
 *   box: {size_mm: [128, 112, 240], plate_mm: 350}   # a box on a square base plate: Table 2's
 *                                                    # relations and the six faces, as the
 *                                                    # simulator's box scene places them
 *   # or explicitly (either or both lists; relations replace the box's):
 *   relations:
 *     - {name: top vs ground, angle_deg: 0, distance_mm: 240}
 *     - {name: orthogonal planes, angle_deg: 90, distance_mm: [0, 240]}
 *   faces:
 *     - {name: top, centre_mm: [0, 0, 240], normal: [0, 0, 1], axis_u: [1, 0, 0], half_size_mm: [64, 56]}
 *   tolerance: {angle_deg: 10, distance_mm: 5}        # inlier boxes (paper: 10 deg, 5 mm)
 */
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief A relation texlet pairs of the object must show (one row of the paper's Table 2). */
struct ExpectedRelation
{
  std::string name;
  double angle_deg = 0.0;      ///< angle between the normals, degrees [0, 180]
  double distance_min_m = 0.0; ///< normal distance, lower end, metres
  double distance_max_m = 0.0; ///< upper end (equal to the lower one for a point relation)
};

/** \brief A planar rectangular face of the object in the reference frame. */
struct ObjectFace
{
  std::string name;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero ();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ (); ///< unit, pointing out of the object
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX (); ///< unit, in the face; axis_v = normal x axis_u
  double half_u_m = 0.0;                              ///< half extent along axis_u, metres
  double half_v_m = 0.0;                              ///< half extent along axis_v, metres
};

/** \brief The known test object. */
struct KnownObject
{
  std::string name;
  std::vector<ExpectedRelation> relations;
  std::vector<ObjectFace> faces; ///< may be empty: no per-face statistics
  double angle_tol_deg = 10.0;   ///< inlier box half width in angle (paper: 10 degrees)
  double distance_tol_m = 0.005; ///< inlier box margin in distance (paper: 5 mm)

  /** \brief Index of the face named \a face_name, or -1. */
  int
  faceIndex (const std::string &face_name) const;
};

/** \brief A box of \a size_m (x, y, height) standing centred on a square base plate of side
  * \a plate_m in z = 0 (the simulator's box scene): the relations of the paper's Table 2 (top
  * vs ground 0 deg / height; opposite sides 180 deg / x and y sizes; same plane 0 deg / 0;
  * orthogonal planes 90 deg / 0 to height) and faces ground, top, side +x, side -x, side +y,
  * side -y. The paper's box is (0.128, 0.112, 0.240).
  * \throws pcl::BadArgumentException for non-positive sizes or a plate smaller than the box.
  */
KnownObject
boxOnPlate (const Eigen::Vector3d &size_m, double plate_m);

/** \brief boxOnPlate with the paper's box (Table 2) and a 0.35 m plate, on which every
  * orthogonal relation stays within Table 2's 0-240 mm.
  */
KnownObject
paperBoxObject ();

/** \brief Loads an object YAML file (format above).
  * \throws pcl::IOException naming the file and the problem.
  */
KnownObject
loadKnownObjectYaml (const std::string &path);

/** \brief The face each point lies on: the face whose plane is nearest to the point, among
  * those within \a max_plane_distance_m of it and with the point's projection inside the face
  * grown by \a margin_m; -1 where none. Labels go by position only, so a texlet with a poor
  * normal is still counted on its face.
  */
int
labelPoint (const KnownObject &object, const Eigen::Vector3d &point, double max_plane_distance_m = 0.02,
            double margin_m = 0.01);

} // namespace texlet
} // namespace pcl
