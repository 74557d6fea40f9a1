/*
 * pcl_texlet_extract end to end: the bundled real frame, a recording folder, and bad input
 * (exit code 2, one line on stderr, no output file left behind).
 */
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/features/point_types.h>
#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/png_image.h>

#include <pcl/io/pcd_io.h>

#include <gtest/gtest.h>

#include "support/app_test.h"
#include "support/recording_folder.h"
#include "support/temp_dir.h"


#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;

namespace
{

using pcl_texlet_test::slurp;

class ExtractApp : public pcl_texlet_test::AppTest
{
protected:
  ExtractApp () : AppTest (EXTRACT_APP) {}

  using AppTest::expectRejected;

  /** Bad input, and no output file nor temporary beside where it would be. */
  void
  expectRejected (const std::string &args, const std::string &needle, const fs::path &output)
  {
    expectRejected (args, needle);
    EXPECT_FALSE (fs::exists (output)) << output;
    EXPECT_EQ (pcl_texlet_test::temporariesIn (output.parent_path ()), std::vector<std::string> ());
  }

  /** A recording folder of `frames` 64x48 frames of a tilted wall. */
  fs::path
  makeRecording (int frames)
  {
    return pcl_texlet_test::writeRecordingFolder (dir_ / "rec", pcl_texlet_test::centredCamera (64, 48, 60), frames,
                                                  [] (int u, int, int f) { return 1000 + 2 * u + f; });
  }
};

const std::string kRealFrame = std::string (DATA_DIR) + "/kinect/grabber_sequence/pcd/frame_20121214T142255.814212.pcd";

} // namespace

TEST_F (ExtractApp, RealKinectFrame)
{
  const fs::path out = dir_ / "texlets.pcd";
  const Result r = run (kRealFrame + " " + out.string () + " --uncertainty analytic");
  ASSERT_EQ (r.code, 0) << r.err;
  pcl::PointCloud<pcl::Texlet> texlets;
  ASSERT_EQ (pcl::io::loadPCDFile (out.string (), texlets), 0);
  EXPECT_EQ (static_cast<int> (texlets.size ()), pcl::texlet::kernels::makeHexGrid (640, 480, 6).size ());
  std::size_t valid = 0;
  for (const auto &t : texlets)
    if (std::isfinite (t.x))
    {
      ++valid;
      EXPECT_NEAR (std::sqrt (t.normal_x * t.normal_x + t.normal_y * t.normal_y + t.normal_z * t.normal_z), 1.0, 1e-5);
      EXPECT_LT (t.normal_x * t.x + t.normal_y * t.y + t.normal_z * t.z, 0.0f); // faces the camera
      EXPECT_GT (t.cov_p_zz, 0.0f);
    }
  EXPECT_GT (valid, texlets.size () / 2);
  EXPECT_NE (r.out.find ("median normal SD"), std::string::npos) << r.out;
  EXPECT_EQ (pcl_texlet_test::temporariesIn (out.parent_path ()), std::vector<std::string> ());
}

TEST_F (ExtractApp, RecordingFolderWritesOneFilePerFrame)
{
  const fs::path rec = makeRecording (3), out = dir_ / "out";
  const Result r = run (rec.string () + " " + out.string () + " --spacing 8 --uncertainty montecarlo --samples 20");
  ASSERT_EQ (r.code, 0) << r.err;
  for (const char *name : {"000000.pcd", "000001.pcd", "000002.pcd"})
  {
    pcl::PointCloud<pcl::Texlet> texlets;
    ASSERT_EQ (pcl::io::loadPCDFile ((out / name).string (), texlets), 0) << name;
    ASSERT_EQ (static_cast<int> (texlets.size ()), pcl::texlet::kernels::makeHexGrid (64, 48, 8).size ());
    // z = 1 + 0.002 u (metres, u in pixels) with fx 60: the wall's normal is along (0.12, 0, -1).
    const Eigen::Vector3f truth = Eigen::Vector3f (0.12f, 0.0f, -1.0f).normalized ();
    for (const auto &t : texlets)
      if (std::isfinite (t.x))
        EXPECT_GT (Eigen::Vector3f (t.normal_x, t.normal_y, t.normal_z).dot (truth), 0.999f);
  }
  EXPECT_NE (r.err.find ("frame 3/3"), std::string::npos) << r.err; // progress lines
}

TEST_F (ExtractApp, TheModelsBiasComesOffUnlessKept)
{
  // A model with a warm-up drift (0.5 px of disparity at frame 0): by default each depth loses
  // the drift's bias before the fit, so P moves against the readings' texlets (which
  // --keep-model-bias gives) by the bias, millimetres at 1 m; the normals stay.
  const fs::path rec = makeRecording (1);
  const fs::path model = dir_ / "drift.yaml";
  std::ofstream (model) << "min_sigma_mm: 0.1\n"
                           "terms:\n"
                           "  - name: polynomial\n"
                           "    parameters: {p00: 2.344, p10: -1.202e-2, p01: -2.734e-3, p20: 1.818e-5, p11: 6.516e-6, "
                           "p02: 1.233e-6}\n"
                           "  - name: temporal_drift\n"
                           "    parameters: {amplitude_px: 0.5, time_constant_frames: 100, scale: 0}\n";
  const std::string args = " --quiet --uncertainty analytic --spacing 8 --noise-model " + model.string ();
  ASSERT_EQ (run (rec.string () + " " + (dir_ / "removed").string () + args).code, 0);
  const Result r = run (rec.string () + " " + (dir_ / "kept").string () + args + " --keep-model-bias");
  ASSERT_EQ (r.code, 0) << r.err;
  pcl::PointCloud<pcl::Texlet> removed, kept;
  ASSERT_EQ (pcl::io::loadPCDFile ((dir_ / "removed" / "000000.pcd").string (), removed), 0);
  ASSERT_EQ (pcl::io::loadPCDFile ((dir_ / "kept" / "000000.pcd").string (), kept), 0);
  ASSERT_EQ (removed.size (), kept.size ());
  int compared = 0;
  for (std::size_t i = 0; i < kept.size (); ++i)
    if (std::isfinite (kept[i].x) && std::isfinite (removed[i].x))
    {
      ++compared;
      EXPECT_GT (std::fabs (removed[i].z - kept[i].z), 1e-3f) << i; // metres
      EXPECT_GT (removed[i].normal_x * kept[i].normal_x + removed[i].normal_y * kept[i].normal_y +
                     removed[i].normal_z * kept[i].normal_z,
                 0.9999f)
          << i;
    }
  EXPECT_GT (compared, 10);
}

TEST_F (ExtractApp, ExactWindowFormAgreesWithTheTables)
{
  // A model with noise shared over a 9 px window: --exact-window-form forms every texlet's window
  // part by the windows' sums, the default takes discs missing few readings from tables; the texlets
  // are the same but for their covariances, within a few percent (docs/benchmarks.md).
  const fs::path rec = makeRecording (1);
  const fs::path model = dir_ / "window.yaml";
  std::ofstream (model) << "min_sigma_mm: 0.1\n"
                           "terms:\n"
                           "  - name: polynomial\n"
                           "    parameters: {p00: 2.344, p10: -1.202e-2, p01: -2.734e-3, p20: 1.818e-5, p11: 6.516e-6, "
                           "p02: 1.233e-6}\n"
                           "  - name: spatial_correlation\n"
                           "    parameters: {share: 1, window_px: 9}\n";
  const std::string args = " --quiet --uncertainty analytic --spacing 8 --noise-model " + model.string ();
  ASSERT_EQ (run (rec.string () + " " + (dir_ / "tables").string () + args).code, 0);
  const Result r = run (rec.string () + " " + (dir_ / "exact").string () + args + " --exact-window-form");
  ASSERT_EQ (r.code, 0) << r.err;
  pcl::PointCloud<pcl::Texlet> tables, exact;
  ASSERT_EQ (pcl::io::loadPCDFile ((dir_ / "tables" / "000000.pcd").string (), tables), 0);
  ASSERT_EQ (pcl::io::loadPCDFile ((dir_ / "exact" / "000000.pcd").string (), exact), 0);
  ASSERT_EQ (tables.size (), exact.size ());
  int compared = 0;
  double worst = 0;
  for (std::size_t i = 0; i < exact.size (); ++i)
    if (std::isfinite (exact[i].cov_n_11))
    {
      ++compared;
      EXPECT_EQ (tables[i].x, exact[i].x) << i;
      EXPECT_EQ (tables[i].normal_z, exact[i].normal_z) << i;
      const double d = (tables[i].covarianceN () - exact[i].covarianceN ()).norm () / exact[i].covarianceN ().norm ();
      worst = std::max (worst, d);
    }
  std::cout << compared << " texlets, largest relative difference of Sigma_N " << worst << "\n";
  EXPECT_GT (compared, 40);
  EXPECT_LT (worst, 0.05);
  EXPECT_GT (worst, 0.0); // the default did take the tables
}

TEST_F (ExtractApp, GrabberTiffFolderWritesOneFilePerFrame)
{
  const fs::path out = dir_ / "out";
  const std::string sequence = std::string (DATA_DIR) + "/kinect/grabber_sequence";
  const Result r = run (sequence + " " + out.string () + " --uncertainty analytic");
  ASSERT_EQ (r.code, 0) << r.err;
  EXPECT_NE (r.err.find ("frame 3/3"), std::string::npos) << r.err;
  const char *frames[] = {"frame_20121214T142255.814212", "frame_20121214T142256.068683", "frame_20121214T142256.332395"};
  for (const char *frame : frames)
  {
    pcl::PointCloud<pcl::Texlet> texlets;
    ASSERT_EQ (pcl::io::loadPCDFile ((out / (std::string (frame) + ".pcd")).string (), texlets), 0) << frame;
    ASSERT_EQ (static_cast<int> (texlets.size ()), pcl::texlet::kernels::makeHexGrid (640, 480, 6).size ());
    std::size_t valid = 0;
    for (const auto &t : texlets)
      if (std::isfinite (t.x))
      {
        ++valid;
        EXPECT_LT (t.normal_x * t.x + t.normal_y * t.y + t.normal_z * t.z, 0.0f); // faces the camera
      }
    EXPECT_GT (valid, texlets.size () / 2) << frame;
  }

  // The first frame's PCD was made by PCL's grabber from the same depth with the same intrinsics
  // (fx = fy = 525, centre (320, 240), recovered from the cloud): its texlets are the TIFF frame's.
  const fs::path from_pcd = dir_ / "from_pcd.pcd";
  ASSERT_EQ (run (kRealFrame + " " + from_pcd.string () + " --uncertainty analytic").code, 0);
  pcl::PointCloud<pcl::Texlet> a, b;
  ASSERT_EQ (pcl::io::loadPCDFile ((out / (std::string (frames[0]) + ".pcd")).string (), a), 0);
  ASSERT_EQ (pcl::io::loadPCDFile (from_pcd.string (), b), 0);
  ASSERT_EQ (a.size (), b.size ());
  std::size_t both = 0, one = 0, same = 0;
  std::vector<double> centre_mm, normal_deg;
  for (std::size_t i = 0; i < a.size (); ++i)
  {
    if (std::isfinite (a[i].x) != std::isfinite (b[i].x))
      ++one;
    if (!std::isfinite (a[i].x) || !std::isfinite (b[i].x))
      continue;
    ++both;
    const Eigen::Vector3f pa (a[i].x, a[i].y, a[i].z), pb (b[i].x, b[i].y, b[i].z);
    const Eigen::Vector3f na (a[i].normal_x, a[i].normal_y, a[i].normal_z), nb (b[i].normal_x, b[i].normal_y, b[i].normal_z);
    centre_mm.push_back (1e3 * double ((pa - pb).norm ()));
    normal_deg.push_back (180.0 / M_PI * std::acos (std::min (1.0f, na.dot (nb))));
    same += centre_mm.back () < 0.01 && normal_deg.back () < 0.1;
  }
  std::sort (centre_mm.begin (), centre_mm.end ());
  std::sort (normal_deg.begin (), normal_deg.end ());
  const auto at = [] (const std::vector<double> &v, double q) { return v[std::size_t (q * (v.size () - 1))]; };
  std::cout << "TIFF vs PCD texlets: " << both << " valid in both, " << one << " in one only, " << same
            << " the same (centre < 0.01 mm, normal < 0.1 deg); centre diff median " << at (centre_mm, 0.5) << " p99 "
            << at (centre_mm, 0.99) << " max " << centre_mm.back () << " mm; normal diff median " << at (normal_deg, 0.5)
            << " p99 " << at (normal_deg, 0.99) << " max " << normal_deg.back () << " deg" << std::endl;
  // The two clouds differ only in float rounding of x and y, which flips a few RANSAC inlier decisions.
  EXPECT_EQ (one, 0u);
  EXPECT_GT (both, 8000u);
  EXPECT_GE (same, both * 995 / 1000);
  EXPECT_LT (at (centre_mm, 0.5), 0.001);
}

TEST_F (ExtractApp, OniFileWritesOneFilePerFrame)
{
  const fs::path out = dir_ / "out";
  const Result r = run (std::string (DATA_DIR) + "/kinect/grabber_sequence.oni " + out.string () +
                        " --uncertainty none --spacing 12");
  ASSERT_EQ (r.code, 0) << r.err;
  for (const char *name : {"000001.pcd", "000002.pcd", "000003.pcd"})
  {
    pcl::PointCloud<pcl::Texlet> texlets;
    ASSERT_EQ (pcl::io::loadPCDFile ((out / name).string (), texlets), 0) << name;
    EXPECT_EQ (static_cast<int> (texlets.size ()), pcl::texlet::kernels::makeHexGrid (640, 480, 12).size ());
  }
  EXPECT_NE (r.out.find ("frames:                3"), std::string::npos) << r.out;
}

TEST_F (ExtractApp, BadInputExitsTwoWithOneLine)
{
  const fs::path out = dir_ / "out.pcd";
  expectRejected ((dir_ / "missing.pcd").string () + " " + out.string (), "missing.pcd", out);

  std::ofstream (dir_ / "garbage.pcd") << "this is not a point cloud\n";
  expectRejected ((dir_ / "garbage.pcd").string () + " " + out.string (), "garbage.pcd", out);

  // Truncated: the real frame cut in half.
  {
    const std::string data = slurp (kRealFrame);
    std::ofstream (dir_ / "truncated.pcd", std::ios::binary).write (data.data (), data.size () / 2);
  }
  expectRejected ((dir_ / "truncated.pcd").string () + " " + out.string (), "truncated.pcd", out);

  // .oni input: missing, and not a recording (OpenNI2's multi-line message comes out on one line).
  expectRejected ((dir_ / "missing.oni").string () + " " + out.string (), "missing.oni", out);
  std::ofstream (dir_ / "garbage.oni") << "this is not a recording\n";
  expectRejected ((dir_ / "garbage.oni").string () + " " + out.string (), "garbage.oni", out);

  pcl::PointCloud<pcl::PointXYZ> flat;
  flat.resize (500, pcl::PointXYZ (0, 0, 1));
  pcl::io::savePCDFileBinary ((dir_ / "flat.pcd").string (), flat);
  expectRejected ((dir_ / "flat.pcd").string () + " " + out.string (), "not an organised", out);

  pcl::PointCloud<pcl::PointXYZ> invalid (64, 48, pcl::PointXYZ (NAN, NAN, NAN));
  pcl::io::savePCDFileBinary ((dir_ / "invalid.pcd").string (), invalid);
  expectRejected ((dir_ / "invalid.pcd").string () + " " + out.string (), "no valid point", out);

  expectRejected (kRealFrame + " " + out.string () + " --spacing 0", "spacing", out);
  expectRejected (kRealFrame + " " + out.string () + " --radius -3", "radius", out);
  expectRejected (kRealFrame + " " + out.string () + " --iterations 0", "ransac_iterations", out);
  expectRejected (kRealFrame + " " + out.string () + " --samples 1", "samples", out);
  expectRejected (kRealFrame + " " + out.string () + " --threshold -1", "threshold", out);
  expectRejected (kRealFrame + " " + out.string () + " --fit ransac", "ransac", out);
  expectRejected (kRealFrame + " " + out.string () + " --camera 0 525 320 240", "focal", out);
  expectRejected (kRealFrame + " " + out.string () + " --spacing six", "spacing", out);
  // NaN, infinite and absurd numbers.
  expectRejected (kRealFrame + " " + out.string () + " --threshold nan", "threshold", out);
  expectRejected (kRealFrame + " " + out.string () + " --sigmas inf", "threshold_sigmas", out);
  expectRejected (kRealFrame + " " + out.string () + " --camera nan 525 320 240", "focal", out);
  expectRejected (kRealFrame + " " + out.string () + " --camera 525 525 inf 240", "--camera: ", out);
  expectRejected (kRealFrame + " " + out.string () + " --samples 2000000000", "samples", out);
  expectRejected (kRealFrame + " " + out.string () + " --iterations 99999999", "ransac_iterations", out);
  expectRejected (kRealFrame + " " + out.string () + " --threads 100000", "threads", out);
  expectRejected (kRealFrame + " " + (dir_ / "no" / "such" / "dir" / "out.pcd").string (), "does not exist",
                  dir_ / "no");
  expectRejected (kRealFrame, "OUTPUT", out); // missing argument
}

TEST_F (ExtractApp, BadRecordingsExitTwo)
{
  const fs::path rec = makeRecording (3), out = dir_ / "out";
  // A frame whose size differs from camera.yaml, with --bad-frames fail: the bad frame is named
  // and the output folder this run made is gone (no half-written output).
  {
    std::vector<std::uint16_t> depth (32 * 24, 1000);
    pcl::texlet::writeDepthPng ((rec / "depth" / "000001.png").string (), depth.data (), 32, 24);
  }
  expectRejected (rec.string () + " " + out.string () + " --quiet --bad-frames fail", "000001.png", out);
  expectRejected (rec.string () + " " + out.string () + " --bad-frames maybe", "--bad-frames", out);

  std::ofstream (rec / "camera.yaml") << "image_width: [unbalanced\n";
  expectRejected (rec.string () + " " + out.string (), "camera.yaml", out);

  const fs::path empty = dir_ / "empty";
  fs::create_directories (empty);
  expectRejected (empty.string () + " " + out.string (), "empty", out);
}

TEST_F (ExtractApp, CorruptFrameInTheMiddleIsSkippedAndCounted)
{
  const fs::path rec = makeRecording (5), out = dir_ / "out";
  // 000002.png cut short (a truncated write), 000003.png the wrong size.
  const std::string bytes = slurp (rec / "depth" / "000002.png");
  std::ofstream (rec / "depth" / "000002.png", std::ios::binary) << bytes.substr (0, bytes.size () / 2);
  {
    std::vector<std::uint16_t> depth (32 * 24, 1000);
    pcl::texlet::writeDepthPng ((rec / "depth" / "000003.png").string (), depth.data (), 32, 24);
  }
  const Result r = run (rec.string () + " " + out.string () + " --quiet --uncertainty none");
  ASSERT_EQ (r.code, 0) << r.err;
  // One warning per bad frame, naming it; shown even with --quiet.
  EXPECT_EQ (pcl_texlet_test::lineCount (r.err), 2u) << r.err;
  EXPECT_NE (r.err.find ("warning"), std::string::npos) << r.err;
  EXPECT_NE (r.err.find ("000002.png"), std::string::npos) << r.err;
  EXPECT_NE (r.err.find ("000003.png"), std::string::npos) << r.err;
  EXPECT_NE (r.out.find ("frames:                3\n"), std::string::npos) << r.out;
  EXPECT_NE (r.out.find ("skipped frames:        2 "), std::string::npos) << r.out;
  for (const char *name : {"000000", "000001", "000004"})
    EXPECT_TRUE (fs::exists (out / (std::string (name) + ".pcd"))) << name;
  EXPECT_FALSE (fs::exists (out / "000002.pcd"));
  EXPECT_FALSE (fs::exists (out / "000003.pcd"));

  // A folder of PCD files follows the same policy.
  const fs::path pcds = dir_ / "pcds", out2 = dir_ / "out2";
  fs::create_directories (pcds);
  fs::copy_file (kRealFrame, pcds / "a.pcd");
  std::ofstream (pcds / "b.pcd") << "# .PCD v0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 640\n"
                                   "HEIGHT 480\nPOINTS 307200\nDATA binary\n\x01\x02";
  const Result p = run (pcds.string () + " " + out2.string () + " --quiet --uncertainty none");
  ASSERT_EQ (p.code, 0) << p.err;
  EXPECT_NE (p.err.find ("b.pcd"), std::string::npos) << p.err;
  EXPECT_NE (p.out.find ("skipped frames:        1 "), std::string::npos) << p.out;
  EXPECT_TRUE (fs::exists (out2 / "a.pcd"));
  EXPECT_FALSE (fs::exists (out2 / "b.pcd"));

  // Every frame bad: nothing to show for it is an error, and no output folder is left.
  for (const char *name : {"000000", "000001", "000004"})
    std::ofstream (rec / "depth" / (std::string (name) + ".png")) << "not a PNG";
  const Result all = run (rec.string () + " " + (dir_ / "out3").string () + " --quiet");
  EXPECT_EQ (all.code, 2) << all.err;
  EXPECT_EQ (pcl_texlet_test::lineCount (all.err), 6u) << all.err; // 5 warnings, 1 error
  EXPECT_NE (all.err.find ("error: no frame of"), std::string::npos) << all.err;
  EXPECT_FALSE (fs::exists (dir_ / "out3"));
}

TEST_F (ExtractApp, XtionSxgaFramesEndToEnd)
{
  // 1280x1024 (the Xtion's SXGA mode) from the simulator, read back and extracted: a fronto-
  // parallel wall at 1.5 m, so every texlet faces the camera at that depth.
  const fs::path rec = dir_ / "sxga", out = dir_ / "out";
  const Result sim = pcl_texlet_test::runApp (SIM_APP, "--width 1280 --height 1024 --frames 2 --distance 1.5 -q " +
                                                           rec.string (), dir_);
  ASSERT_EQ (sim.code, 0) << sim.err;
  const Result r = run (rec.string () + " " + out.string () + " --quiet --uncertainty analytic --spacing 12");
  ASSERT_EQ (r.code, 0) << r.err;
  EXPECT_NE (r.out.find ("frames:                2\n"), std::string::npos) << r.out;
  pcl::PointCloud<pcl::Texlet> texlets;
  ASSERT_EQ (pcl::io::loadPCDFile ((out / "000001.pcd").string (), texlets), 0);
  EXPECT_EQ (texlets.size (), pcl::texlet::kernels::makeHexGrid (1280, 1024, 12).size ());
  // Per texlet the normal is noisy (a 1.5 mm-pixel disc under millimetres of depth noise); the
  // mean normal and the median depth are the wall's.
  std::size_t valid = 0;
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero ();
  std::vector<double> depth_error;
  for (const auto &t : texlets)
    if (std::isfinite (t.x))
    {
      ++valid;
      normal_sum += Eigen::Vector3d (t.normal_x, t.normal_y, t.normal_z);
      depth_error.push_back (std::abs (t.z - 1.5));
    }
  ASSERT_GT (valid, 0u);
  EXPECT_GT (-normal_sum.normalized ().z (), std::cos (M_PI / 180.0)) << normal_sum.transpose ();
  std::nth_element (depth_error.begin (), depth_error.begin () + valid / 2, depth_error.end ());
  EXPECT_LT (depth_error[valid / 2], 0.003);
  EXPECT_GT (valid, texlets.size () * 9 / 10);
}

TEST_F (ExtractApp, HelpExitsZero)
{
  const Result r = run ("--help");
  EXPECT_EQ (r.code, 0);
  EXPECT_NE (r.out.find ("--spacing"), std::string::npos);
  EXPECT_NE (r.out.find ("--uncertainty"), std::string::npos);
}

TEST_F (ExtractApp, LongRecordingsStreamInBoundedMemory)
{
  // One frame at a time, and the summary's medians from a bounded sample: ten times the frames
  // costs time, not memory. At spacing 2 a 160 x 120 frame has about 5,500 texlets; keeping a
  // number per texlet for the summary, as the app once did, would add about 12 MB over the 270
  // extra frames (8 bytes each), and keeping the frames' clouds 600 kB a frame.
  long peak[2] = {0, 0};
  int k = 0;
  for (const int frames : {30, 300})
  {
    const fs::path rec = dir_ / ("rec" + std::to_string (frames)), out = dir_ / ("out" + std::to_string (frames));
    const Result sim = pcl_texlet_test::runApp (SIM_APP, "--width 160 --height 120 --frames " + std::to_string (frames) +
                                                             " --seed 5 -q " + rec.string (), dir_);
    ASSERT_EQ (sim.code, 0) << sim.err;
    const Result r = pcl_texlet_test::runCommand (pcl_texlet_test::kPeakMemoryEnvironment + std::string (EXTRACT_APP) + " " +
                                                      rec.string () + " " + out.string () +
                                                      " -q -j 1 --spacing 2 --uncertainty none",
                                                  dir_);
    ASSERT_EQ (r.code, 0) << r.err;
    EXPECT_NE (r.out.find ("frames:                " + std::to_string (frames) + "\n"), std::string::npos) << r.out;
    peak[k++] = r.peak_rss_kb;
    fs::remove_all (out);
  }
  ASSERT_GT (peak[0], 0);
  EXPECT_LT (peak[1] - peak[0], 6 * 1024) << "peak RSS " << peak[0] << " kB for 30 frames, " << peak[1]
                                          << " kB for 300";
}
