/*
 * Test support: organised clouds rendered by ray casting analytic scenes (planes, spheres,
 * boxes) through a pinhole camera, with depth noise from a NoiseModel added along each ray.
 * Ground truth (noise-free points and surface normals) comes with every render. The ray
 * intersections are the library's kernels (kernels/ray_cast.h), which the simulator uses too.
 */
#pragma once

#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/kernels/ray_cast.h>
#include <pcl_texlet/noise/noise_model.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

namespace pcl_texlet_test
{

/** A surface hit: depth along the ray parameter (z, since rays have z = 1) and unit normal. */
struct Hit
{
  double t = std::numeric_limits<double>::infinity ();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero ();
};

inline pcl::texlet::kernels::Vec3<double>
vec3 (const Eigen::Vector3d &v)
{
  return {v.x (), v.y (), v.z ()};
}

/** Rays start at the camera centre. */
const pcl::texlet::kernels::Vec3<double> kOrigin = {0.0, 0.0, 0.0};

struct Surface
{
  virtual ~Surface () = default;
  /** Nearest hit of the ray t * r (t > 0), if closer than `hit`. */
  virtual void intersect (const Eigen::Vector3d &r, Hit &hit) const = 0;
};

/** Plane n . p = d, optionally bounded to the half space where side . p > side_offset. */
struct PlaneSurface : Surface
{
  Eigen::Vector3d n;
  double d;
  Eigen::Vector3d side = Eigen::Vector3d::Zero ();
  double side_offset = 0.0;

  PlaneSurface (const Eigen::Vector3d &normal, const Eigen::Vector3d &point) : n (normal.normalized ()), d (n.dot (point)) {}

  void
  intersect (const Eigen::Vector3d &r, Hit &hit) const override
  {
    double t;
    if (!pcl::texlet::kernels::rayPlane (kOrigin, vec3 (r), vec3 (n), d, t))
      return;
    if (t <= 0 || t >= hit.t)
      return;
    if (side.squaredNorm () > 0 && side.dot (t * r) <= side_offset)
      return;
    hit.t = t;
    hit.normal = n;
  }
};

struct SphereSurface : Surface
{
  Eigen::Vector3d c;
  double radius;

  SphereSurface (const Eigen::Vector3d &centre, double r) : c (centre), radius (r) {}

  void
  intersect (const Eigen::Vector3d &r, Hit &hit) const override
  {
    double t;
    if (!pcl::texlet::kernels::raySphere (kOrigin, vec3 (r), vec3 (c), radius, t))
      return;
    if (t <= 0 || t >= hit.t)
      return;
    hit.t = t;
    hit.normal = (t * r - c).normalized ();
  }
};

/** Axis-aligned box in camera coordinates. */
struct BoxSurface : Surface
{
  Eigen::Vector3d lo, hi;

  BoxSurface (const Eigen::Vector3d &min, const Eigen::Vector3d &max) : lo (min), hi (max) {}

  void
  intersect (const Eigen::Vector3d &r, Hit &hit) const override
  {
    double tmin, sign;
    int axis;
    if (!pcl::texlet::kernels::rayBoxEntry (kOrigin, vec3 (r), vec3 (lo), vec3 (hi), tmin, axis, sign))
      return;
    if (tmin <= 0 || tmin >= hit.t)
      return;
    hit.t = tmin;
    hit.normal = Eigen::Vector3d::Zero ();
    hit.normal[axis] = sign;
  }
};

struct Scene
{
  std::vector<std::shared_ptr<Surface>> surfaces;

  template <typename T, typename... Args> Scene &
  add (Args &&...args)
  {
    surfaces.push_back (std::make_shared<T> (std::forward<Args> (args)...));
    return *this;
  }
};

/** A render: the noisy organised cloud and its ground truth per pixel. */
/** A plane at \a distance on the optical axis, facing the camera turned by the two tilts (degrees). */
inline Scene
tiltedPlane (double tilt_x_deg, double tilt_y_deg, double distance)
{
  const double ax = tilt_x_deg * M_PI / 180, ay = tilt_y_deg * M_PI / 180;
  const Eigen::Vector3d n = (Eigen::AngleAxisd (ax, Eigen::Vector3d::UnitX ()) *
                             Eigen::AngleAxisd (ay, Eigen::Vector3d::UnitY ()) * Eigen::Vector3d (0, 0, -1));
  Scene s;
  s.add<PlaneSurface> (n, Eigen::Vector3d (0, 0, distance));
  return s;
}

/** A sphere of radius 0.45 m, 1.3 m ahead: every incidence angle. */
inline Scene
sphereScene ()
{
  Scene s;
  s.add<SphereSurface> (Eigen::Vector3d (0, 0, 1.3), 0.45);
  return s;
}

/** A box on a wall behind it: faces at three orientations plus depth edges. */
inline Scene
boxScene ()
{
  Scene s;
  s.add<BoxSurface> (Eigen::Vector3d (-0.12, -0.10, 0.9), Eigen::Vector3d (0.18, 0.14, 1.2));
  s.add<PlaneSurface> (Eigen::Vector3d (0.1, 0.2, -1), Eigen::Vector3d (0, 0, 1.5));
  return s;
}

struct Render
{
  pcl::PointCloud<pcl::PointXYZ> cloud;
  std::vector<Eigen::Vector3d> clean;   // noise-free points (NaN where no hit)
  std::vector<Eigen::Vector3d> normals; // true unit normals facing the camera
};

struct CameraSpec
{
  int width = 160, height = 120;
  double fx = 525.0 / 4, fy = 525.0 / 4, cx = 79.5, cy = 59.5;

  pcl::texlet::PinholeModel
  pinhole () const { return pcl::texlet::PinholeModel (fx, fy, cx, cy); }
};

/** Ray-casts `scene`; adds depth noise of the model's sigma along each ray when `noise` is set. */
inline Render
render (const Scene &scene, const CameraSpec &cam, const pcl::texlet::NoiseModel *noise, std::uint32_t seed)
{
  Render out;
  out.cloud.width = cam.width;
  out.cloud.height = cam.height;
  out.cloud.is_dense = false;
  out.cloud.resize (static_cast<std::size_t> (cam.width) * cam.height);
  out.clean.assign (out.cloud.size (), Eigen::Vector3d::Constant (std::nan ("")));
  out.normals.assign (out.cloud.size (), Eigen::Vector3d::Zero ());
  std::mt19937 rng (seed);
  std::normal_distribution<double> gauss (0.0, 1.0);
  const pcl::texlet::PinholeModel pin = cam.pinhole ();
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * cam.width + u;
      const Eigen::Vector3d r ((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
      Hit hit;
      for (const auto &s : scene.surfaces)
        s->intersect (r, hit);
      pcl::PointXYZ &p = out.cloud[i];
      if (!std::isfinite (hit.t))
      {
        p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN ();
        continue;
      }
      double z = hit.t;
      out.clean[i] = z * r;
      out.normals[i] = hit.normal.dot (r) < 0 ? hit.normal : Eigen::Vector3d (-hit.normal);
      if (noise)
      {
        pcl::texlet::PixelContext ctx;
        ctx.u = u;
        ctx.v = v;
        ctx.radius_px = pin.principalPointDistance (u, v);
        ctx.depth_mm = z * 1000.0;
        z += noise->sigmaMm (ctx) * 1e-3 * gauss (rng);
      }
      p.x = static_cast<float> (z * r.x ());
      p.y = static_cast<float> (z * r.y ());
      p.z = static_cast<float> (z);
    }
  return out;
}

/** Angle in radians between two directions, ignoring their sign. */
inline double
axisAngle (const Eigen::Vector3d &a, const Eigen::Vector3d &b)
{
  return std::atan2 (a.cross (b).norm (), std::fabs (a.dot (b)));
}

/** A noise model with the paper's sigma scaled by `factor`. */
inline pcl::texlet::NoiseModel
scaledPaperNoise (double factor)
{
  auto c = pcl::texlet::kernels::paperPolynomial ();
  c = {c.p00 * factor, c.p10 * factor, c.p01 * factor, c.p20 * factor, c.p11 * factor, c.p02 * factor};
  pcl::texlet::NoiseModel m;
  m.add (pcl::texlet::PolynomialSigmaTerm (c));
  return m;
}

} // namespace pcl_texlet_test
