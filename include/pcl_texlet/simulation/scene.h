/*
 * pcl_texlet simulator: scenes of surfaces that rays can be cast against.
 *
 * Surfaces live in the scene frame (metres). A ray is origin + t * direction; the simulator
 * casts rays whose direction has z = 1 in the camera frame, so t is the depth along the
 * sensor's optical axis. Surfaces are immutable once built and safe to share between threads.
 */
#pragma once

#include <Eigen/Geometry>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief The nearest hit found so far along a ray. */
struct SurfaceHit
{
  double t = std::numeric_limits<double>::infinity (); ///< ray parameter
  Eigen::Vector3d normal = Eigen::Vector3d::Zero ();     ///< unit normal, scene frame (either side)
  int surface = -1;                                      ///< index of the surface in its Scene
};

/** \brief A surface rays can hit. */
class Surface
{
public:
  using Ptr = std::shared_ptr<Surface>;
  using ConstPtr = std::shared_ptr<const Surface>;

  virtual ~Surface () = default;

  /** \brief What kind of surface this is ("plane", "box", "mesh", ...). */
  virtual std::string
  name () const = 0;

  /** \brief Looks for a hit with t_min < t < hit.t; on finding one, stores t and the normal in
    * \a hit and returns true (hit.surface is set by the Scene).
    */
  virtual bool
  intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min, SurfaceHit &hit) const = 0;
};

/** \brief Infinite plane through \a point with normal \a normal. */
class PlaneSurface : public Surface
{
public:
  /** \throws pcl::BadArgumentException for a zero or non-finite normal or a non-finite point. */
  PlaneSurface (const Eigen::Vector3d &point, const Eigen::Vector3d &normal);

  std::string
  name () const override { return "plane"; }

  bool
  intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
             SurfaceHit &hit) const override;

  /** \brief Unit normal. */
  const Eigen::Vector3d &
  normal () const { return normal_; }

  /** \brief normal . p for the points p of the plane. */
  double
  offset () const { return offset_; }

private:
  Eigen::Vector3d normal_;
  double offset_; ///< normal . p for points p of the plane
};

/** \brief Rectangle: centre, unit normal and in-plane axis, half sizes along that axis and
  * along normal x axis (a table top, a finite wall).
  */
class RectangleSurface : public Surface
{
public:
  /** \throws pcl::BadArgumentException for non-positive sizes or axes that are zero or not
    *         perpendicular to the normal.
    */
  RectangleSurface (const Eigen::Vector3d &centre, const Eigen::Vector3d &normal, const Eigen::Vector3d &axis_u,
                    double half_u, double half_v);

  std::string
  name () const override { return "rectangle"; }

  bool
  intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
             SurfaceHit &hit) const override;

private:
  Eigen::Vector3d centre_, normal_, axis_u_, axis_v_;
  double half_u_, half_v_;
};

/** \brief Sphere of a centre and a radius (hit from outside). */
class SphereSurface : public Surface
{
public:
  /** \throws pcl::BadArgumentException for a non-positive radius. */
  SphereSurface (const Eigen::Vector3d &centre, double radius);

  std::string
  name () const override { return "sphere"; }

  bool
  intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
             SurfaceHit &hit) const override;

private:
  Eigen::Vector3d centre_;
  double radius_;
};

/** \brief Box of edge lengths \a size (x, y, z of its own frame) whose centre and axes are
  * given by \a pose (scene from box). Hit from outside.
  */
class BoxSurface : public Surface
{
public:
  /** \throws pcl::BadArgumentException for non-positive sizes or a pose that is not rigid. */
  BoxSurface (const Eigen::Isometry3d &pose, const Eigen::Vector3d &size);

  std::string
  name () const override { return "box"; }

  bool
  intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
             SurfaceHit &hit) const override;

  /** \brief Edge lengths along the box's own x, y, z axes. */
  const Eigen::Vector3d &
  size () const { return size_; }

private:
  Eigen::Isometry3d pose_;
  Eigen::Vector3d size_;
};

/** \brief A set of surfaces; the nearest hit wins. */
class Scene
{
public:
  using Ptr = std::shared_ptr<Scene>;
  using ConstPtr = std::shared_ptr<const Scene>;

  /** \brief Adds a surface (shared, not copied). \throws pcl::BadArgumentException for null. */
  Scene &
  add (const Surface::ConstPtr &surface);

  /** \brief The surfaces in the order they were added (SurfaceHit::surface indexes them). */
  const std::vector<Surface::ConstPtr> &
  surfaces () const { return surfaces_; }

  /** \brief Nearest hit with t_min < t < t_max; false if none. */
  bool
  intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min, double t_max,
             SurfaceHit &hit) const;

  /** \brief True if some surface lies strictly between \a from and \a to (short of \a to by more
    * than \a tolerance metres): the segment is blocked.
    */
  bool
  occluded (const Eigen::Vector3d &from, const Eigen::Vector3d &to, double tolerance = 1e-4) const;

private:
  std::vector<Surface::ConstPtr> surfaces_;
};

} // namespace sim
} // namespace texlet
} // namespace pcl
