/*
 * Bad input across the library's readers and parameters, the cases docs/inputs.md lists that no
 * other test covers: empty files, NaN and infinite numbers, absurd sizes, and the bad-frame
 * policy (FrameSkippingReader). Each must be an exception naming the input and the problem.
 */
#include "support/expect_error.h"
#include "support/recording_folder.h"
#include "support/temp_dir.h"

#include <pcl_texlet/io/frame_skipping_reader.h>
#include <pcl_texlet/relations/extrinsics.h>
#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/grabber_intrinsics.h>
#include <pcl_texlet/io/open_recording.h>
#include <pcl_texlet/io/pcd_folder_reader.h>
#include <pcl_texlet/io/png_image.h>
#include <pcl_texlet/io/recording_folder_reader.h>
#include <pcl_texlet/io/tiff_image.h>
#include <pcl_texlet/io/recording_writer.h>
#include <pcl_texlet/features/texlet_parameters.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pcl::texlet;

namespace
{

using BadInput = pcl_texlet_test::TempDirTest;
using pcl_texlet_test::expectError;

/** A recording folder of \a n 16x12 frames whose depth is 1000 + frame index. */
fs::path
makeRecording (const fs::path &folder, int n)
{
  return pcl_texlet_test::writeRecordingFolder (folder, pcl_texlet_test::centredCamera (16, 12, 20), n,
                                                [] (int, int, int f) { return 1000 + f; });
}

const char *const kCameraYaml = "image_width: 16\nimage_height: 12\ncamera_name: depth\n"
                                "camera_matrix: {rows: 3, cols: 3, data: [FX, 0, 7.5, 0, 20, 5.5, 0, 0, 1]}\n"
                                "distortion_model: plumb_bob\n"
                                "distortion_coefficients: {rows: 1, cols: 5, data: [0, 0, 0, 0, 0]}\n";

std::string
cameraYaml (const std::string &fx)
{
  std::string s = kCameraYaml;
  s.replace (s.find ("FX"), 2, fx);
  return s;
}

} // namespace

TEST_F (BadInput, EmptyFilesAreNamed)
{
  const fs::path empty = write ("empty", "");
  expectError<pcl::IOException> ([&] { loadCameraInfoYaml (empty.string ()); }, "empty", "");
  int w = 0, h = 0;
  expectError<pcl::IOException> ([&] { readDepthPng (empty.string (), w, h); }, "empty", "");
  expectError<pcl::IOException> ([&] { readRgbPng (empty.string (), w, h); }, "empty", "");
  expectError<pcl::IOException> ([&] { readDepthTiff (empty.string (), w, h); }, "empty", "");
  expectError<pcl::IOException> ([&] { loadGrabberIntrinsicsXml (empty.string ()); }, "empty", "");
  expectError<pcl::PCLException> ([&] { loadNoiseModelYaml (empty.string ()); }, "empty", "");
  expectError<pcl::PCLException> ([&] { loadExtrinsicsYaml (empty.string ()); }, "empty", "");
  const fs::path pcd = write ("empty.pcd", "");
  expectError<pcl::IOException> ([&] { PcdFolderReader r (pcd.string ()); }, "empty.pcd", "");
}

TEST_F (BadInput, NanAndInfiniteIntrinsicsAreRejected)
{
  for (const std::string fx : {".nan", ".inf", "-.inf", "0", "-20", "1e400"})
  {
    const fs::path p = write ("camera.yaml", cameraYaml (fx));
    expectError<pcl::IOException> ([&] { loadCameraInfoYaml (p.string ()); }, "camera.yaml", "");
  }
  // The principal point too: a NaN there would make every back-projected point NaN.
  std::string s = cameraYaml ("20");
  s.replace (s.find ("7.5"), 3, ".nan");
  const fs::path p = write ("camera.yaml", s);
  expectError<pcl::IOException> ([&] { loadCameraInfoYaml (p.string ()); }, "camera.yaml", "");
}

TEST_F (BadInput, AbsurdImageSizesAreRejectedBeforeAllocating)
{
  for (const std::string size : {"image_width: 16\nimage_height: 2000000000\n", "image_width: -16\nimage_height: 12\n",
                                 "image_width: 1e30\nimage_height: 12\n"})
  {
    std::string s = kCameraYaml;
    s.replace (0, s.find ("camera_name"), size);
    s.replace (s.find ("FX"), 2, "20");
    const fs::path p = write ("camera.yaml", s);
    expectError<pcl::IOException> ([&] { loadCameraInfoYaml (p.string ()); }, "camera.yaml", "");
  }
  // A PNG whose header claims 100000 x 100000 pixels (20 GB of depth) with no data behind it.
  const fs::path png = dir_ / "huge.png";
  {
    FILE *f = std::fopen (png.string ().c_str (), "wb");
    ASSERT_NE (f, nullptr);
    png_structp ps = png_create_write_struct (PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop pi = png_create_info_struct (ps);
    png_init_io (ps, f);
    png_set_IHDR (ps, pi, 100000, 100000, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                  PNG_FILTER_TYPE_DEFAULT);
    png_write_info (ps, pi);
    png_destroy_write_struct (&ps, &pi);
    std::fclose (f);
  }
  int w = 0, h = 0;
  expectError<pcl::IOException> ([&] { readDepthPng (png.string (), w, h); }, "huge.png", "");
}

TEST_F (BadInput, NanAndAbsurdTexletParametersAreRejected)
{
  const double nan = std::numeric_limits<double>::quiet_NaN (), inf = std::numeric_limits<double>::infinity ();
  for (const double t : {nan, inf, -1.0})
  {
    TexletParameters p;
    p.ransac_threshold = t;
    EXPECT_THROW (validate (p), pcl::PCLException) << t;
  }
  for (const double s : {nan, inf, 0.0, -3.0})
  {
    TexletParameters p;
    p.threshold_sigmas = s;
    EXPECT_THROW (validate (p), pcl::PCLException) << s;
  }
  for (const int big : {1 << 20, std::numeric_limits<int>::max ()})
  {
    TexletParameters p;
    p.radius = big;
    EXPECT_THROW (validate (p), pcl::PCLException) << "radius " << big;
    p = TexletParameters ();
    p.samples = big;
    EXPECT_THROW (validate (p), pcl::PCLException) << "samples " << big;
    p = TexletParameters ();
    p.ransac_iterations = big;
    EXPECT_THROW (validate (p), pcl::PCLException) << "iterations " << big;
  }
}

TEST_F (BadInput, NanInNoiseModelAndExtrinsicsIsRejected)
{
  const NoiseModel paper = NoiseModel::paper ();
  std::string yaml = noiseModelToYaml (paper);
  // The polynomial's constant made NaN or infinite.
  const std::size_t at = yaml.find_first_of ("-0123456789", yaml.find ("p00: "));
  ASSERT_NE (at, std::string::npos) << yaml;
  const std::size_t end = yaml.find_first_of (",]\n", at);
  for (const std::string bad : {".nan", ".inf"})
  {
    std::string y = yaml;
    y.replace (at, end - at, bad);
    const fs::path p = write ("model.yaml", y);
    expectError<pcl::PCLException> ([&] { loadNoiseModelYaml (p.string ()); }, "model.yaml", "");
  }
  std::vector<SensorExtrinsics> sensors (1);
  sensors[0].name = "sensor_0";
  const fs::path good = dir_ / "extrinsics.yaml";
  saveExtrinsicsYaml (good.string (), sensors);
  std::string text;
  {
    std::ifstream in (good);
    std::stringstream s;
    s << in.rdbuf ();
    text = s.str ();
  }
  const std::size_t one = text.find ("1");
  ASSERT_NE (one, std::string::npos) << text;
  text.replace (one, 1, ".nan");
  const fs::path p = write ("extrinsics.yaml", text);
  expectError<pcl::PCLException> ([&] { loadExtrinsicsYaml (p.string ()); }, "extrinsics.yaml", "");
}

TEST_F (BadInput, FrameSkippingReaderPassesOverBadFramesAndCountsThem)
{
  const fs::path rec = makeRecording (dir_ / "rec", 6);
  // Frame 2 truncated, frame 4 not a PNG at all.
  std::string bytes;
  {
    std::ifstream in (rec / "depth" / "000002.png", std::ios::binary);
    std::stringstream s;
    s << in.rdbuf ();
    bytes = s.str ();
  }
  std::ofstream (rec / "depth" / "000002.png", std::ios::binary) << bytes.substr (0, bytes.size () / 2);
  std::ofstream (rec / "depth" / "000004.png") << "not a PNG";

  std::vector<std::string> warnings;
  FrameSkippingReader reader (std::make_shared<RecordingFolderReader> (rec.string ()),
                              [&] (const std::string &m) { warnings.push_back (m); });
  EXPECT_EQ (reader.size (), 6u);
  EXPECT_EQ (reader.cameraInfo ().width, 16);
  std::vector<int> depths;
  DepthFrame frame;
  while (reader.next (frame))
    depths.push_back (frame.depth_mm.front ());
  EXPECT_EQ (depths, (std::vector<int>{1000, 1001, 1003, 1005})); // the good frames, in order
  EXPECT_EQ (reader.skipped (), 2u);
  EXPECT_EQ (reader.delivered (), 4u);
  ASSERT_EQ (warnings.size (), 2u);
  EXPECT_NE (warnings[0].find ("000002.png"), std::string::npos) << warnings[0];
  EXPECT_NE (warnings[1].find ("000004.png"), std::string::npos) << warnings[1];
  EXPECT_EQ (reader.skippedMessages (), warnings);
  EXPECT_FALSE (reader.next (frame)); // stays at the end

  // The plain reader stops at the first bad frame, naming it.
  RecordingFolderReader plain (rec.string ());
  ASSERT_TRUE (plain.next (frame));
  ASSERT_TRUE (plain.next (frame));
  expectError<pcl::IOException> ([&] { plain.next (frame); }, "000002.png", "");
}

namespace
{
/** A reader that throws without moving on: the skipping reader must not spin on it. */
class StuckReader : public RecordingReader
{
public:
  std::size_t
  size () const override { return 3; }
  const CameraInfo &
  cameraInfo () const override { return info_; }
  bool
  next (DepthFrame &) override { throw pcl::IOException ("frame 'stuck' cannot be read"); }

private:
  CameraInfo info_;
};
} // namespace

TEST_F (BadInput, FrameSkippingReaderGivesUpOnAReaderThatDoesNotMoveOn)
{
  FrameSkippingReader reader (std::make_shared<StuckReader> ());
  DepthFrame frame;
  expectError<pcl::IOException> ([&] { reader.next (frame); }, "more bad frames than the 3 frames", "stuck");
  EXPECT_THROW (FrameSkippingReader (nullptr), pcl::BadArgumentException);
}

TEST_F (BadInput, SxgaRecordingRoundTripsThroughWriterAndReader)
{
  // 1280 x 1024, the Xtion's SXGA mode: written, read back value for value.
  CameraInfo info;
  info.width = 1280;
  info.height = 1024;
  const double K[9] = {1160, 0, 639.5, 0, 1160, 511.5, 0, 0, 1};
  std::copy (K, K + 9, info.K);
  RecordingFolderWriter w ((dir_ / "sxga").string (), info);
  DepthFrame frame;
  frame.name = "000000";
  frame.width = 1280;
  frame.height = 1024;
  frame.depth_mm.resize (1280 * 1024);
  for (std::size_t i = 0; i < frame.depth_mm.size (); ++i)
    frame.depth_mm[i] = static_cast<std::uint16_t> (i % 65536);
  frame.rgb.assign (3 * frame.depth_mm.size (), 7);
  w.writeFrame (frame);
  w.commit ();
  const RecordingReader::Ptr r = openRecording ((dir_ / "sxga").string ());
  EXPECT_EQ (r->cameraInfo ().width, 1280);
  EXPECT_EQ (r->cameraInfo ().height, 1024);
  DepthFrame back;
  ASSERT_TRUE (r->next (back));
  EXPECT_EQ (back.depth_mm, frame.depth_mm);
  EXPECT_EQ (back.rgb, frame.rgb);
}

TEST_F (BadInput, WritersLeaveNoPartialFile)
{
  // Into a folder that does not exist: an error naming the file, and nothing left anywhere.
  const fs::path missing = dir_ / "missing";
  CameraInfo info;
  info.width = 4;
  info.height = 3;
  info.K[0] = info.K[4] = 5;
  const std::vector<std::uint16_t> depth (12, 1000);
  const std::vector<std::uint8_t> rgb (36, 9);
  expectError<pcl::PCLException> ([&] { saveCameraInfoYaml ((missing / "camera.yaml").string (), info); },
                                  "camera.yaml", "");
  expectError<pcl::PCLException> ([&] { saveNoiseModelYaml ((missing / "model.yaml").string (), NoiseModel::paper ()); },
                                  "model.yaml", "");
  expectError<pcl::PCLException> ([&] { saveExtrinsicsYaml ((missing / "extrinsics.yaml").string (), {}); },
                                  "extrinsics.yaml", "");
  expectError<pcl::PCLException> ([&] { writeDepthPng ((missing / "d.png").string (), depth.data (), 4, 3); }, "d.png",
                                  "");
  expectError<pcl::PCLException> ([&] { writeRgbPng ((missing / "c.png").string (), rgb.data (), 4, 3); }, "c.png", "");
  EXPECT_TRUE (fs::is_empty (dir_));

  // Written: the file and nothing beside it (no temporary left over).
  saveCameraInfoYaml ((dir_ / "camera.yaml").string (), info);
  saveNoiseModelYaml ((dir_ / "model.yaml").string (), NoiseModel::paper ());
  saveExtrinsicsYaml ((dir_ / "extrinsics.yaml").string (), std::vector<SensorExtrinsics> (1));
  writeDepthPng ((dir_ / "d.png").string (), depth.data (), 4, 3);
  std::vector<std::string> names;
  for (const auto &e : fs::directory_iterator (dir_))
    names.push_back (e.path ().filename ().string ());
  std::sort (names.begin (), names.end ());
  EXPECT_EQ (names, (std::vector<std::string>{"camera.yaml", "d.png", "extrinsics.yaml", "model.yaml"}));

  // A recording writer destroyed before commit leaves no folder, not even its hidden temporary.
  {
    RecordingFolderWriter w ((dir_ / "rec").string (), info);
    DepthFrame f;
    f.name = "000000";
    f.width = 4;
    f.height = 3;
    f.depth_mm = depth;
    w.writeFrame (f);
  }
  std::size_t entries = 0;
  for (const auto &e : fs::directory_iterator (dir_))
    entries += e.path ().filename ().string ().find ("rec") != std::string::npos ? 1 : 0;
  EXPECT_EQ (entries, 0u);
}
