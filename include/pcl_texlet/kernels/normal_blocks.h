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

#if defined(__AVX2__) && !defined(__CUDACC__)
#include <immintrin.h>
#define PCL_TEXLET_AVX2_KERNELS 1 // compiled for x86-64-v3 (src/features/texlet_kernel_x86_64_v3.cpp)
#endif

namespace pcl
{
namespace texlet
{
namespace kernels
{

#if defined(PCL_TEXLET_AVX2_KERNELS)
/** \brief The ten rounds of Philox4x32-10 with key (seed, 0x7e41e7) (that of philoxWords())
  * on four counters at once, one per 64-bit lane: word i of counter j is in the low 32 bits of
  * lane j of ci. _mm256_mul_epu32 multiplies the low 32 bits of each lane into a full 64-bit
  * product, so no word is ever packed or unpacked between rounds (what the auto-vectoriser
  * spends most of its instructions on). The high halves of the lanes may hold garbage: only
  * the multiplies and philoxStore4() read a lane, and both take its low 32 bits.
  */
inline void
philoxRounds4 (std::uint32_t seed, __m256i &c0, __m256i &c1, __m256i &c2, __m256i &c3)
{
  const __m256i vm0 = _mm256_set1_epi64x (0xD2511F53LL), vm1 = _mm256_set1_epi64x (0xCD9E8D57LL);
  std::uint32_t k0 = seed, k1 = 0x7e41e7u;
  for (int round = 0; round < 10; ++round)
  {
    const __m256i p0 = _mm256_mul_epu32 (c0, vm0), p1 = _mm256_mul_epu32 (c2, vm1);
    c0 = _mm256_xor_si256 (_mm256_srli_epi64 (p1, 32), _mm256_xor_si256 (c1, _mm256_set1_epi32 (static_cast<int> (k0))));
    c1 = p1;
    c2 = _mm256_xor_si256 (_mm256_srli_epi64 (p0, 32), _mm256_xor_si256 (c3, _mm256_set1_epi32 (static_cast<int> (k1))));
    c3 = p0;
    k0 += 0x9E3779B9u;
    k1 += 0xBB67AE85u;
  }
}

/** \brief Stores the low words of the four lanes of each of c0..c3 (philoxRounds4()) at
  * w0[0..3] .. w3[0..3].
  */
inline void
philoxStore4 (__m256i c0, __m256i c1, __m256i c2, __m256i c3, std::uint32_t *w0, std::uint32_t *w1,
              std::uint32_t *w2, std::uint32_t *w3)
{
  const __m256i low_words = _mm256_setr_epi32 (0, 2, 4, 6, 0, 2, 4, 6);
  const auto store = [&low_words] (__m256i c, std::uint32_t *w) {
    _mm_storeu_si128 (reinterpret_cast<__m128i *> (w), _mm256_castsi256_si128 (_mm256_permutevar8x32_epi32 (c, low_words)));
  };
  store (c0, w0);
  store (c1, w1);
  store (c2, w2);
  store (c3, w3);
}
#endif

/** \brief Philox4x32-10 words of blocks first .. first+n-1 for (seed, texlet, counter, stream):
  * the words of block first+b are w0[b] .. w3[b], equal to
  * philoxWords (seed, texlet, counter, first + b, stream).
  */
PCL_TEXLET_HD void
philoxBlocks (std::uint32_t seed, std::uint32_t texlet, std::uint32_t counter, RandomStream stream, int first, int n,
              std::uint32_t *w0, std::uint32_t *w1, std::uint32_t *w2, std::uint32_t *w3)
{
  const std::uint64_t m0 = 0xD2511F53u, m1 = 0xCD9E8D57u;
  int b = 0;
#if defined(PCL_TEXLET_AVX2_KERNELS)
  {
    const __m256i v_c0 = _mm256_set1_epi32 (static_cast<int> (texlet));
    const __m256i v_c1 = _mm256_set1_epi32 (static_cast<int> (counter));
    const __m256i v_c3 = _mm256_set1_epi32 (static_cast<int> (stream));
    for (; b + 4 <= n; b += 4)
    {
      __m256i c0 = v_c0, c1 = v_c1, c3 = v_c3;
      __m256i c2 = _mm256_add_epi64 (_mm256_set1_epi64x (static_cast<long long> (static_cast<std::uint32_t> (first + b))),
                                     _mm256_setr_epi64x (0, 1, 2, 3));
      philoxRounds4 (seed, c0, c1, c2, c3);
      philoxStore4 (c0, c1, c2, c3, w0 + b, w1 + b, w2 + b, w3 + b);
    }
  }
#endif
  for (; b < n; ++b)
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

/** \brief Philox4x32-10 words of counters first .. first+n-1 for (seed, texlet, block, stream):
  * the words of counter first+i are w0[i] .. w3[i], equal to
  * philoxWords (seed, texlet, first + i, block, stream). RANSAC draws its hypotheses' triples
  * this way, all iterations at once.
  */
PCL_TEXLET_HD void
philoxCounters (std::uint32_t seed, std::uint32_t texlet, std::uint32_t block, RandomStream stream, int first, int n,
                std::uint32_t *w0, std::uint32_t *w1, std::uint32_t *w2, std::uint32_t *w3)
{
  int i = 0;
#if defined(PCL_TEXLET_AVX2_KERNELS)
  // As in philoxBlocks(): four counters at a time, one per 64-bit lane.
  for (; i + 4 <= n; i += 4)
  {
    __m256i c0 = _mm256_set1_epi32 (static_cast<int> (texlet));
    __m256i c1 = _mm256_add_epi64 (_mm256_set1_epi64x (static_cast<long long> (static_cast<std::uint32_t> (first + i))),
                                   _mm256_setr_epi64x (0, 1, 2, 3));
    __m256i c2 = _mm256_set1_epi32 (static_cast<int> (block));
    __m256i c3 = _mm256_set1_epi32 (static_cast<int> (stream));
    philoxRounds4 (seed, c0, c1, c2, c3);
    philoxStore4 (c0, c1, c2, c3, w0 + i, w1 + i, w2 + i, w3 + i);
  }
#endif
  for (; i < n; ++i)
  {
    const r123::Philox4x32::ctr_type w = philoxWords (seed, texlet, static_cast<std::uint32_t> (first + i), block, stream);
    w0[i] = w.v[0];
    w1[i] = w.v[1];
    w2[i] = w.v[2];
    w3[i] = w.v[3];
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

#if defined(PCL_TEXLET_AVX2_KERNELS)
/** \brief boxMullerFloat() on eight word pairs at once, the same float operations in the same
  * order (no FMA: intrinsics are never contracted), so the same bits.
  */
inline void
boxMullerFloat8 (__m256i u0, __m256i u1, __m256 &x, __m256 &y)
{
  const auto mul = [] (__m256 a, __m256 b) { return _mm256_mul_ps (a, b); };
  const auto add = [] (__m256 a, __m256 b) { return _mm256_add_ps (a, b); };
  const auto sub = [] (__m256 a, __m256 b) { return _mm256_sub_ps (a, b); };
  const auto k = [] (float v) { return _mm256_set1_ps (v); };
  const __m256 angle = add (mul (_mm256_cvtepi32_ps (u0), k (4.6566128730773926e-10f)), k (2.3283064365386963e-10f));
  // float (u1) of an unsigned word, correctly rounded: both 16-bit halves convert exactly and
  // the one addition rounds once.
  const __m256 u1f = add (mul (_mm256_cvtepi32_ps (_mm256_srli_epi32 (u1, 16)), k (65536.0f)),
                          _mm256_cvtepi32_ps (_mm256_and_si256 (u1, _mm256_set1_epi32 (0xffff))));
  const __m256 u = add (mul (u1f, k (2.3283064365386963e-10f)), k (1.1641532182693481e-10f));
  // logPositiveFloat (u)
  const __m256i bits = _mm256_sub_epi32 (_mm256_castps_si256 (u), _mm256_set1_epi32 (0x3f3504f3));
  const __m256 ef = _mm256_cvtepi32_ps (_mm256_srai_epi32 (bits, 23));
  const __m256 m = _mm256_castsi256_ps (_mm256_add_epi32 (_mm256_and_si256 (bits, _mm256_set1_epi32 (0x007fffff)),
                                                          _mm256_set1_epi32 (0x3f3504f3)));
  const __m256 f = sub (m, k (1.0f));
  const __m256 s = _mm256_div_ps (f, add (k (2.0f), f)), s2 = mul (s, s);
  const __m256 poly =
      mul (s2, add (k (0.6666666666f), mul (s2, add (k (0.4000000000f), mul (s2, add (k (0.2857142857f),
                                                                                          mul (s2, k (0.2222222222f))))))));
  const __m256 logm = sub (f, mul (s, sub (f, poly)));
  const __m256 logu = add (mul (ef, k (0.693359375f)), add (logm, mul (ef, k (-2.12194440e-4f))));
  const __m256 r = _mm256_sqrt_ps (mul (k (-2.0f), logu));
  // sinCosPiFloat (angle)
  const __m256 a = mul (k (3.1415926535897932f), angle);
  const __m256 kf = sub (add (mul (a, k (0.63661977236758134f)), k (12582912.0f)), k (12582912.0f));
  const __m256i q = _mm256_and_si256 (_mm256_cvttps_epi32 (kf), _mm256_set1_epi32 (3));
  const __m256 rr = sub (sub (sub (a, mul (kf, k (1.5703125f))), mul (kf, k (4.837512969970703125e-4f))),
                         mul (kf, k (7.54978995489188216e-8f)));
  const __m256 r2 = mul (rr, rr);
  const __m256 sr = add (rr, mul (mul (rr, r2), add (k (-1.6666654611e-1f),
                                                     mul (r2, add (k (8.3321608736e-3f), mul (r2, k (-1.9515295891e-4f)))))));
  const __m256 cr = add (sub (k (1.0f), mul (k (0.5f), r2)),
                         mul (mul (r2, r2), add (k (4.166664568298827e-2f),
                                                 mul (r2, add (k (-1.388731625493765e-3f), mul (r2, k (2.443315711809948e-5f)))))));
  const __m256i one = _mm256_set1_epi32 (1), two = _mm256_set1_epi32 (2);
  const __m256 odd = _mm256_castsi256_ps (_mm256_cmpeq_epi32 (_mm256_and_si256 (q, one), one));
  const __m256 sq = _mm256_blendv_ps (sr, cr, odd), cq = _mm256_blendv_ps (cr, sr, odd);
  const __m256 sign_s = _mm256_castsi256_ps (_mm256_slli_epi32 (_mm256_and_si256 (q, two), 30));
  const __m256 sign_c = _mm256_castsi256_ps (_mm256_slli_epi32 (_mm256_and_si256 (_mm256_add_epi32 (q, one), two), 30));
  x = mul (_mm256_xor_ps (sq, sign_s), r);
  y = mul (_mm256_xor_ps (cq, sign_c), r);
}

/** \brief The normals of Philox blocks b .. b + 7 whose words are w0[] .. w3[]: x0, y0 from
  * (w0, w1) and x1, y1 from (w2, w3), one lane per block.
  */
inline void
boxMullerBlocks8 (const std::uint32_t *w0, const std::uint32_t *w1, const std::uint32_t *w2, const std::uint32_t *w3,
                  int b, __m256 &x0, __m256 &y0, __m256 &x1, __m256 &y1)
{
  const auto load = [b] (const std::uint32_t *w) { return _mm256_loadu_si256 (reinterpret_cast<const __m256i *> (w + b)); };
  boxMullerFloat8 (load (w0), load (w1), x0, y0);
  boxMullerFloat8 (load (w2), load (w3), x1, y1);
}

/** \brief Stores the normals of one Philox block (four floats) at \a g. */
inline void
storeNormalQuad (__m128 v, float *g)
{
  _mm_storeu_ps (g, v);
}

inline void
storeNormalQuad (__m128 v, double *g)
{
  _mm256_storeu_pd (g, _mm256_cvtps_pd (v));
}
#endif

/** \brief Box-Muller normals of \a n Philox blocks whose words are w0[b] .. w3[b]:
  * g[4 b + 0..3] = boxMullerFloat (w0[b], w1[b]), boxMullerFloat (w2[b], w3[b]). The AVX2 path
  * gives the bits of the scalar one.
  */
template <typename G> PCL_TEXLET_HD void
boxMullerWords (const std::uint32_t *w0, const std::uint32_t *w1, const std::uint32_t *w2, const std::uint32_t *w3,
                int n, G *g)
{
  int b = 0;
#if defined(PCL_TEXLET_AVX2_KERNELS)
  for (; b + 8 <= n; b += 8)
  {
    __m256 x0, y0, x1, y1;
    boxMullerBlocks8 (w0, w1, w2, w3, b, x0, y0, x1, y1);
    // Interleave to g[4 b + i]: each 128-bit quarter below is one block's (x0, y0, x1, y1).
    const __m256 lo0 = _mm256_unpacklo_ps (x0, y0), hi0 = _mm256_unpackhi_ps (x0, y0);
    const __m256 lo1 = _mm256_unpacklo_ps (x1, y1), hi1 = _mm256_unpackhi_ps (x1, y1);
    const __m256 q0 = _mm256_shuffle_ps (lo0, lo1, 0x44), q1 = _mm256_shuffle_ps (lo0, lo1, 0xee); // blocks 0|4, 1|5
    const __m256 q2 = _mm256_shuffle_ps (hi0, hi1, 0x44), q3 = _mm256_shuffle_ps (hi0, hi1, 0xee); // blocks 2|6, 3|7
    G *out = g + 4 * b;
    storeNormalQuad (_mm256_castps256_ps128 (q0), out + 0);
    storeNormalQuad (_mm256_castps256_ps128 (q1), out + 4);
    storeNormalQuad (_mm256_castps256_ps128 (q2), out + 8);
    storeNormalQuad (_mm256_castps256_ps128 (q3), out + 12);
    storeNormalQuad (_mm256_extractf128_ps (q0, 1), out + 16);
    storeNormalQuad (_mm256_extractf128_ps (q1, 1), out + 20);
    storeNormalQuad (_mm256_extractf128_ps (q2, 1), out + 24);
    storeNormalQuad (_mm256_extractf128_ps (q3, 1), out + 28);
  }
#endif
  for (; b < n; ++b)
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

/** \brief Normals g[4 b + i] = normalQuad (seed, texlet, sample, first + b)[i] (to float
  * rounding) for blocks first .. first+n-1. \a words is scratch of 4 n words.
  */
template <typename G> PCL_TEXLET_HD void
normalBlocks (std::uint32_t seed, std::uint32_t texlet, std::uint32_t sample, int first, int n, std::uint32_t *words,
              G *g)
{
  std::uint32_t *w0 = words, *w1 = words + n, *w2 = words + 2 * n, *w3 = words + 3 * n;
  philoxBlocks (seed, texlet, sample, RandomStream::MonteCarlo, first, n, w0, w1, w2, w3);
  boxMullerWords (w0, w1, w2, w3, n, g);
}

#if defined(PCL_TEXLET_AVX2_KERNELS)
/** \brief Stores eight normals at \a g. */
inline void
storeNormals8 (__m256 v, float *g)
{
  _mm256_storeu_ps (g, v);
}

inline void
storeNormals8 (__m256 v, double *g)
{
  _mm256_storeu_pd (g, _mm256_cvtps_pd (_mm256_castps256_ps128 (v)));
  _mm256_storeu_pd (g + 4, _mm256_cvtps_pd (_mm256_extractf128_ps (v, 1)));
}
#endif

/** \brief boxMullerWords() with the output split by position in the block (structure of
  * arrays): g0[b], g1[b] = boxMullerFloat (w0[b], w1[b]) and g2[b], g3[b] =
  * boxMullerFloat (w2[b], w3[b]), the same bits.
  */
template <typename G> PCL_TEXLET_HD void
boxMullerWordsSoA (const std::uint32_t *w0, const std::uint32_t *w1, const std::uint32_t *w2, const std::uint32_t *w3,
                   int n, G *g0, G *g1, G *g2, G *g3)
{
  int b = 0;
#if defined(PCL_TEXLET_AVX2_KERNELS)
  for (; b + 8 <= n; b += 8)
  {
    __m256 x0, y0, x1, y1;
    boxMullerBlocks8 (w0, w1, w2, w3, b, x0, y0, x1, y1);
    storeNormals8 (x0, g0 + b);
    storeNormals8 (y0, g1 + b);
    storeNormals8 (x1, g2 + b);
    storeNormals8 (y1, g3 + b);
  }
#endif
  for (; b < n; ++b)
  {
    float x0, y0, x1, y1;
    boxMullerFloat (w0[b], w1[b], x0, y0);
    boxMullerFloat (w2[b], w3[b], x1, y1);
    g0[b] = x0;
    g1[b] = y0;
    g2[b] = x1;
    g3[b] = y1;
  }
}

/** \brief Normals across samples instead of blocks: g0[i] .. g3[i] = normalQuad (seed, texlet,
  * first + i, block)[0..3] (to float rounding; the bits of boxMullerFloat()) for samples
  * first .. first+n-1 of one block, one array per position in the block so that consecutive
  * samples lie side by side. \a words is scratch of 4 n words.
  */
template <typename G> PCL_TEXLET_HD void
normalSamples (std::uint32_t seed, std::uint32_t texlet, std::uint32_t block, int first, int n, std::uint32_t *words,
               G *g0, G *g1, G *g2, G *g3)
{
  std::uint32_t *w0 = words, *w1 = words + n, *w2 = words + 2 * n, *w3 = words + 3 * n;
  philoxCounters (seed, texlet, block, RandomStream::MonteCarlo, first, n, w0, w1, w2, w3);
  boxMullerWordsSoA (w0, w1, w2, w3, n, g0, g1, g2, g3);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
