/*
 * pcl_texlet kernels: one depth pixel of one simulated frame.
 *
 * The scene is static, so everything that depends only on geometry (true disparity, static
 * offsets, noise SD, hole probability) is computed once per sensor into per-pixel maps; a frame
 * then costs a few Philox draws per pixel. Draws are keyed by (seed, pixel, frame, sensor), so a
 * frame is the same whichever thread, or device, computes it.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/philox_rng.h>
#include <pcl_texlet/kernels/structured_light.h>

#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Static per-pixel maps of one sensor (row-major, width * height each). */
struct SensorPixelMaps
{
  int width = 0;
  int height = 0;
  const double *disparity_px = nullptr; ///< f b / z plus static offsets; 0 where no reading is possible
  const float *sigma_px = nullptr;      ///< disparity noise SD, pixels
  const float *dropout = nullptr;       ///< probability of a hole per frame, or null for none
  const float *depth_m = nullptr;       ///< true depth for the edge test, 0 where no surface
};

/** \brief What changes from frame to frame, and the sensor's constants. */
struct SensorFrameSettings
{
  std::uint32_t seed = 0;
  std::uint32_t sensor = 0;
  std::uint32_t frame = 0;
  double fb = 0.0;                          ///< focal length (px) times baseline (m)
  double min_depth_m = 0.0;                 ///< shorter readings are dropped
  double max_depth_m = 0.0;                 ///< longer readings are dropped (<= 65.535)
  double frame_offset_px = 0.0;             ///< disparity offset of the whole frame (drift)
  const float *column_offset_px = nullptr;  ///< disparity offset per column (stripes), or null
  double quantisation_step_px = 0.0;        ///< disparity step; 0 = not quantised
  double lateral_sigma_px = 0.0;            ///< SD of the edge jitter; 0 = none
  double lateral_min_jump_m = 0.0;          ///< depth difference that makes an edge
  int dropout_blob_px = 1;                  ///< side of the blocks in which holes are decided
};

/** \brief The pixel whose surface (u, v) reports in this frame: itself, or with lateral noise
  * the pixel its jittered correlation window landed on when that lies across a depth edge.
  */
PCL_TEXLET_HD int
reportingPixel (const SensorPixelMaps &m, const SensorFrameSettings &s, int u, int v)
{
  const int own = v * m.width + u;
  if (!(s.lateral_sigma_px > 0))
    return own;
  const r123::Philox4x32::ctr_type w =
      philoxWords (s.seed, static_cast<std::uint32_t> (own), s.frame, s.sensor, RandomStream::LateralJitter);
  const r123::float2 g = r123::boxmuller (w.v[0], w.v[1]);
  int nu = u + static_cast<int> (std::floor (s.lateral_sigma_px * g.x + 0.5));
  int nv = v + static_cast<int> (std::floor (s.lateral_sigma_px * g.y + 0.5));
  nu = nu < 0 ? 0 : (nu >= m.width ? m.width - 1 : nu);
  nv = nv < 0 ? 0 : (nv >= m.height ? m.height - 1 : nv);
  const int other = nv * m.width + nu;
  if (other == own)
    return own;
  const double z_own = m.depth_m[own], z_other = m.depth_m[other];
  const bool across = (z_own > 0) != (z_other > 0) || std::fabs (z_own - z_other) > s.lateral_min_jump_m;
  return across ? other : own;
}

/** \brief Depth in millimetres that the sensor reports at (u, v) in this frame, 0 = none. */
PCL_TEXLET_HD std::uint16_t
simulateDepthPixel (const SensorPixelMaps &m, const SensorFrameSettings &s, int u, int v)
{
  const int i = reportingPixel (m, s, u, v);
  const double d0 = m.disparity_px[i];
  if (!(d0 > 0))
    return 0;
  if (m.dropout && m.dropout[i] > 0.0f)
  {
    const int blocks_x = (m.width + s.dropout_blob_px - 1) / s.dropout_blob_px;
    const std::uint32_t block = static_cast<std::uint32_t> ((v / s.dropout_blob_px) * blocks_x + u / s.dropout_blob_px);
    const r123::Philox4x32::ctr_type w = philoxWords (s.seed, block, s.frame, s.sensor, RandomStream::SensorDropout);
    if (uniformFloat (w.v[0]) < m.dropout[i])
      return 0;
  }
  const r123::Philox4x32::ctr_type w = philoxWords (s.seed, static_cast<std::uint32_t> (v * m.width + u), s.frame,
                                                    s.sensor, RandomStream::SensorNoise);
  const double gauss = r123::boxmuller (w.v[0], w.v[1]).x;
  double d = d0 + s.frame_offset_px + m.sigma_px[i] * gauss;
  if (s.column_offset_px)
    d += s.column_offset_px[u];
  if (s.quantisation_step_px > 0)
    d = quantiseDisparity (d, s.quantisation_step_px);
  return reportedDepthMm (d, s.fb, s.min_depth_m, s.max_depth_m);
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
