#include <pcl_texlet/simulation/scene.h>
#include <pcl_texlet/kernels/ray_cast.h>

#include "vec3_eigen.h"

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

std::string
text (const Eigen::Vector3d &v)
{
  std::ostringstream s;
  s << "(" << v.x () << ", " << v.y () << ", " << v.z () << ")";
  return s.str ();
}

Eigen::Vector3d
unitNormal (const Eigen::Vector3d &n, const std::string &what)
{
  if (!n.allFinite () || !(n.norm () > 1e-12))
    throw pcl::BadArgumentException (what + ": the normal " + text (n) + " must be finite and non-zero");
  return n.normalized ();
}

/** Accepts a hit only inside (t_min, hit.t). */
bool
closer (double t, double t_min, const SurfaceHit &hit)
{
  return t > t_min && t < hit.t;
}

} // namespace

// ---------------------------------------------------------------------------------------------

PlaneSurface::PlaneSurface (const Eigen::Vector3d &point, const Eigen::Vector3d &normal)
  : normal_ (unitNormal (normal, "PlaneSurface")), offset_ (normal_.dot (point))
{
  if (!point.allFinite ())
    throw pcl::BadArgumentException ("PlaneSurface: the point " + text (point) + " must be finite");
}

bool
PlaneSurface::intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
                         SurfaceHit &hit) const
{
  double t;
  if (!kernels::rayPlane (toVec3 (origin), toVec3 (direction), toVec3 (normal_), offset_, t) || !closer (t, t_min, hit))
    return false;
  hit.t = t;
  hit.normal = normal_;
  return true;
}

// ---------------------------------------------------------------------------------------------

RectangleSurface::RectangleSurface (const Eigen::Vector3d &centre, const Eigen::Vector3d &normal,
                                    const Eigen::Vector3d &axis_u, double half_u, double half_v)
  : centre_ (centre), normal_ (unitNormal (normal, "RectangleSurface")), half_u_ (half_u), half_v_ (half_v)
{
  if (!centre.allFinite () || !(half_u > 0) || !(half_v > 0) || !std::isfinite (half_u) || !std::isfinite (half_v))
  {
    std::ostringstream msg;
    msg << "RectangleSurface: the centre must be finite and the half sizes positive (got centre " << text (centre)
        << ", half sizes " << half_u << " x " << half_v << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
  if (!axis_u.allFinite () || !(axis_u.norm () > 1e-12) || std::fabs (axis_u.normalized ().dot (normal_)) > 1e-9)
    throw pcl::BadArgumentException ("RectangleSurface: the in-plane axis " + text (axis_u) +
                                     " must be non-zero and perpendicular to the normal " + text (normal_));
  axis_u_ = axis_u.normalized ();
  axis_v_ = normal_.cross (axis_u_);
}

bool
RectangleSurface::intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
                             SurfaceHit &hit) const
{
  double t;
  if (!kernels::rayPlane (toVec3 (origin), toVec3 (direction), toVec3 (normal_), normal_.dot (centre_), t) ||
      !closer (t, t_min, hit))
    return false;
  const Eigen::Vector3d local = origin + t * direction - centre_;
  if (std::fabs (local.dot (axis_u_)) > half_u_ || std::fabs (local.dot (axis_v_)) > half_v_)
    return false;
  hit.t = t;
  hit.normal = normal_;
  return true;
}

// ---------------------------------------------------------------------------------------------

SphereSurface::SphereSurface (const Eigen::Vector3d &centre, double radius) : centre_ (centre), radius_ (radius)
{
  if (!centre.allFinite () || !(radius > 0) || !std::isfinite (radius))
  {
    std::ostringstream msg;
    msg << "SphereSurface: the centre must be finite and the radius positive (got centre " << text (centre)
        << ", radius " << radius << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
}

bool
SphereSurface::intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
                          SurfaceHit &hit) const
{
  double t;
  if (!kernels::raySphere (toVec3 (origin), toVec3 (direction), toVec3 (centre_), radius_, t) || !closer (t, t_min, hit))
    return false;
  hit.t = t;
  hit.normal = (origin + t * direction - centre_).normalized ();
  return true;
}

// ---------------------------------------------------------------------------------------------

BoxSurface::BoxSurface (const Eigen::Isometry3d &pose, const Eigen::Vector3d &size) : pose_ (pose), size_ (size)
{
  if (!size.allFinite () || !(size.minCoeff () > 0))
    throw pcl::BadArgumentException ("BoxSurface: the edge lengths " + text (size) + " must be positive");
  const Eigen::Matrix3d r = pose.linear ();
  if (!pose.matrix ().allFinite () || !(r.transpose () * r).isIdentity (1e-9) || !(r.determinant () > 0))
    throw pcl::BadArgumentException ("BoxSurface: the pose must be a finite rigid transform (rotation and translation)");
}

bool
BoxSurface::intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min,
                       SurfaceHit &hit) const
{
  // Into the box's frame, where it is axis-aligned; t is unchanged by a rigid transform.
  const Eigen::Matrix3d rt = pose_.linear ().transpose ();
  const Eigen::Vector3d o = rt * (origin - pose_.translation ()), d = rt * direction;
  double t, sign;
  int axis;
  if (!kernels::rayBoxEntry (toVec3 (o), toVec3 (d), toVec3 (-0.5 * size_), toVec3 (0.5 * size_), t, axis, sign) ||
      !closer (t, t_min, hit))
    return false;
  hit.t = t;
  hit.normal = sign * pose_.linear ().col (axis);
  return true;
}

// ---------------------------------------------------------------------------------------------

Scene &
Scene::add (const Surface::ConstPtr &surface)
{
  if (!surface)
    throw pcl::BadArgumentException ("Scene::add: the surface is null");
  surfaces_.push_back (surface);
  return *this;
}

bool
Scene::intersect (const Eigen::Vector3d &origin, const Eigen::Vector3d &direction, double t_min, double t_max,
                  SurfaceHit &hit) const
{
  hit = SurfaceHit ();
  hit.t = t_max;
  bool found = false;
  for (std::size_t i = 0; i < surfaces_.size (); ++i)
    if (surfaces_[i]->intersect (origin, direction, t_min, hit))
    {
      hit.surface = static_cast<int> (i);
      found = true;
    }
  if (!found)
    hit.t = std::numeric_limits<double>::infinity ();
  return found;
}

bool
Scene::occluded (const Eigen::Vector3d &from, const Eigen::Vector3d &to, double tolerance) const
{
  const Eigen::Vector3d d = to - from;
  const double length = d.norm ();
  if (!(length > tolerance))
    return false;
  SurfaceHit hit;
  // With t in units of the segment, "short of `to` by more than tolerance" is t < 1 - tol/length.
  return intersect (from, d, tolerance / length, 1.0 - tolerance / length, hit);
}

} // namespace sim
} // namespace texlet
} // namespace pcl
