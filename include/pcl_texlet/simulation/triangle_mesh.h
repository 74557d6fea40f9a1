/*
 * pcl_texlet simulator: triangle meshes as scene surfaces, with a bounding volume hierarchy so
 * that rays cost O(log n) triangles, and loaders for PLY/OBJ/STL/VTK meshes and organised PCD
 * clouds (triangulated over their pixel grid).
 */
#pragma once

#include <pcl_texlet/kernels/ray_cast.h>
#include <pcl_texlet/simulation/scene.h>

#include <pcl/PolygonMesh.h>

#include <array>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief A triangle mesh surface. The BVH splits triangles at the median centroid along the
  * longest axis, four triangles or fewer per leaf; rays traverse it with the header-only
  * kernels::rayBvh, the same code a GPU would run.
  */
class TriangleMeshSurface : public Surface
{
public:
  using Ptr = std::shared_ptr<TriangleMeshSurface>;
  using ConstPtr = std::shared_ptr<const TriangleMeshSurface>;

  /** \brief Builds the mesh of \a vertices (metres) and triangles of vertex indices.
    * Degenerate triangles (zero area) are dropped.
    * \throws pcl::BadArgumentException for an index out of range, a non-finite vertex, or no
    *         triangle with an area left.
    */
  TriangleMeshSurface (const std::vector<Eigen::Vector3d> &vertices, const std::vector<std::array<int, 3>> &triangles);

  std::string
  name () const override { return "mesh"; }

  bool
  intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
             SurfaceHit &hit) const override;

  /** \brief The same mesh with every vertex mapped by \a transform. */
  TriangleMeshSurface
  transformed (const Eigen::Isometry3d &transform) const;

  /** \brief Triangles kept (degenerate ones dropped). */
  std::size_t
  triangleCount () const { return triangles_.size (); }

  /** \brief Axis-aligned bounds of all vertices. */
  const Eigen::AlignedBox3d &
  bounds () const { return bounds_; }

  /** \brief Depth of the BVH (1 for a single leaf). */
  int
  bvhDepth () const { return depth_; }

  /** \brief Reference hit test against every triangle (no BVH), for checking the BVH. */
  bool
  intersectBruteForce (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
                       SurfaceHit &hit) const;

private:
  void
  build ();

  int
  buildNode (int node, int first, int count, int depth, std::vector<Eigen::Vector3d> &centroids);

  std::vector<kernels::Triangle<double>> triangles_;
  std::vector<Eigen::Vector3d> normals_; ///< unit face normal per triangle (same order)
  std::vector<kernels::BvhNode<double>> nodes_;
  Eigen::AlignedBox3d bounds_;
  int depth_ = 0;
};

/** \brief Triangles of a pcl::PolygonMesh (polygons with more than three vertices are fanned).
  * \a scale multiplies the coordinates (e.g. 0.001 for a mesh in millimetres); \a source names
  * the mesh in error messages.
  * \throws pcl::BadArgumentException for a mesh without x, y, z fields or without faces.
  */
TriangleMeshSurface
meshFromPolygonMesh (const pcl::PolygonMesh &mesh, double scale = 1.0, const std::string &source = "mesh");

/** \brief Loads a mesh file: .ply (pcl::io::loadPLYFile), .obj, .stl, .vtk
  * (pcl::io::loadPolygonFile), or an organised .pcd cloud, triangulated over its pixel grid
  * (two triangles per 2x2 block of valid points, leaving out triangles with an edge within
  * 12.5 degrees of the line of sight from the cloud's sensor origin, as pcl::OrganizedFastMesh
  * does: those bridge depth discontinuities).
  * \throws pcl::IOException naming the file and the problem (missing, unreadable, unknown
  *         extension, no faces, an unorganised PCD).
  */
TriangleMeshSurface
loadTriangleMesh (const std::string &path, double scale = 1.0);

} // namespace sim
} // namespace texlet
} // namespace pcl
