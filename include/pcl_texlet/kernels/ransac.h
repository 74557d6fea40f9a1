/*
 * pcl_texlet kernels: RANSAC outlier rejection in a texlet's neighbourhood (paper, Step 2).
 *
 * As in the paper's GPU version: a fixed number of iterations, three points per hypothesis,
 * a point-to-plane threshold, and no refit of the best plane (the fit that follows is done
 * on its inliers). The triples come from Philox counters (seed, texlet, iteration), so the
 * outcome depends on nothing else.
 */
#pragma once

#include <pcl_texlet/kernels/philox_rng.h>
#include <pcl_texlet/kernels/vec3.h>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Plane n . p + d = 0 with unit n. */
template <typename S>
struct Plane
{
  Vec3<S> n;
  S d;
};

template <typename S> PCL_TEXLET_HD S
pointPlaneDistance (const Plane<S> &plane, const Vec3<S> &p)
{
  return std::fabs (dot (plane.n, p) + plane.d);
}

/** \brief Best plane over \a iterations hypotheses through three distinct points of the
  * \a n points (x, y, z). \return its inlier count (distance <= threshold), 0 if every
  * hypothesis was degenerate (collinear triples) or n < 3.
  */
template <typename S> PCL_TEXLET_HD int
ransacPlane (const S *x, const S *y, const S *z, int n, int iterations, S threshold,
             std::uint32_t seed, std::uint32_t texlet, Plane<S> &best)
{
  if (n < 3)
    return 0;
  int best_count = 0;
  for (int it = 0; it < iterations; ++it)
  {
    int ia, ib, ic;
    distinctTriple (philoxWords (seed, texlet, static_cast<std::uint32_t> (it), 0u, RandomStream::Ransac), n, ia, ib, ic);
    const Vec3<S> pa = {x[ia], y[ia], z[ia]};
    const Vec3<S> ab = make3 (x[ib], y[ib], z[ib]) - pa, ac = make3 (x[ic], y[ic], z[ic]) - pa;
    const Vec3<S> c = cross (ab, ac);
    const S c2 = squaredNorm (c);
    // Skip (nearly) collinear triples: their plane is not determined.
    if (!(c2 > S (1e-10) * squaredNorm (ab) * squaredNorm (ac)))
      continue;
    Plane<S> h;
    h.n = (S (1) / std::sqrt (c2)) * c;
    h.d = -dot (h.n, pa);
    // Count in chunks and give up on a hypothesis once it can no longer beat the best one:
    // the same planes win, with less counting.
    int count = 0;
    for (int start = 0; start < n; start += 32)
    {
      const int end = n - start < 32 ? n : start + 32;
      for (int i = start; i < end; ++i)
        count += pointPlaneDistance (h, make3 (x[i], y[i], z[i])) <= threshold ? 1 : 0;
      if (count + (n - end) <= best_count)
        break;
    }
    if (count > best_count)
    {
      best_count = count;
      best = h;
    }
  }
  return best_count;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
