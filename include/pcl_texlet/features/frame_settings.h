/*
 * pcl_texlet: the texlet stages' settings of a frame (kernels/texlet_stages.h) from the user's
 * TexletParameters, for the CPU path and the GPU backend alike. Needs no PCL.
 */
#pragma once

#include <pcl_texlet/features/texlet_parameters.h>
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/texlet_stages.h>

namespace pcl
{
namespace texlet
{

/** \brief The stages' settings from \a p, with normals facing \a viewpoint and the neighbourhood
  * \a disc (whose offsets the caller keeps); \a min_sigma_m: the noise model's least depth SD.
  */
template <typename S> kernels::FrameSettings<S>
frameSettings (const TexletParameters &p, const float viewpoint[3], const kernels::PixelDisc &disc,
               double min_sigma_m = 0.0)
{
  kernels::FrameSettings<S> fs;
  fs.kernel.ransac_iterations = p.ransac_iterations;
  fs.kernel.fit = p.fit;
  fs.kernel.centre = p.centre;
  fs.kernel.uncertainty = p.uncertainty;
  fs.kernel.samples = p.samples;
  fs.kernel.seed = p.seed;
  fs.kernel.min_support = p.min_support;
  fs.kernel.viewpoint = {S (viewpoint[0]), S (viewpoint[1]), S (viewpoint[2])};
  fs.fixed_threshold = p.ransac_threshold;
  fs.threshold_sigmas = p.threshold_sigmas;
  fs.min_sigma = min_sigma_m;
  fs.kernel.robust_sigmas = p.ransac_threshold == 0.0 ? S (p.robust_sigmas) : S (0);
  fs.disc = disc;
  kernels::hexRingOffsets (p.radius, fs.ring_du, fs.ring_dv);
  fs.need_sigma = p.uncertainty != UncertaintyMethod::None;
  return fs;
}

} // namespace texlet
} // namespace pcl
