/*
 * pcl_texlet kernels: many standard normal draws at once, equal (to float rounding) to
 * normalQuad() of philox_rng.h.
 *
 * Monte Carlo needs four normals per Philox block and dozens of blocks per sample, so the
 * draws are made block-parallel: Philox4x32-10 over structure-of-arrays counters (the
 * compiler turns the 32x32->64 bit products into SIMD multiplies), then the Box-Muller
 * transform with branch-free float approximations of log and sincos (the libm calls of
 * r123::boxmuller cannot be vectorised). The Philox words are bit for bit those of
 * philoxWords(); the normals differ from r123::boxmuller's by at most a few float ulps.
 */
#pragma once

#include <pcl_texlet/kernels/philox_rng.h>

#include <cstring>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Philox4x32-10 words of blocks first .. first+n-1 for (seed, texlet, counter, stream):
  * the words of block first+b are w0[b] .. w3[b], equal to
  * philoxWords (seed, texlet, counter, first + b, stream).
  */
PCL_TEXLET_HD void
philoxBlocks (std::uint32_t seed, std::uint32_t texlet, std::uint32_t counter, RandomStream stream, int first, int n,
              std::uint32_t *w0, std::uint32_t *w1, std::uint32_t *w2, std::uint32_t *w3)
{
  const std::uint64_t m0 = 0xD2511F53u, m1 = 0xCD9E8D57u;
  for (int b = 0; b < n; ++b)
  {
    std::uint32_t c0 = texlet, c1 = counter, c2 = static_cast<std::uint32_t> (first + b),
                  c3 = static_cast<std::uint32_t> (stream);
    std::uint32_t k0 = seed, k1 = 0x7e41e7u; // the key of philoxWords()
    for (int round = 0; round < 10; ++round)
    {
      const std::uint64_t p0 = m0 * c0, p1 = m1 * c2;
      const std::uint32_t hi0 = static_cast<std::uint32_t> (p0 >> 32), lo0 = static_cast<std::uint32_t> (p0);
      const std::uint32_t hi1 = static_cast<std::uint32_t> (p1 >> 32), lo1 = static_cast<std::uint32_t> (p1);
      c0 = hi1 ^ c1 ^ k0;
      c1 = lo1;
      c2 = hi0 ^ c3 ^ k1;
      c3 = lo0;
      k0 += 0x9E3779B9u;
      k1 += 0xBB67AE85u;
    }
    w0[b] = c0;
    w1[b] = c1;
    w2[b] = c2;
    w3[b] = c3;
  }
}

/** \brief Bits of a float as an integer and back, without aliasing. */
PCL_TEXLET_HD std::uint32_t
floatBits (float f)
{
  std::uint32_t u;
  std::memcpy (&u, &f, sizeof u);
  return u;
}

PCL_TEXLET_HD float
bitsFloat (std::uint32_t u)
{
  float f;
  std::memcpy (&f, &u, sizeof f);
  return f;
}

/** \brief Natural logarithm of a positive normal float, branch-free (about 1 ulp). */
PCL_TEXLET_HD float
logPositiveFloat (float x)
{
  // x = 2^e m with m in [sqrt(1/2), sqrt(2)): log x = e ln2 + log m, log m = 2 atanh(s).
  const std::uint32_t bits = floatBits (x) - 0x3f3504f3u; // offset of sqrt(1/2)
  const int e = static_cast<int> (bits) >> 23;
  const float m = bitsFloat ((bits & 0x007fffffu) + 0x3f3504f3u);
  const float f = m - 1.0f;
  const float s = f / (2.0f + f), s2 = s * s;
  // 2 atanh(s) = 2 s + 2 s^3/3 + ... ; |s| <= 0.1716, the series to s^9 is below 1e-9.
  const float poly = s2 * (0.6666666666f + s2 * (0.4000000000f + s2 * (0.2857142857f + s2 * 0.2222222222f)));
  const float logm = f - s * (f - poly);
  const float ef = static_cast<float> (e);
  return ef * 0.693359375f + (logm + ef * -2.12194440e-4f); // ln2 split: hi exact in float
}

/** \brief sin and cos of pi x for |x| <= 1, branch-free (about 1 ulp of the float pi x). */
PCL_TEXLET_HD void
sinCosPiFloat (float x, float &s, float &c)
{
  // r123::boxmuller takes sincosf of the float product pi x: round it the same way.
  const float a = 3.1415926535897932f * x;
  // Quarter turns k = round(a / (pi/2)), r = a - k pi/2 in [-pi/4, pi/4] (Cody-Waite).
  const float kf = (a * 0.63661977236758134f + 12582912.0f) - 12582912.0f; // round to nearest
  const int q = static_cast<int> (kf) & 3;
  const float r = ((a - kf * 1.5703125f) - kf * 4.837512969970703125e-4f) - kf * 7.54978995489188216e-8f;
  const float r2 = r * r;
  const float sr = r + r * r2 * (-1.6666654611e-1f + r2 * (8.3321608736e-3f + r2 * -1.9515295891e-4f));
  const float cr = 1.0f - 0.5f * r2 + r2 * r2 * (4.166664568298827e-2f + r2 * (-1.388731625493765e-3f +
                                                                               r2 * 2.443315711809948e-5f));
  // sin(r + q pi/2), cos(r + q pi/2).
  const float sq = (q & 1) ? cr : sr, cq = (q & 1) ? sr : cr;
  s = (q & 2) ? -sq : sq;
  c = ((q + 1) & 2) ? -cq : cq;
}

/** \brief The Box-Muller pair of r123::boxmuller (u0, u1) with the branch-free approximations. */
PCL_TEXLET_HD void
boxMullerFloat (std::uint32_t u0, std::uint32_t u1, float &x, float &y)
{
  // uneg11<float> and u01<float> of Random123's uniform.hpp.
  const float angle = static_cast<float> (static_cast<std::int32_t> (u0)) * 4.6566128730773926e-10f + 2.3283064365386963e-10f;
  const float u = static_cast<float> (u1) * 2.3283064365386963e-10f + 1.1641532182693481e-10f;
  const float r = std::sqrt (-2.0f * logPositiveFloat (u));
  float s, c;
  sinCosPiFloat (angle, s, c);
  x = s * r;
  y = c * r;
}

/** \brief Normals g[4 b + i] = normalQuad (seed, texlet, sample, first + b)[i] (to float
  * rounding) for blocks first .. first+n-1. \a words is scratch of 4 n words.
  */
template <typename G> PCL_TEXLET_HD void
normalBlocks (std::uint32_t seed, std::uint32_t texlet, std::uint32_t sample, int first, int n, std::uint32_t *words,
              G *g)
{
  std::uint32_t *w0 = words, *w1 = words + n, *w2 = words + 2 * n, *w3 = words + 3 * n;
  philoxBlocks (seed, texlet, sample, RandomStream::MonteCarlo, first, n, w0, w1, w2, w3);
  for (int b = 0; b < n; ++b)
  {
    float x0, y0, x1, y1;
    boxMullerFloat (w0[b], w1[b], x0, y0);
    boxMullerFloat (w2[b], w3[b], x1, y1);
    g[4 * b + 0] = x0;
    g[4 * b + 1] = y0;
    g[4 * b + 2] = x1;
    g[4 * b + 3] = y1;
  }
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
