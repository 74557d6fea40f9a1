#include "texlet_backend.h"

#include <pcl_texlet/features/texlet_estimation.h>

#ifdef PCL_TEXLET_VIEWER_WITH_GPU
#include <pcl_texlet/gpu/texlet_estimation_pcl.h>
#endif

#include <stdexcept>

namespace pcl_texlet_viewer
{

bool
gpuAvailable (std::string &why)
{
#ifdef PCL_TEXLET_VIEWER_WITH_GPU
  if (pcl::texlet::gpu::cudaDeviceCount () > 0)
    return true;
  why = "no CUDA device found";
#else
  why = "this build has no CUDA backend (nvcc was not found when it was configured)";
#endif
  return false;
}

void
computeTexlets (const Cloud::ConstPtr &cloud, const pcl::texlet::CameraModel::ConstPtr &camera,
                const pcl::texlet::TexletParameters &params, bool gpu, Texlets &out)
{
  if (gpu)
  {
#ifdef PCL_TEXLET_VIEWER_WITH_GPU
    pcl::texlet::gpu::TexletEstimation est;
    est.setParameters (params);
    if (camera)
      est.setCamera (pcl::texlet::gpu::toDeviceCamera (*camera));
    est.compute (*cloud, out);
    return;
#else
    throw std::logic_error ("computeTexlets: GPU asked for in a build without the CUDA backend");
#endif
  }
  pcl::TexletEstimation<pcl::PointXYZRGBA> est;
  est.setParameters (params);
  est.setInputCloud (cloud);
  est.setCameraModel (camera);
  est.compute (out);
}

} // namespace pcl_texlet_viewer
