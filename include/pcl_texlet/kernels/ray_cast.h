/*
 * pcl_texlet kernels: ray intersections with planes, spheres, boxes, triangles and a BVH.
 *
 * A ray is origin + t * direction; the direction need not be unit length. The simulator casts
 * rays whose direction has z = 1 in the camera frame, so t is the depth along the optical axis.
 * Each function returns false when the ray misses (or runs parallel to a plane); callers decide
 * which t are acceptable (t > 0, closer than the best hit so far).
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/vec3.h>

#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Ray parameter where the ray meets the plane n . p = offset. False when parallel. */
template <typename S> PCL_TEXLET_HD bool
rayPlane (const Vec3<S> &origin, const Vec3<S> &direction, const Vec3<S> &n, S offset, S &t)
{
  const S den = dot (n, direction);
  if (std::fabs (den) < S (1e-12))
    return false;
  t = (offset - dot (n, origin)) / den;
  return true;
}

/** \brief Nearer ray parameter where the ray meets the sphere |p - centre| = radius. */
template <typename S> PCL_TEXLET_HD bool
raySphere (const Vec3<S> &origin, const Vec3<S> &direction, const Vec3<S> &centre, S radius, S &t)
{
  const Vec3<S> oc = origin - centre;
  const S a = squaredNorm (direction), b = S (2) * dot (direction, oc), c = squaredNorm (oc) - radius * radius;
  const S disc = b * b - S (4) * a * c;
  if (disc < 0)
    return false;
  t = (-b - std::sqrt (disc)) / (S (2) * a);
  return true;
}

/** \brief Entry into the axis-aligned box [lo, hi] (slab test): ray parameter, the entered
  * face's axis (0, 1, 2) and the sign of its outward normal along that axis. False when the ray
  * misses the box or starts inside it (no entry face).
  */
template <typename S> PCL_TEXLET_HD bool
rayBoxEntry (const Vec3<S> &origin, const Vec3<S> &direction, const Vec3<S> &lo, const Vec3<S> &hi, S &t,
             int &axis, S &sign)
{
  S tmin = 0, tmax = S (3e38); // beyond any scene, and finite in float too
  axis = -1;
  sign = 0;
  for (int i = 0; i < 3; ++i)
  {
    const S o = component (origin, i), r = component (direction, i);
    const S l = component (lo, i), h = component (hi, i);
    if (std::fabs (r) < S (1e-15))
    {
      if (o < l || o > h)
        return false;
      continue;
    }
    S t0 = (l - o) / r, t1 = (h - o) / r;
    S s = -1;
    if (t0 > t1)
    {
      const S tmp = t0;
      t0 = t1;
      t1 = tmp;
      s = 1;
    }
    if (t0 > tmin)
    {
      tmin = t0;
      axis = i;
      sign = s;
    }
    tmax = tmax < t1 ? tmax : t1;
    if (tmin > tmax)
      return false;
  }
  if (axis < 0)
    return false;
  t = tmin;
  return true;
}

/** \brief Interval [t_near, t_far] of the ray inside the box [lo, hi], given the reciprocal
  * direction (components may be +-inf). False when the interval is empty or beyond t_max.
  */
template <typename S> PCL_TEXLET_HD bool
raySlabs (const Vec3<S> &origin, const Vec3<S> &inv_direction, const S lo[3], const S hi[3], S t_max, S &t_near)
{
  S tn = 0, tf = t_max;
  for (int i = 0; i < 3; ++i)
  {
    const S o = component (origin, i), inv = component (inv_direction, i);
    S t0 = (lo[i] - o) * inv, t1 = (hi[i] - o) * inv;
    // 0 * inf is NaN when the ray lies in a slab's plane: treat that side as unbounded.
    if (t0 != t0)
      t0 = -S (3e38);
    if (t1 != t1)
      t1 = S (3e38);
    if (t0 > t1)
    {
      const S tmp = t0;
      t0 = t1;
      t1 = tmp;
    }
    tn = t0 > tn ? t0 : tn;
    tf = t1 < tf ? t1 : tf;
    if (tn > tf)
      return false;
  }
  t_near = tn;
  return true;
}

/** \brief A triangle stored as a vertex and two edges (what Moller-Trumbore needs). */
template <typename S>
struct Triangle
{
  Vec3<S> a, e1, e2; ///< vertex a, b - a, c - a
};

/** \brief Moller-Trumbore ray-triangle intersection (both faces). */
template <typename S> PCL_TEXLET_HD bool
rayTriangle (const Vec3<S> &origin, const Vec3<S> &direction, const Triangle<S> &tri, S &t)
{
  const Vec3<S> p = cross (direction, tri.e2);
  const S det = dot (tri.e1, p);
  if (std::fabs (det) < S (1e-18))
    return false;
  const S inv = S (1) / det;
  const Vec3<S> s = origin - tri.a;
  const S bu = dot (s, p) * inv;
  if (bu < 0 || bu > 1)
    return false;
  const Vec3<S> q = cross (s, tri.e1);
  const S bv = dot (direction, q) * inv;
  if (bv < 0 || bu + bv > 1)
    return false;
  t = dot (tri.e2, q) * inv;
  return true;
}

/** \brief Node of a flat bounding volume hierarchy. A leaf (count > 0) holds the triangles
  * [first, first + count); an inner node (count == 0) has its children at first and first + 1.
  */
template <typename S>
struct BvhNode
{
  S lo[3];
  S hi[3];
  std::int32_t first;
  std::int32_t count;
};

/** \brief Deepest BVH the traversal stack holds (depth-first, one pending sibling per level);
  * builders must not exceed it.
  */
constexpr int kBvhMaxDepth = 64;

/** \brief Nearest triangle hit with t_min < t < t_best along the ray; updates t_best and
  * triangle and returns true when one was found.
  */
template <typename S> PCL_TEXLET_HD bool
rayBvh (const BvhNode<S> *nodes, const Triangle<S> *triangles, const Vec3<S> &origin, const Vec3<S> &direction,
        S t_min, S &t_best, std::int32_t &triangle)
{
  const Vec3<S> inv = {S (1) / direction.x, S (1) / direction.y, S (1) / direction.z};
  std::int32_t stack[kBvhMaxDepth + 1];
  int top = 0;
  stack[top++] = 0;
  bool found = false;
  while (top > 0)
  {
    const BvhNode<S> &node = nodes[stack[--top]];
    S t_near;
    if (!raySlabs (origin, inv, node.lo, node.hi, t_best, t_near))
      continue;
    if (node.count > 0)
    {
      for (std::int32_t i = node.first; i < node.first + node.count; ++i)
      {
        S t;
        if (rayTriangle (origin, direction, triangles[i], t) && t > t_min && t < t_best)
        {
          t_best = t;
          triangle = i;
          found = true;
        }
      }
    }
    else
    {
      stack[top++] = node.first;
      stack[top++] = node.first + 1;
    }
  }
  return found;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
