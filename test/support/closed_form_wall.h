/*
 * pcl_texlet tests: what the model lab's closed-form wall tests share (test_lab_resolution,
 * test_lab_sd_floor): a small pinhole camera, frames of a known depth plus Gaussian noise recorded
 * in whole millimetres, and a model whose SD is one constant.
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>
#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/noise/noise_model.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace pcl_texlet_test
{

/** \brief A \a width x \a height camera with the Kinect's focal length scaled to the width and
  * its principal point at (\a cx, \a cy).
  */
inline pcl::texlet::CameraInfo
closedFormCamera (int width, int height, double cx, double cy)
{
  pcl::texlet::CameraInfo c;
  c.width = width;
  c.height = height;
  const double f = 571.3 * width / 640.0;
  const double K[9] = {f, 0, cx, 0, f, cy, 0, 0, 1};
  std::copy (K, K + 9, c.K);
  return c;
}

/** \brief \a frames frames of \a width x \a height pixels: each sample the depth \a true_depth_mm
  * (u, v) gives plus N(0, \a sigma^2), rounded to whole millimetres; seed \a seed.
  */
template <typename TrueDepth>
std::vector<pcl::texlet::DepthFrame>
closedFormFrames (int width, int height, int frames, const TrueDepth &true_depth_mm, double sigma, unsigned seed)
{
  std::mt19937_64 rng (seed);
  std::normal_distribution<double> gauss (0.0, sigma);
  std::vector<pcl::texlet::DepthFrame> out (frames);
  for (int t = 0; t < frames; ++t)
  {
    pcl::texlet::DepthFrame &f = out[t];
    f.name = std::to_string (t);
    f.width = width;
    f.height = height;
    f.depth_mm.resize (static_cast<std::size_t> (width) * height);
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u)
        f.depth_mm[static_cast<std::size_t> (v) * width + u] =
            static_cast<std::uint16_t> (std::lround (true_depth_mm (u, v) + gauss (rng)));
  }
  return out;
}

/** \brief The paper's model with its polynomial reduced to the constant SD \a sigma_mm and a floor
  * far below it: nothing else.
  */
inline pcl::texlet::NoiseModel
constantSdModel (double sigma_mm)
{
  pcl::texlet::NoiseModel model = pcl::texlet::NoiseModel::paper ();
  model.setMinSigmaMm (0.01);
  const pcl::texlet::NoiseTerm::Ptr poly = model.find ("polynomial");
  std::vector<double> p (poly->parameters ().size (), 0.0);
  p[0] = sigma_mm;
  poly->setParameters (p);
  return model;
}

} // namespace pcl_texlet_test
