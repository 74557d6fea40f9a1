/*
 * What the lab measures of a recording beyond its depth: the colour frames' grey level, in the
 * unit the noise terms read it (PixelContext::intensity, 0 to 1), against Rec. 601 luma computed
 * by hand.
 */
#include <pcl_texlet/lab/recording_measurement.h>
#include <pcl_texlet/noise/pixel_context.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

using namespace pcl::texlet;

TEST (RecordingMeasurement, GreyLevelIsTheColourFramesMeanLumaFromZeroToOne)
{
  const int W = 32, H = 24;
  CameraInfo cam;
  cam.width = W;
  cam.height = H;
  const double K[9] = {30, 0, 15.5, 0, 30, 11.5, 0, 0, 1};
  std::copy (K, K + 9, cam.K);
  // Two frames of a wall at 1 m; the left half black then white, the right half two colours.
  const std::uint8_t colours[2][2][3] = {{{0, 0, 0}, {200, 100, 50}}, {{255, 255, 255}, {10, 240, 90}}};
  std::vector<DepthFrame> frames (2);
  for (int t = 0; t < 2; ++t)
  {
    DepthFrame &f = frames[t];
    f.name = std::to_string (t);
    f.width = W;
    f.height = H;
    f.depth_mm.assign (static_cast<std::size_t> (W) * H, static_cast<std::uint16_t> (1000 + t));
    for (int v = 0; v < H; ++v)
      for (int u = 0; u < W; ++u)
        for (int c = 0; c < 3; ++c)
          f.rgb.push_back (colours[t][u < W / 2 ? 0 : 1][c]);
  }
  const lab::RecordingMeasurement::Ptr m = lab::measureFrames (frames, cam, "grey wall", "scene: plane\n");
  ASSERT_EQ (m->intensity.size (), static_cast<std::size_t> (W) * H);
  const double left = 0.5, right = 0.5 * ((0.299 * 200 + 0.587 * 100 + 0.114 * 50) + (0.299 * 10 + 0.587 * 240 + 0.114 * 90)) / 255.0;
  EXPECT_NEAR (m->intensity[0], left, 1e-6);
  EXPECT_NEAR (m->intensity[W - 1], right, 1e-6);
  EXPECT_NEAR (m->intensity[static_cast<std::size_t> (H - 1) * W + W / 2], right, 1e-6);
  EXPECT_NEAR (greyLevel (128, 128, 128), 128.0 / 255.0, 1e-12);
}
