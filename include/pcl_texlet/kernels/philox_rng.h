/*
 * pcl_texlet kernels: counter-based random numbers (Random123 Philox4x32-10).
 *
 * Every draw is a pure function of (seed, texlet, counter, block, stream), so results do not
 * depend on thread count, scheduling or device: the CPU and the GPU draw the same numbers.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <Random123/boxmuller.hpp>
#include <Random123/philox.h>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Independent random streams, told apart by the last counter word. */
enum class RandomStream : std::uint32_t
{
  Ransac = 0x52414e53u,        // "RANS"
  MonteCarlo = 0x4d434d43u,    // "MCMC"
  SensorNoise = 0x534e4f49u,   // "SNOI": the simulator's per-pixel disparity noise
  SensorDropout = 0x53445250u, // "SDRP": the simulator's holes (interference)
  LateralJitter = 0x4c4a4954u, // "LJIT": the simulator's edge jitter
  Stripes = 0x53545250u,       // "STRP": the simulator's vertical stripe layouts
  Distortion = 0x44495354u     // "DIST": the simulator's static distortion map
};

/** \brief Four independent 32-bit words for (seed, texlet, counter, block, stream). */
PCL_TEXLET_HD r123::Philox4x32::ctr_type
philoxWords (std::uint32_t seed, std::uint32_t texlet, std::uint32_t counter, std::uint32_t block,
             RandomStream stream)
{
  r123::Philox4x32 rng;
  const r123::Philox4x32::ctr_type ctr = {{texlet, counter, block, static_cast<std::uint32_t> (stream)}};
  const r123::Philox4x32::key_type key = {{seed, 0x7e41e7u}};
  return rng (ctr, key);
}

/** \brief Maps a uniform 32-bit word to [0, n) by multiply-shift (Lemire), no division. */
PCL_TEXLET_HD std::uint32_t
boundedIndex (std::uint32_t word, std::uint32_t n)
{
  return static_cast<std::uint32_t> ((static_cast<std::uint64_t> (word) * n) >> 32);
}

/** \brief Three distinct indices in [0, n), n >= 3, from three random words. */
PCL_TEXLET_HD void
distinctTriple (const r123::Philox4x32::ctr_type &w, int n, int &a, int &b, int &c)
{
  a = static_cast<int> (boundedIndex (w.v[0], n));
  b = static_cast<int> (boundedIndex (w.v[1], n - 1));
  if (b >= a)
    ++b;
  const int lo = a < b ? a : b, hi = a < b ? b : a;
  c = static_cast<int> (boundedIndex (w.v[2], n - 2));
  if (c >= lo)
    ++c;
  if (c >= hi)
    ++c;
}

/** \brief A uniform draw in [0, 1) from a 32-bit word (its top 24 bits, exact in float). */
PCL_TEXLET_HD float
uniformFloat (std::uint32_t word)
{
  return static_cast<float> (word >> 8) * (1.0f / 16777216.0f);
}

/** \brief Four standard normal draws (Box-Muller on Philox words). */
PCL_TEXLET_HD void
normalQuad (std::uint32_t seed, std::uint32_t texlet, std::uint32_t sample, std::uint32_t block, float out[4])
{
  const r123::Philox4x32::ctr_type w = philoxWords (seed, texlet, sample, block, RandomStream::MonteCarlo);
  const r123::float2 a = r123::boxmuller (w.v[0], w.v[1]);
  const r123::float2 b = r123::boxmuller (w.v[2], w.v[3]);
  out[0] = a.x;
  out[1] = a.y;
  out[2] = b.x;
  out[3] = b.y;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
