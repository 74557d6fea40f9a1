#pragma once

#include "frame_sources.h"

#include <pcl_texlet/camera/camera_model.h>
#include <pcl_texlet/features/texlet_parameters.h>

#include <string>

namespace pcl_texlet_viewer
{

/** \brief Whether texlets can be computed on the GPU here: this build has the CUDA backend and
  * a CUDA device is present. \a why says why not, for the user.
  */
bool
gpuAvailable (std::string &why);

/** \brief Texlets of an organised cloud, on the CPU (pcl::TexletEstimation) or on the GPU
  * (pcl::texlet::gpu::TexletEstimation: the same kernels and Philox draws, so the same texlets).
  * \a camera may be null: a pinhole is then estimated from the cloud, on either backend.
  * \throws pcl::PCLException for bad input; pcl::texlet::gpu::CudaError (std::runtime_error) on the GPU
  */
void
computeTexlets (const Cloud::ConstPtr &cloud, const pcl::texlet::CameraModel::ConstPtr &camera,
                const pcl::texlet::TexletParameters &params, bool gpu, Texlets &out);

} // namespace pcl_texlet_viewer
