/*
 * pcl_texlet kernels: the relation between two texlets (the paper's Sect. 4, Fig. 9).
 *
 * A pair of texlets (P_i, N_i), (P_j, N_j) is related by
 *  - the normal distance n_ij = |N_j . (P_i - P_j)|: how far texlet i's centre lies from texlet
 *    j's plane (for parallel planes, the distance between the planes), and
 *  - the angle theta = acos(N_i . N_j) between the normals, 0 to 180 degrees.
 * n_ij and n_ji differ unless the planes are parallel, so an unordered pair gives two directed
 * relations that share one angle; the paper's histograms take every texlet against every other
 * one, i.e. both directions.
 *
 * Plain functions on Vec3, no PCL types: the CPU accumulation and a future CUDA backend run the
 * same code (one thread per row i, say).
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/vec3.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Both directed relations of one texlet pair. */
template <typename S>
struct PairRelation
{
  S distance_ij; ///< |N_j . (P_i - P_j)|: centre i from plane j, in the units of P
  S distance_ji; ///< |N_i . (P_j - P_i)|: centre j from plane i
  S angle_deg;   ///< angle between N_i and N_j, degrees in [0, 180]
};

/** \brief Angle between two unit vectors in degrees, [0, 180]; the cosine is clamped so that
  * rounding never makes acos return NaN.
  */
template <typename S> PCL_TEXLET_HD S
normalAngleDeg (const Vec3<S> &n_i, const Vec3<S> &n_j)
{
  S c = dot (n_i, n_j);
  c = c > S (1) ? S (1) : (c < S (-1) ? S (-1) : c);
  return std::acos (c) * S (57.29577951308232);
}

/** \brief Normal distance from centre \a p_i to the plane through \a p_j with unit normal \a n_j. */
template <typename S> PCL_TEXLET_HD S
normalDistance (const Vec3<S> &p_i, const Vec3<S> &p_j, const Vec3<S> &n_j)
{
  return std::fabs (dot (n_j, p_i - p_j));
}

/** \brief The relation of texlets i and j in both directions (normals must be unit vectors). */
template <typename S> PCL_TEXLET_HD PairRelation<S>
texletRelation (const Vec3<S> &p_i, const Vec3<S> &n_i, const Vec3<S> &p_j, const Vec3<S> &n_j)
{
  const Vec3<S> d = p_i - p_j;
  PairRelation<S> r;
  r.distance_ij = std::fabs (dot (n_j, d));
  r.distance_ji = std::fabs (dot (n_i, d));
  r.angle_deg = normalAngleDeg (n_i, n_j);
  return r;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
