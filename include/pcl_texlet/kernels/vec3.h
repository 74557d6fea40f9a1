/*
 * pcl_texlet kernels: a minimal 3-vector usable on host and device.
 *
 * Eigen's fixed-size types would do on the host, but a plain aggregate keeps the kernels
 * trivially copyable into CUDA code and independent of any library.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace kernels
{

template <typename Scalar>
struct Vec3
{
  Scalar x, y, z;
};

template <typename S> PCL_TEXLET_HD Vec3<S>
make3 (S x, S y, S z) { return Vec3<S>{x, y, z}; }

template <typename S> PCL_TEXLET_HD Vec3<S>
operator+ (const Vec3<S> &a, const Vec3<S> &b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }

template <typename S> PCL_TEXLET_HD Vec3<S>
operator- (const Vec3<S> &a, const Vec3<S> &b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }

template <typename S> PCL_TEXLET_HD Vec3<S>
operator- (const Vec3<S> &a) { return {-a.x, -a.y, -a.z}; }

template <typename S> PCL_TEXLET_HD Vec3<S>
operator* (S s, const Vec3<S> &a) { return {s * a.x, s * a.y, s * a.z}; }

template <typename S> PCL_TEXLET_HD S
dot (const Vec3<S> &a, const Vec3<S> &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

template <typename S> PCL_TEXLET_HD Vec3<S>
cross (const Vec3<S> &a, const Vec3<S> &b)
{
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <typename S> PCL_TEXLET_HD S
squaredNorm (const Vec3<S> &a) { return dot (a, a); }

template <typename S> PCL_TEXLET_HD S
norm (const Vec3<S> &a) { return std::sqrt (dot (a, a)); }

/** \brief Unit vector along \a a; \a a must not be zero. */
template <typename S> PCL_TEXLET_HD Vec3<S>
normalized (const Vec3<S> &a) { return (S (1) / norm (a)) * a; }

/** \brief Packed symmetric 3x3 matrix index: xx xy xz yy yz zz. */
PCL_TEXLET_HD int
symIndex (int r, int c)
{
  const int lo = r < c ? r : c, hi = r < c ? c : r;
  return lo == 0 ? hi : (lo == 1 ? 2 + hi : 5);
}

/** \brief Component \a i (0, 1, 2) of \a a. */
template <typename S> PCL_TEXLET_HD S
component (const Vec3<S> &a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }

} // namespace kernels
} // namespace texlet
} // namespace pcl
