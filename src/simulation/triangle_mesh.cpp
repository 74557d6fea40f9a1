#include <pcl_texlet/simulation/triangle_mesh.h>

#include <pcl_texlet/common/error_text.h>
#include "vec3_eigen.h"

#include <pcl/conversions.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/io/vtk_lib_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <sstream>

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{
namespace sim
{

namespace
{

/** Leaves hold at most this many triangles: a few slab tests per triangle saved, not more. */
constexpr int kLeafSize = 4;

Eigen::Vector3d
vertexB (const kernels::Triangle<double> &t)
{
  return toEigen (t.a + t.e1);
}

Eigen::Vector3d
vertexC (const kernels::Triangle<double> &t)
{
  return toEigen (t.a + t.e2);
}

} // namespace

TriangleMeshSurface::TriangleMeshSurface (const std::vector<Eigen::Vector3d> &vertices,
                                          const std::vector<std::array<int, 3>> &triangles)
{
  for (std::size_t i = 0; i < vertices.size (); ++i)
    if (!vertices[i].allFinite ())
      throw pcl::BadArgumentException ("TriangleMeshSurface: vertex " + std::to_string (i) + " is not finite");
  const int n = static_cast<int> (vertices.size ());
  for (std::size_t i = 0; i < triangles.size (); ++i)
  {
    const auto &f = triangles[i];
    for (int k = 0; k < 3; ++k)
      if (f[k] < 0 || f[k] >= n)
        throw pcl::BadArgumentException ("TriangleMeshSurface: triangle " + std::to_string (i) + " refers to vertex " +
                                         std::to_string (f[k]) + " but there are " + std::to_string (n) + " vertices");
    const Eigen::Vector3d a = vertices[f[0]], e1 = vertices[f[1]] - a, e2 = vertices[f[2]] - a;
    const Eigen::Vector3d normal = e1.cross (e2);
    // Zero-area triangles can never be hit reliably and have no normal.
    if (!(normal.norm () > 1e-14 * std::max (1.0, e1.squaredNorm () + e2.squaredNorm ())))
      continue;
    triangles_.push_back ({toVec3 (a), toVec3 (e1), toVec3 (e2)});
    normals_.push_back (normal.normalized ());
  }
  if (triangles_.empty ())
    throw pcl::BadArgumentException ("TriangleMeshSurface: no triangle with a non-zero area (" +
                                     std::to_string (triangles.size ()) + " given)");
  build ();
}

void
TriangleMeshSurface::build ()
{
  const int n = static_cast<int> (triangles_.size ());
  std::vector<Eigen::Vector3d> centroids (n);
  bounds_.setEmpty ();
  for (int i = 0; i < n; ++i)
  {
    const Eigen::Vector3d a = toEigen (triangles_[i].a), b = vertexB (triangles_[i]), c = vertexC (triangles_[i]);
    centroids[i] = (a + b + c) / 3.0;
    bounds_.extend (a);
    bounds_.extend (b);
    bounds_.extend (c);
  }
  nodes_.clear ();
  nodes_.reserve (2 * static_cast<std::size_t> (n));
  nodes_.emplace_back ();
  depth_ = buildNode (0, 0, n, 1, centroids);
}

int
TriangleMeshSurface::buildNode (int node, int first, int count, int depth, std::vector<Eigen::Vector3d> &centroids)
{
  Eigen::AlignedBox3d box, centre_box;
  for (int i = first; i < first + count; ++i)
  {
    box.extend (toEigen (triangles_[i].a));
    box.extend (vertexB (triangles_[i]));
    box.extend (vertexC (triangles_[i]));
    centre_box.extend (centroids[i]);
  }
  // Padded by a hair, so that rounding in the slab test never culls a hit on a node's face.
  for (int k = 0; k < 3; ++k)
  {
    nodes_[node].lo[k] = box.min ()[k] - 1e-9 * (1.0 + std::fabs (box.min ()[k]));
    nodes_[node].hi[k] = box.max ()[k] + 1e-9 * (1.0 + std::fabs (box.max ()[k]));
  }
  // Median splits halve the count, so the depth stays near log2(n / kLeafSize), far below the
  // traversal stack's limit; the check only guards against the impossible.
  if (count <= kLeafSize || depth >= kernels::kBvhMaxDepth)
  {
    nodes_[node].first = first;
    nodes_[node].count = count;
    return depth;
  }
  int axis;
  centre_box.sizes ().maxCoeff (&axis);
  // Sort the triangles of this node (with their normals and centroids) about the median.
  std::vector<int> order (count);
  std::iota (order.begin (), order.end (), first);
  const int half = count / 2;
  std::nth_element (order.begin (), order.begin () + half, order.end (),
                    [&] (int a, int b) { return centroids[a][axis] < centroids[b][axis]; });
  std::vector<kernels::Triangle<double>> tris (count);
  std::vector<Eigen::Vector3d> norms (count), cents (count);
  for (int i = 0; i < count; ++i)
  {
    tris[i] = triangles_[order[i]];
    norms[i] = normals_[order[i]];
    cents[i] = centroids[order[i]];
  }
  std::copy (tris.begin (), tris.end (), triangles_.begin () + first);
  std::copy (norms.begin (), norms.end (), normals_.begin () + first);
  std::copy (cents.begin (), cents.end (), centroids.begin () + first);

  const int left = static_cast<int> (nodes_.size ());
  nodes_.emplace_back ();
  nodes_.emplace_back ();
  nodes_[node].first = left;
  nodes_[node].count = 0;
  const int dl = buildNode (left, first, half, depth + 1, centroids);
  const int dr = buildNode (left + 1, first + half, count - half, depth + 1, centroids);
  return std::max (dl, dr);
}

bool
TriangleMeshSurface::intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
                                SurfaceHit &hit) const
{
  double t = hit.t;
  std::int32_t triangle = -1;
  if (!kernels::rayBvh (nodes_.data (), triangles_.data (), toVec3 (origin), toVec3 (direction), t_min, t, triangle))
    return false;
  hit.t = t;
  hit.normal = normals_[triangle];
  return true;
}

bool
TriangleMeshSurface::intersectBruteForce (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction,
                                          double t_min, SurfaceHit &hit) const
{
  bool found = false;
  for (std::size_t i = 0; i < triangles_.size (); ++i)
  {
    double t;
    if (kernels::rayTriangle (toVec3 (origin), toVec3 (direction), triangles_[i], t) && t > t_min && t < hit.t)
    {
      hit.t = t;
      hit.normal = normals_[i];
      found = true;
    }
  }
  return found;
}

TriangleMeshSurface
TriangleMeshSurface::transformed (const Eigen::Isometry3d &transform) const
{
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> faces;
  vertices.reserve (3 * triangles_.size ());
  for (const auto &t : triangles_)
  {
    const int i = static_cast<int> (vertices.size ());
    vertices.push_back (transform * toEigen (t.a));
    vertices.push_back (transform * vertexB (t));
    vertices.push_back (transform * vertexC (t));
    faces.push_back ({i, i + 1, i + 2});
  }
  return TriangleMeshSurface (vertices, faces);
}

// ---------------------------------------------------------------------------------------------

TriangleMeshSurface
meshFromPolygonMesh (const pcl::PolygonMesh &mesh, double scale, const std::string &source)
{
  int xyz = 0;
  for (const auto &f : mesh.cloud.fields)
    xyz += (f.name == "x" || f.name == "y" || f.name == "z") ? 1 : 0;
  if (xyz != 3)
    throw pcl::BadArgumentException (source + ": the mesh's vertices have no x, y, z fields");
  if (!(scale > 0) || !std::isfinite (scale))
    throw pcl::BadArgumentException (source + ": the scale must be positive (got " + std::to_string (scale) + ")");
  pcl::PointCloud<pcl::PointXYZ> cloud;
  pcl::fromPCLPointCloud2 (mesh.cloud, cloud);
  std::vector<Eigen::Vector3d> vertices (cloud.size ());
  for (std::size_t i = 0; i < cloud.size (); ++i)
    vertices[i] = scale * cloud[i].getVector3fMap ().cast<double> ();
  std::vector<std::array<int, 3>> triangles;
  for (const auto &polygon : mesh.polygons)
    for (std::size_t k = 2; k < polygon.vertices.size (); ++k)
      triangles.push_back ({static_cast<int> (polygon.vertices[0]), static_cast<int> (polygon.vertices[k - 1]),
                            static_cast<int> (polygon.vertices[k])});
  if (triangles.empty ())
    throw pcl::BadArgumentException (source + ": the mesh has no faces (" + std::to_string (cloud.size ()) +
                                     " vertices, " + std::to_string (mesh.polygons.size ()) + " polygons)");
  try
  {
    return TriangleMeshSurface (vertices, triangles);
  }
  catch (const pcl::BadArgumentException &e)
  {
    throw pcl::BadArgumentException (source + ": " + errorText (e));
  }
}

namespace
{

/** Triangulates an organised cloud over its pixel grid. */
TriangleMeshSurface
meshFromOrganisedCloud (const pcl::PointCloud<pcl::PointXYZ> &cloud, double scale, const std::string &source)
{
  const Eigen::Vector3d origin = cloud.sensor_origin_.head<3> ().cast<double> ();
  // As pcl::OrganizedFastMesh: an edge within 12.5 degrees of the line of sight joins a
  // foreground to a background pixel across a depth discontinuity, not one surface.
  const double along_sight = std::cos (12.5 * M_PI / 180.0);
  std::vector<Eigen::Vector3d> vertices (cloud.size ());
  for (std::size_t i = 0; i < cloud.size (); ++i)
    vertices[i] = cloud[i].getVector3fMap ().cast<double> ();
  const auto valid = [&] (int i) { return vertices[i].allFinite (); };
  const auto shadowEdge = [&] (int a, int b) {
    const Eigen::Vector3d edge = vertices[b] - vertices[a], sight = vertices[a] - origin;
    return std::fabs (edge.dot (sight)) > along_sight * edge.norm () * sight.norm ();
  };
  std::vector<std::array<int, 3>> triangles;
  const auto addIfSurface = [&] (int a, int b, int c) {
    if (!valid (a) || !valid (b) || !valid (c) || shadowEdge (a, b) || shadowEdge (b, c) || shadowEdge (c, a))
      return;
    triangles.push_back ({a, b, c});
  };
  const int w = static_cast<int> (cloud.width), h = static_cast<int> (cloud.height);
  for (int v = 0; v + 1 < h; ++v)
    for (int u = 0; u + 1 < w; ++u)
    {
      const int i00 = v * w + u, i10 = i00 + 1, i01 = i00 + w, i11 = i01 + 1;
      addIfSurface (i00, i10, i01);
      addIfSurface (i10, i11, i01);
    }
  if (triangles.empty ())
    throw pcl::IOException (source + ": no triangle could be made from the organised cloud (" + std::to_string (w) +
                            "x" + std::to_string (h) + ", too few valid neighbouring points)");
  for (auto &p : vertices)
    if (p.allFinite ())
      p *= scale;
    else
      p.setZero (); // unused by any triangle
  return TriangleMeshSurface (vertices, triangles);
}

std::string
lowerExtension (const std::string &path)
{
  std::string ext = fs::path (path).extension ().string ();
  std::transform (ext.begin (), ext.end (), ext.begin (), [] (unsigned char c) { return std::tolower (c); });
  return ext;
}

} // namespace

TriangleMeshSurface
loadTriangleMesh (const std::string &path, double scale)
{
  const std::string what = "mesh file '" + path + "'";
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw pcl::IOException (what + ": does not exist");
  if (!fs::is_regular_file (path, ec))
    throw pcl::IOException (what + ": is not a file");
  if (!(scale > 0) || !std::isfinite (scale))
    throw pcl::BadArgumentException (what + ": the scale must be positive (got " + std::to_string (scale) + ")");
  const std::string ext = lowerExtension (path);
  try
  {
    if (ext == ".pcd")
    {
      pcl::PointCloud<pcl::PointXYZ> cloud;
      if (pcl::io::loadPCDFile (path, cloud) != 0)
        throw pcl::IOException (what + ": not a readable PCD file");
      if (cloud.height <= 1)
        throw pcl::IOException (what + ": an unorganised PCD cloud (height " + std::to_string (cloud.height) +
                                ") has no pixel grid to triangulate; give a mesh (PLY, OBJ, STL, VTK) instead");
      return meshFromOrganisedCloud (cloud, scale, what);
    }
    pcl::PolygonMesh mesh;
    if (ext == ".ply")
    {
      if (pcl::io::loadPLYFile (path, mesh) < 0)
        throw pcl::IOException (what + ": not a readable PLY file");
    }
    else if (ext == ".obj" || ext == ".stl" || ext == ".vtk")
    {
      if (pcl::io::loadPolygonFile (path, mesh) <= 0)
        throw pcl::IOException (what + ": not a readable " + ext.substr (1) + " mesh");
    }
    else
      throw pcl::IOException (what + ": unknown extension '" + ext + "' (expected .ply, .obj, .stl, .vtk or .pcd)");
    return meshFromPolygonMesh (mesh, scale, what);
  }
  catch (const pcl::BadArgumentException &e)
  {
    throw pcl::IOException (errorText (e));
  }
}

} // namespace sim
} // namespace texlet
} // namespace pcl
