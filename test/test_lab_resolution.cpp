/*
 * The model lab against the recordings' own resolution, whole millimetres: where the noise is
 * below a millimetre the recorded SD and mean swing with the sub-millimetre phase of the depth,
 * and the lab predicts both from the rounded Gaussian's moments (not a flat 1/12 mm^2). Ground
 * truth in closed form: a tilted wall, Gaussian noise of a known SD, rounded by this test.
 */
#include "support/closed_form_wall.h"

#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/lab/recording_measurement.h>
#include <pcl_texlet/noise/noise_model.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace pcl::texlet;

namespace
{

const int kWidth = 160, kHeight = 120, kFrames = 40;

/** The wall's depth (mm) at pixel (u, v) before noise: a plane at 620 to 660 mm. */
double
trueDepthMm (const CameraInfo &camera, int u, int v)
{
  // A plane is affine in inverse depth over the normalised image coordinates.
  const double x = (u - camera.cx ()) / camera.fx (), y = (v - camera.cy ()) / camera.fy ();
  return 1.0 / (1.0 / 640.0 + 4.0e-5 * x + 2.5e-5 * y);
}

} // namespace

TEST (ModelLabResolution, PredictsTheWholeMillimetreStaircaseWhereTheNoiseIsBelowAMillimetre)
{
  const double sigma = 0.15;
  const CameraInfo cam = pcl_texlet_test::closedFormCamera (kWidth, kHeight, 79.3, 60.4);
  const std::vector<DepthFrame> frames = pcl_texlet_test::closedFormFrames (
      kWidth, kHeight, kFrames, [&] (int u, int v) { return trueDepthMm (cam, u, v); }, sigma, 20261202);
  // What a flat 1/12 mm^2 (no offset) predicts gets wrong, from the truth: per pixel, the
  // measured SD against sqrt (sigma^2 + 1/12), the measured mean against the true depth.
  double flat_sd2 = 0, flat_bias2 = 0;
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u)
    {
      double s1 = 0, s2 = 0;
      for (const DepthFrame &f : frames)
      {
        const double z = f.depth_mm[static_cast<std::size_t> (v) * kWidth + u];
        s1 += z;
        s2 += z * z;
      }
      const double mean = s1 / kFrames, sd = std::sqrt (std::max (0.0, (s2 - s1 * mean) / (kFrames - 1)));
      flat_sd2 += std::pow (sd - std::sqrt (sigma * sigma + 1.0 / 12.0), 2);
      flat_bias2 += std::pow (mean - trueDepthMm (cam, u, v), 2);
    }
  const double n = double (kWidth) * kHeight;
  const double flat_sd = std::sqrt (flat_sd2 / n), flat_bias = std::sqrt (flat_bias2 / n);

  lab::ModelLab lab{lab::LabSettings ()};
  lab.addRecording (lab::measureFrames (frames, cam, "wall", "scene: plane\n"));
  const lab::LabMetrics m = lab.evaluate (pcl_texlet_test::constantSdModel (sigma));
  std::cout << "flat 1/12: sd error " << flat_sd << " mm, bias error " << flat_bias << " mm; lab: sd_rmse "
            << m.sd_rmse_mm << " mm, bias_rmse " << m.bias_rmse_mm << " mm\n";
  // The staircase is there to be predicted: the flat prediction is off by a tenth of a mm.
  ASSERT_GT (flat_sd, 0.08);
  ASSERT_GT (flat_bias, 0.08);
  EXPECT_LT (m.sd_rmse_mm, 0.5 * flat_sd);
  EXPECT_LT (m.bias_rmse_mm, 0.5 * flat_bias);
}
