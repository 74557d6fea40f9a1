/*
 * The kernels' AVX2 paths (built when the compiler targets x86-64-v3, as the library's
 * src/features/texlet_kernel_x86_64_v3.cpp does) against their scalar definitions, bit for bit: the
 * Philox words of many counters or blocks at once, the Box-Muller normals, and RANSAC's
 * inlier count. This file is compiled twice (test/CMakeLists.txt): for the baseline, where it
 * checks the portable loops, and for x86-64-v3, where it checks the intrinsics.
 */
#include <pcl_texlet/kernels/normal_blocks.h>
#include <pcl_texlet/kernels/ransac.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace pcl::texlet::kernels;

namespace
{

bool
processorRunsThisBuild ()
{
#if defined(PCL_TEXLET_AVX2_KERNELS)
  __builtin_cpu_init ();
  return __builtin_cpu_supports ("avx2") && __builtin_cpu_supports ("fma");
#else
  return true;
#endif
}

} // namespace

TEST (SimdPaths, PhiloxCountersAreThoseOfRandom123)
{
  if (!processorRunsThisBuild ())
    GTEST_SKIP () << "this processor does not run x86-64-v3 code";
  std::uint32_t w[4][23];
  for (std::uint32_t texlet : {0u, 5u, 307199u, 0xffffffffu})
    for (int first : {0, 7, 1000})
      for (int n : {1, 3, 4, 8, 23})
      {
        philoxCounters (3u, texlet, 0u, RandomStream::Ransac, first, n, w[0], w[1], w[2], w[3]);
        for (int i = 0; i < n; ++i)
        {
          const auto ref = philoxWords (3u, texlet, static_cast<std::uint32_t> (first + i), 0u, RandomStream::Ransac);
          for (int j = 0; j < 4; ++j)
            ASSERT_EQ (w[j][i], ref.v[j]) << "texlet " << texlet << " counter " << first + i;
        }
      }
}

TEST (SimdPaths, NormalBlocksAreTheScalarBoxMullerBitForBit)
{
  if (!processorRunsThisBuild ())
    GTEST_SKIP () << "this processor does not run x86-64-v3 code";
  std::uint32_t words[4 * 40];
  double g[4 * 40];
  float gf[4 * 40];
  long compared = 0;
  for (std::uint32_t texlet = 0; texlet < 2000; ++texlet)
  {
    const int n = 1 + static_cast<int> (texlet % 40);
    normalBlocks (11u, texlet, texlet % 7, 2, n, words, g);
    normalBlocks (11u, texlet, texlet % 7, 2, n, words, gf);
    for (int b = 0; b < n; ++b)
    {
      const auto w = philoxWords (11u, texlet, texlet % 7, static_cast<std::uint32_t> (2 + b), RandomStream::MonteCarlo);
      float ref[4];
      boxMullerFloat (w.v[0], w.v[1], ref[0], ref[1]);
      boxMullerFloat (w.v[2], w.v[3], ref[2], ref[3]);
      for (int i = 0; i < 4; ++i)
      {
        ASSERT_EQ (g[4 * b + i], static_cast<double> (ref[i])) << "texlet " << texlet << " block " << b;
        ASSERT_EQ (gf[4 * b + i], ref[i]) << "texlet " << texlet << " block " << b;
        ++compared;
      }
    }
  }
  EXPECT_GT (compared, 100000);
}

TEST (SimdPaths, NormalSamplesAreTheScalarBoxMullerBitForBit)
{
  // The PCA Monte Carlo's batched draws (across samples) against the per-sample ones the GPU
  // makes (kernels/pca_sampler.h draws each sample's blocks this way).
  if (!processorRunsThisBuild ())
    GTEST_SKIP () << "this processor does not run x86-64-v3 code";
  std::uint32_t words[4 * 40];
  double g[4][40];
  float gf[4][40];
  long compared = 0;
  for (std::uint32_t texlet = 0; texlet < 2000; ++texlet)
  {
    const int n = 1 + static_cast<int> (texlet % 40);
    const std::uint32_t block = texlet % 4;
    normalSamples (11u, texlet, block, 5, n, words, g[0], g[1], g[2], g[3]);
    normalSamples (11u, texlet, block, 5, n, words, gf[0], gf[1], gf[2], gf[3]);
    for (int i = 0; i < n; ++i)
    {
      const auto w = philoxWords (11u, texlet, static_cast<std::uint32_t> (5 + i), block, RandomStream::MonteCarlo);
      float ref[4];
      boxMullerFloat (w.v[0], w.v[1], ref[0], ref[1]);
      boxMullerFloat (w.v[2], w.v[3], ref[2], ref[3]);
      for (int j = 0; j < 4; ++j)
      {
        ASSERT_EQ (g[j][i], static_cast<double> (ref[j])) << "texlet " << texlet << " sample " << 5 + i;
        ASSERT_EQ (gf[j][i], ref[j]) << "texlet " << texlet << " sample " << 5 + i;
        ++compared;
      }
    }
  }
  EXPECT_GT (compared, 100000);
}

TEST (SimdPaths, BoxMullerOfExtremeWordsIsFiniteAndExact)
{
  if (!processorRunsThisBuild ())
    GTEST_SKIP () << "this processor does not run x86-64-v3 code";
  // Words at the ends of the range (u1 = 0 and 2^32 - 1: the largest and smallest radius).
  const std::uint32_t special[8] = {0u, 1u, 0x7fffffffu, 0x80000000u, 0xffffffffu, 0xfffffffeu, 0x00010000u, 0xffff0000u};
  for (std::uint32_t a : special)
    for (std::uint32_t b : special)
    {
      float x, y;
      boxMullerFloat (a, b, x, y);
      EXPECT_TRUE (std::isfinite (x) && std::isfinite (y));
#if defined(PCL_TEXLET_AVX2_KERNELS)
      __m256 vx, vy;
      boxMullerFloat8 (_mm256_set1_epi32 (static_cast<int> (a)), _mm256_set1_epi32 (static_cast<int> (b)), vx, vy);
      float lx[8], ly[8];
      _mm256_storeu_ps (lx, vx);
      _mm256_storeu_ps (ly, vy);
      for (int i = 0; i < 8; ++i)
      {
        EXPECT_EQ (lx[i], x) << a << " " << b;
        EXPECT_EQ (ly[i], y) << a << " " << b;
      }
#endif
    }
}

TEST (SimdPaths, InlierCountAndMaskAreThePointPlaneTest)
{
  if (!processorRunsThisBuild ())
    GTEST_SKIP () << "this processor does not run x86-64-v3 code";
  std::mt19937 rng (17);
  std::normal_distribution<double> noise (0.0, 2e-3);
  std::uniform_real_distribution<double> spread (-0.02, 0.02);
  for (int trial = 0; trial < 500; ++trial)
  {
    const int n = 1 + trial % 120;
    std::vector<double> x (n), y (n), z (n);
    for (int i = 0; i < n; ++i)
    {
      x[i] = spread (rng);
      y[i] = spread (rng);
      z[i] = 1.0 + 0.3 * x[i] + noise (rng);
    }
    Plane<double> plane;
    plane.n = (1.0 / std::sqrt (1.09)) * make3 (-0.3, 0.0, 1.0);
    plane.d = -plane.n.z;
    // Thresholds that put points on both sides, and exactly on one point's distance.
    for (double threshold : {1e-3, 3e-3, pointPlaneDistance (plane, make3 (x[0], y[0], z[0]))})
    {
      int expected = 0;
      for (int i = 0; i < n; ++i)
        expected += pointPlaneDistance (plane, make3 (x[i], y[i], z[i])) <= threshold ? 1 : 0;
      EXPECT_EQ (countInliers (plane, x.data (), y.data (), z.data (), 0, n, threshold), expected) << "trial " << trial;
      std::vector<unsigned char> mask (n, 7);
      markInliers (plane, x.data (), y.data (), z.data (), n, threshold, mask.data ());
      for (int i = 0; i < n; ++i)
        ASSERT_EQ (mask[i], pointPlaneDistance (plane, make3 (x[i], y[i], z[i])) <= threshold ? 1 : 0) << "point " << i;
      const int mid = n / 3;
      EXPECT_EQ (countInliers (plane, x.data (), y.data (), z.data (), 0, mid, threshold) +
                     countInliers (plane, x.data (), y.data (), z.data (), mid, n, threshold),
                 expected);
    }
  }
}
