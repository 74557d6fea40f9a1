// Uses the installed CUDA backend (pcl_texlet::pcl_texlet_gpu_pcl), from C++ alone: with a CUDA
// device, the GPU's texlets of a synthetic frontal wall must face the camera, as the CPU's do;
// without one, compute () must throw pcl::texlet::gpu::CudaError naming the failed call.
#include <pcl_texlet/camera/camera_estimation.h>
#include <pcl_texlet/gpu/texlet_estimation_pcl.h>

#include <cmath>
#include <iostream>

int
main ()
{
  pcl::PointCloud<pcl::PointXYZ> cloud (64, 48);
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u)
      cloud (u, v) = pcl::PointXYZ ((u - 31.5f) / 60.0f, (v - 23.5f) / 60.0f, 1.0f);
  pcl::texlet::gpu::TexletEstimation est;
  est.setCamera (pcl::texlet::gpu::toDeviceCamera (pcl::texlet::estimatePinholeModel (cloud)));
  pcl::PointCloud<pcl::Texlet> texlets;
  if (pcl::texlet::gpu::cudaDeviceCount () == 0)
  {
    try
    {
      est.compute (cloud, texlets);
    }
    catch (const pcl::texlet::gpu::CudaError &e)
    {
      std::cout << "consumer_gpu: no CUDA device; compute () threw: " << e.what () << std::endl;
      return 0;
    }
    std::cout << "consumer_gpu: no CUDA device, yet compute () returned " << texlets.size () << " texlets" << std::endl;
    return 1;
  }
  est.compute (cloud, texlets);
  int good = 0;
  for (const auto &t : texlets)
    good += (std::isfinite (t.normal_z) && t.normal_z < -0.999f) ? 1 : 0;
  std::cout << "consumer_gpu: " << good << " of " << texlets.size () << " texlets face the camera" << std::endl;
  return (texlets.size () > 50 && good == static_cast<int> (texlets.size ())) ? 0 : 1;
}
