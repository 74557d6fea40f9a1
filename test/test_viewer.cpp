/*
 * pcl_texlet_viewer --screenshot under Xvfb: the image shows the scene and the texlets (their
 * exact mean colours), and bad input exits 2 with one line and no image.
 */
#include "support/app_run.h"
#include "support/recording_folder.h"
#include "support/temp_dir.h"

#include <pcl_texlet/io/png_image.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/io/pcd_io.h>

#include <gtest/gtest.h>


#include <filesystem>
#include <set>

namespace fs = std::filesystem;

namespace
{

const std::string kFrame = std::string (DATA_DIR) + "/kinect/grabber_sequence/pcd/frame_20121214T142255.814212.pcd";

struct Image
{
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;

  /** Pixels away from the two text overlays (status at the top, PCL's FPS counter at the bottom). */
  template <typename F> void
  forEachScenePixel (F &&f) const
  {
    for (int v = 40; v < height - 30; ++v)
      for (int u = 0; u < width; ++u)
      {
        const std::uint8_t *p = &rgb[3 * (static_cast<std::size_t> (v) * width + u)];
        f (p[0], p[1], p[2]);
      }
  }
};

class Viewer : public pcl_texlet_test::TempDirTest
{
protected:
  void
  SetUp () override
  {
    if (std::string (XVFB_RUN).empty ())
      GTEST_SKIP () << "xvfb-run is not installed: no X server for the viewer";
  }

  /** Runs the viewer under xvfb-run; its stdout stays in the test folder's "stdout". */
  int
  run (const std::string &args, std::string *err = nullptr)
  {
    const pcl_texlet_test::AppResult r =
        pcl_texlet_test::runCommand (std::string (XVFB_RUN) + " -a -s '-screen 0 1280x1024x24' " + VIEWER_APP + " " + args, dir_);
    if (err)
      *err = r.err;
    return r.code;
  }

  Image
  screenshot (const std::string &args)
  {
    const fs::path png = dir_ / "shot.png";
    fs::remove (png);
    std::string err;
    const int rc = run (args + " --size 640 --screenshot " + png.string (), &err);
    EXPECT_EQ (rc, 0) << err;
    Image img;
    if (rc == 0)
      img.rgb = pcl::texlet::readRgbPng (png.string (), img.width, img.height);
    return img;
  }
};

double
litFraction (const Image &img)
{
  std::size_t lit = 0, all = 0;
  img.forEachScenePixel ([&] (int r, int g, int b) {
    lit += (r + g + b > 30) ? 1 : 0;
    ++all;
  });
  return all ? static_cast<double> (lit) / all : 0.0;
}

} // namespace

TEST_F (Viewer, ScreenshotShowsTheSceneAndTheTexlets)
{
  const Image cloud = screenshot (kFrame + " --layers cloud -u none");
  ASSERT_EQ (cloud.width, 640);
  ASSERT_EQ (cloud.height, 480);
  EXPECT_GT (litFraction (cloud), 0.5) << "the real frame fills most of the sensor's view";

  // Texlets alone, from a texlet file made by the library: their exact colours must show
  // (the discs are drawn unlit).
  pcl::PointCloud<pcl::PointXYZRGBA>::Ptr frame (new pcl::PointCloud<pcl::PointXYZRGBA>);
  ASSERT_EQ (pcl::io::loadPCDFile (kFrame, *frame), 0);
  pcl::TexletEstimation<pcl::PointXYZRGBA> est;
  est.setInputCloud (frame);
  est.setUncertaintyMethod (pcl::texlet::UncertaintyMethod::None);
  pcl::PointCloud<pcl::Texlet> texlets;
  est.compute (texlets);
  const fs::path file = dir_ / "texlets.pcd";
  ASSERT_EQ (pcl::io::savePCDFileBinary (file.string (), texlets), 0);
  std::set<std::uint32_t> colours;
  for (const auto &t : texlets)
    if (std::isfinite (t.x))
      colours.insert ((std::uint32_t (t.r) << 16) | (std::uint32_t (t.g) << 8) | t.b);

  const Image discs = screenshot (file.string () + " --layers texlets");
  std::size_t lit = 0, exact = 0;
  discs.forEachScenePixel ([&] (int r, int g, int b) {
    if (r + g + b == 0)
      return;
    ++lit;
    exact += colours.count ((std::uint32_t (r) << 16) | (std::uint32_t (g) << 8) | std::uint32_t (b));
  });
  EXPECT_GT (litFraction (discs), 0.3);
  EXPECT_GT (static_cast<double> (exact) / lit, 0.8) << exact << " of " << lit << " lit pixels have a texlet's colour";

  // Both layers together differ from the cloud alone.
  const Image both = screenshot (kFrame + " --layers cloud,texlets,normals,sigma_p,sigma_n -u analytic");
  std::size_t differ = 0;
  for (std::size_t i = 0; i < both.rgb.size () && i < cloud.rgb.size (); ++i)
    differ += both.rgb[i] != cloud.rgb[i] ? 1 : 0;
  EXPECT_GT (differ, both.rgb.size () / 10);
}

TEST_F (Viewer, RecordingFolderAndPcdFolder)
{
  // A recording folder of a tilted wall (grey: no rgb frames).
  const fs::path rec = pcl_texlet_test::writeRecordingFolder (dir_ / "rec", pcl_texlet_test::centredCamera (160, 120, 130), 1,
                                                              [] (int u, int v, int) { return 900 + 2 * u + v; });
  EXPECT_GT (litFraction (screenshot (rec.string () + " --layers texlets --spacing 4")), 0.3);
  EXPECT_GT (litFraction (screenshot (fs::path (kFrame).parent_path ().string () + " --layers cloud -u none")), 0.5);
}

TEST_F (Viewer, GrabberTiffFolder)
{
  // The bundled sequence's TIFF depth frames + intrinsics XML, back-projected by the viewer.
  const std::string folder = fs::path (kFrame).parent_path ().parent_path ().string (); // holds tiff/ and pcd/
  EXPECT_GT (litFraction (screenshot (folder + " --layers cloud,texlets -u none")), 0.5);
  const std::string out = pcl_texlet_test::slurp (dir_ / "stdout");
  // Frames of the TIFF reader are named by their time stamp, without the PCD folder's ".pcd".
  EXPECT_NE (out.find ("frame_20121214T142255.814212  |"), std::string::npos) << out;
}

TEST_F (Viewer, GpuBackendRunsOrSaysWhyNot)
{
  // With a CUDA device (and a CUDA build) the texlets come from the GPU backend; without one,
  // --gpu is refused on one line naming the reason, and no image is written.
  const fs::path png = dir_ / "shot.png";
  std::string err;
  const int rc = run (kFrame + " -u analytic --gpu --size 640 --screenshot " + png.string (), &err);
  const std::string out = pcl_texlet_test::slurp (dir_ / "stdout");
  if (rc == 2)
  {
    EXPECT_EQ (std::count (err.begin (), err.end (), '\n'), 1) << err;
    EXPECT_TRUE (err.find ("--gpu: no CUDA device found") != std::string::npos ||
                 err.find ("--gpu: this build has no CUDA backend") != std::string::npos)
        << err;
    EXPECT_FALSE (fs::exists (png));
  }
  else
  {
    ASSERT_EQ (rc, 0) << err;
    EXPECT_NE (out.find ("(GPU, spacing 6"), std::string::npos) << out;
    Image img;
    img.rgb = pcl::texlet::readRgbPng (png.string (), img.width, img.height);
    EXPECT_GT (litFraction (img), 0.3);
  }
}

TEST_F (Viewer, WithoutInputOrSensorItPlaysTheBundledFrames)
{
  // No OpenNI2 device is connected on a test machine: the viewer falls back to data/kinect.
  const Image img = screenshot ("-u none");
  EXPECT_GT (litFraction (img), 0.5);
  const std::string out = pcl_texlet_test::slurp (dir_ / "stdout");
  EXPECT_NE (out.find ("frame_20121214T142255.814212.pcd"), std::string::npos) << out;
}

TEST_F (Viewer, BadInputExitsTwoWithOneLineAndNoImage)
{
  const fs::path png = dir_ / "shot.png";
  pcl::PointCloud<pcl::PointXYZ> flat;
  flat.resize (100, pcl::PointXYZ (0, 0, 1));
  pcl::io::savePCDFileBinary ((dir_ / "flat.pcd").string (), flat);
  for (const auto &[args, needle] : std::vector<std::pair<std::string, std::string>>{
           {(dir_ / "missing.pcd").string (), "missing.pcd"},
           {(dir_ / "flat.pcd").string (), "not an organised"},
           {kFrame + " --layers cloud,sparkles", "sparkles"},
           {kFrame + " --spacing 0", "spacing"},
           {kFrame + " --fit ransac", "ransac"},
           {(dir_ / "nowhere").string () + "/x.oni", "does not exist"}})
  {
    std::string err;
    EXPECT_EQ (run (args + " --screenshot " + png.string (), &err), 2) << args;
    EXPECT_EQ (std::count (err.begin (), err.end (), '\n'), 1) << err;
    EXPECT_NE (err.find (needle), std::string::npos) << err;
    EXPECT_FALSE (fs::exists (png));
  }
  std::string err;
  EXPECT_EQ (run (kFrame + " --screenshot " + (dir_ / "no" / "dir" / "shot.png").string (), &err), 2);
  EXPECT_NE (err.find ("does not exist"), std::string::npos) << err;
}
