/*
 * pcl_texlet kernels: RANSAC outlier rejection in a texlet's neighbourhood (paper, Step 2).
 *
 * As in the paper's GPU version: a fixed number of iterations, three points per hypothesis,
 * a point-to-plane threshold, and no refit of the best plane (the fit that follows is done
 * on its inliers). The triples come from Philox counters (seed, texlet, iteration), so the
 * outcome depends on nothing else.
 */
#pragma once

#include <pcl_texlet/kernels/normal_blocks.h>
#include <pcl_texlet/kernels/philox_rng.h>
#include <pcl_texlet/kernels/vec3.h>

#include <type_traits>

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

/** \brief Whether \a p is an inlier of \a plane: within \a threshold of it. */
template <typename S> PCL_TEXLET_HD bool
isInlier (const Plane<S> &plane, const Vec3<S> &p, S threshold)
{
  return pointPlaneDistance (plane, p) <= threshold;
}

/** \brief Number of points i in [begin, end) that are inliers of \a plane (isInlier()). */
template <typename S> PCL_TEXLET_HD int
countInliers (const Plane<S> &plane, const S *x, const S *y, const S *z, int begin, int end, S threshold)
{
  int count = 0;
  int i = begin;
#if defined(PCL_TEXLET_AVX2_KERNELS)
  if constexpr (std::is_same<S, double>::value)
  {
    // Four points a step, the very operations of pointPlaneDistance in the same order.
    const __m256d nx = _mm256_set1_pd (plane.n.x), ny = _mm256_set1_pd (plane.n.y), nz = _mm256_set1_pd (plane.n.z);
    const __m256d d = _mm256_set1_pd (plane.d), thr = _mm256_set1_pd (threshold);
    const __m256d abs_mask = _mm256_castsi256_pd (_mm256_set1_epi64x (0x7fffffffffffffffLL));
    __m256i in = _mm256_setzero_si256 ();
    for (; i + 4 <= end; i += 4)
    {
      const __m256d dot = _mm256_add_pd (_mm256_add_pd (_mm256_mul_pd (nx, _mm256_loadu_pd (x + i)),
                                                        _mm256_mul_pd (ny, _mm256_loadu_pd (y + i))),
                                         _mm256_mul_pd (nz, _mm256_loadu_pd (z + i)));
      const __m256d dist = _mm256_and_pd (_mm256_add_pd (dot, d), abs_mask);
      in = _mm256_sub_epi64 (in, _mm256_castpd_si256 (_mm256_cmp_pd (dist, thr, _CMP_LE_OQ)));
    }
    const __m128i sum2 = _mm_add_epi64 (_mm256_castsi256_si128 (in), _mm256_extracti128_si256 (in, 1));
    count = static_cast<int> (_mm_cvtsi128_si64 (sum2) + _mm_extract_epi64 (sum2, 1));
  }
#endif
  for (; i < end; ++i)
    count += isInlier (plane, make3 (x[i], y[i], z[i]), threshold) ? 1 : 0;
  return count;
}

/** \brief mask[i] = 1 for the inliers of \a plane (isInlier()), else 0, for i in [0, n). */
template <typename S> PCL_TEXLET_HD void
markInliers (const Plane<S> &plane, const S *x, const S *y, const S *z, int n, S threshold, unsigned char *mask)
{
  int i = 0;
#if defined(PCL_TEXLET_AVX2_KERNELS)
  if constexpr (std::is_same<S, double>::value)
  {
    const __m256d nx = _mm256_set1_pd (plane.n.x), ny = _mm256_set1_pd (plane.n.y), nz = _mm256_set1_pd (plane.n.z);
    const __m256d d = _mm256_set1_pd (plane.d), thr = _mm256_set1_pd (threshold);
    const __m256d abs_mask = _mm256_castsi256_pd (_mm256_set1_epi64x (0x7fffffffffffffffLL));
    for (; i + 4 <= n; i += 4)
    {
      const __m256d dot = _mm256_add_pd (_mm256_add_pd (_mm256_mul_pd (nx, _mm256_loadu_pd (x + i)),
                                                        _mm256_mul_pd (ny, _mm256_loadu_pd (y + i))),
                                         _mm256_mul_pd (nz, _mm256_loadu_pd (z + i)));
      const __m256d dist = _mm256_and_pd (_mm256_add_pd (dot, d), abs_mask);
      const int bits = _mm256_movemask_pd (_mm256_cmp_pd (dist, thr, _CMP_LE_OQ));
      for (int j = 0; j < 4; ++j)
        mask[i + j] = static_cast<unsigned char> ((bits >> j) & 1);
    }
  }
#endif
  for (; i < n; ++i)
    mask[i] = isInlier (plane, make3 (x[i], y[i], z[i]), threshold) ? 1 : 0;
}

/** \brief Philox words of RANSAC hypothesis \a iteration of a texlet (the batches of
  * philoxCounters() in ransacPlane() hold the same words).
  */
PCL_TEXLET_HD r123::Philox4x32::ctr_type
ransacWords (std::uint32_t seed, std::uint32_t texlet, int iteration)
{
  return philoxWords (seed, texlet, static_cast<std::uint32_t> (iteration), 0u, RandomStream::Ransac);
}

/** \brief One RANSAC hypothesis: the plane \a h through the three distinct points of the \a n
  * points (x, y, z) that the words \a w pick (distinctTriple()).
  * \return false for a (nearly) collinear triple, whose plane is not determined
  */
template <typename S> PCL_TEXLET_HD bool
ransacHypothesis (const S *x, const S *y, const S *z, int n, const r123::Philox4x32::ctr_type &w, Plane<S> &h)
{
  int ia, ib, ic;
  distinctTriple (w, n, ia, ib, ic);
  const Vec3<S> pa = {x[ia], y[ia], z[ia]};
  const Vec3<S> ab = make3 (x[ib], y[ib], z[ib]) - pa, ac = make3 (x[ic], y[ic], z[ic]) - pa;
  const Vec3<S> c = cross (ab, ac);
  const S c2 = squaredNorm (c);
  if (!(c2 > S (1e-10) * squaredNorm (ab) * squaredNorm (ac)))
    return false;
  h.n = (S (1) / std::sqrt (c2)) * c;
  h.d = -dot (h.n, pa);
  return true;
}

/** \brief Best plane over \a iterations hypotheses (ransacHypothesis()) of the \a n points
  * (x, y, z); the first of the hypotheses with the most inliers wins.
  * \return its inlier count, 0 if every hypothesis was degenerate or n < 3
  */
template <typename S> PCL_TEXLET_HD int
ransacPlane (const S *x, const S *y, const S *z, int n, int iterations, S threshold,
             std::uint32_t seed, std::uint32_t texlet, Plane<S> &best)
{
  if (n < 3)
    return 0;
  int best_count = 0;
  // The hypotheses' Philox words, a batch of iterations at a time (philoxCounters).
  constexpr int batch = 8;
  std::uint32_t words[4][batch];
  for (int it = 0; it < iterations; ++it)
  {
    const int slot = it % batch;
    if (slot == 0)
    {
      const int m = iterations - it < batch ? iterations - it : batch;
      philoxCounters (seed, texlet, 0u, RandomStream::Ransac, it, m, words[0], words[1], words[2], words[3]);
    }
    const r123::Philox4x32::ctr_type w = {{words[0][slot], words[1][slot], words[2][slot], words[3][slot]}};
    Plane<S> h;
    if (!ransacHypothesis (x, y, z, n, w, h))
      continue;
    // Count in chunks and give up on a hypothesis once it can no longer beat the best one:
    // the same planes win, with less counting.
    int count = 0;
    for (int start = 0; start < n; start += 32)
    {
      const int end = n - start < 32 ? n : start + 32;
      count += countInliers (h, x, y, z, start, end, threshold);
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
