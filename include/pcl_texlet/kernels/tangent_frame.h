/*
 * pcl_texlet kernels: the tangent frame in which the normal's covariance is expressed.
 *
 * Sigma_N is a 2x2 covariance of the normal's deviation along two unit tangents (t1, t2) of N,
 * in radians (small angles). The frame is a fixed function of N alone (Duff et al. 2017,
 * "Building an orthonormal basis, revisited"), so a reader can rebuild it from the stored
 * normal. (t1, t2, N) is right-handed; for a surface facing the camera (N.z < 0) t1 points to
 * +x (right in the image) and t2 to -y (up in the image). The only discontinuity is at N.z = 0,
 * a surface seen exactly edge-on.
 */
#pragma once

#include <pcl_texlet/kernels/vec3.h>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Tangents t1, t2 of unit normal \a n, such that (t1, t2, n) is right-handed. */
template <typename S> PCL_TEXLET_HD void
tangentFrame (const Vec3<S> &n, Vec3<S> &t1, Vec3<S> &t2)
{
  const S sign = n.z >= S (0) ? S (1) : S (-1);
  const S a = S (-1) / (sign + n.z);
  const S b = n.x * n.y * a;
  t1 = {S (1) + sign * n.x * n.x * a, sign * b, -sign * n.x};
  t2 = {b, sign + n.y * n.y * a, -n.y};
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
