// Uses the installed pcl_texlet: texlets of a synthetic frontal wall must face the camera.
#include <pcl_texlet/features/texlet_estimation.h>

#include <cmath>
#include <iostream>

int
main ()
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud (new pcl::PointCloud<pcl::PointXYZ> (64, 48));
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u)
      (*cloud) (u, v) = pcl::PointXYZ ((u - 31.5f) / 60.0f, (v - 23.5f) / 60.0f, 1.0f);
  pcl::TexletEstimation<pcl::PointXYZ> est;
  est.setInputCloud (cloud);
  est.setUncertaintyMethod (pcl::texlet::UncertaintyMethod::Analytic);
  pcl::PointCloud<pcl::Texlet> texlets;
  est.compute (texlets);
  int good = 0;
  for (const auto &t : texlets)
    good += (std::isfinite (t.normal_z) && t.normal_z < -0.999f) ? 1 : 0;
  std::cout << "consumer: " << good << " of " << texlets.size () << " texlets face the camera" << std::endl;
  return (texlets.size () > 50 && good == static_cast<int> (texlets.size ())) ? 0 : 1;
}
