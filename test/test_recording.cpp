/*
 * Recording folders (docs/inputs.md): exact PNG and camera.yaml round trips, frames streamed
 * in name order, and bad files rejected with a pcl::IOException that names the file.
 */
#include "support/expect_error.h"
#include "support/image_patterns.h"
#include "support/recording_folder.h"
#include "support/temp_dir.h"

#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/png_image.h>
#include <pcl_texlet/io/recording_folder_reader.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pcl::texlet;

namespace
{

/** \brief A fresh folder per test (test/support/temp_dir.h). */
using RecordingTest = pcl_texlet_test::TempDirTest;
using pcl_texlet_test::depthPattern;
using pcl_texlet_test::expectError;
using pcl_texlet_test::rgbPattern;

/** \brief 16-bit samples as PNG stores them: big-endian, independent of the host. */
std::vector<unsigned char>
bigEndianBytes (const std::vector<std::uint16_t> &samples)
{
  std::vector<unsigned char> bytes;
  for (const std::uint16_t s : samples)
  {
    bytes.push_back (static_cast<unsigned char> (s >> 8));
    bytes.push_back (static_cast<unsigned char> (s & 0xff));
  }
  return bytes;
}

/** \brief Writes a 33 x 17 \a image as \a name in the test's folder with \a write and expects
  * that file alone there (no temporary left) and \a read to give every value back.
  */
template <typename Sample, typename Write, typename Read> void
expectPngRoundTrip (const pcl_texlet_test::TempDir &folder, const std::string &name, const std::vector<Sample> &image,
                    Write write, Read read)
{
  const std::string path = (folder.path () / name).string ();
  write (path, image.data (), 33, 17);
  EXPECT_EQ (folder.entries (), std::vector<std::string>{name}) << "no temporary file left";
  int width = 0, height = 0;
  EXPECT_EQ (read (path, width, height), image);
  EXPECT_EQ (width, 33);
  EXPECT_EQ (height, 17);
}

/** \brief Writes any PNG with libpng directly, from rows of bytes already in PNG order, so that the
  * reader is checked against files it did not write itself. Only trivially destructible locals
  * live here because libpng's default error handler longjmps to the setjmp below.
  */
bool
writeRawPng (const char *path, int width, int height, int bit_depth, int colour_type, int interlace,
             const unsigned char *bytes, std::size_t row_bytes)
{
  std::FILE *file = std::fopen (path, "wb");
  if (!file)
    return false;
  png_structp png = png_create_write_struct (PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct (png) : nullptr;
  if (!info || setjmp (png_jmpbuf (png)))
  {
    png_destroy_write_struct (&png, &info);
    std::fclose (file);
    return false;
  }
  png_init_io (png, file);
  png_set_IHDR (png, info, width, height, bit_depth, colour_type, interlace, PNG_COMPRESSION_TYPE_DEFAULT,
                PNG_FILTER_TYPE_DEFAULT);
  png_write_info (png, info);
  const int passes = png_set_interlace_handling (png);
  for (int pass = 0; pass < passes; ++pass)
    for (int y = 0; y < height; ++y)
      png_write_row (png, bytes + y * row_bytes);
  png_write_end (png, nullptr);
  png_destroy_write_struct (&png, &info);
  return std::fclose (file) == 0;
}

/** \brief An 8-bit grey image: a valid PNG, but not a depth frame. */
bool
writeGrey8Png (const std::string &path, int width, int height)
{
  std::vector<unsigned char> grey (static_cast<std::size_t> (width) * height);
  for (std::size_t i = 0; i < grey.size (); ++i)
    grey[i] = static_cast<unsigned char> (i);
  return writeRawPng (path.c_str (), width, height, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, grey.data (),
                      static_cast<std::size_t> (width));
}

bool
writeRgb8Png (const std::string &path, int width, int height, const std::vector<std::uint8_t> &rgb)
{
  return writeRawPng (path.c_str (), width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, rgb.data (),
                      static_cast<std::size_t> (width) * 3);
}

void
writeText (const std::string &path, const std::string &text)
{
  std::ofstream (path, std::ios::binary) << text;
}

using pcl_texlet_test::camera33x17;

/** \brief A recording folder: camera.yaml, and depth/ (and rgb/) frames named by \a names. */
void
makeRecording (const fs::path &folder, const CameraInfo &info, std::initializer_list<std::string> names,
               bool with_rgb)
{
  fs::create_directories (folder / "depth");
  saveCameraInfoYaml ((folder / "camera.yaml").string (), info);
  if (with_rgb)
    fs::create_directories (folder / "rgb");
  for (const std::string &name : names)
  {
    const unsigned seed = static_cast<unsigned> (std::stoul (name));
    const std::vector<std::uint16_t> depth = depthPattern (info.width, info.height, seed);
    writeDepthPng ((folder / "depth" / (name + ".png")).string (), depth.data (), info.width, info.height);
    if (with_rgb)
    {
      ASSERT_TRUE (writeRgb8Png ((folder / "rgb" / (name + ".png")).string (), info.width, info.height,
                                 rgbPattern (info.width, info.height, seed)));
    }
  }
}

} // namespace

// ---------------------------------------------------------------------------------------------
// PNG

TEST_F (RecordingTest, DepthPngRoundTripKeepsEveryValueAndLeavesNoTemporaryFile)
{
  expectPngRoundTrip (temp_, "depth.png", depthPattern (33, 17, 1), writeDepthPng, readDepthPng);
  // Writing over an existing frame replaces it whole.
  expectPngRoundTrip (temp_, "depth.png", depthPattern (33, 17, 2), writeDepthPng, readDepthPng);
}

TEST_F (RecordingTest, DepthPngReadsBigEndianSamplesWrittenByLibpng)
{
  const std::vector<std::uint16_t> depth = depthPattern (33, 17, 3);
  const std::vector<unsigned char> bytes = bigEndianBytes (depth);
  ASSERT_TRUE (writeRawPng (file ("plain.png").c_str (), 33, 17, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                            bytes.data (), 33 * 2));
  ASSERT_TRUE (writeRawPng (file ("adam7.png").c_str (), 33, 17, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_ADAM7,
                            bytes.data (), 33 * 2));
  int width = 0, height = 0;
  EXPECT_EQ (readDepthPng (file ("plain.png"), width, height), depth);
  EXPECT_EQ (readDepthPng (file ("adam7.png"), width, height), depth);
  EXPECT_EQ (width, 33);
  EXPECT_EQ (height, 17);
}

TEST_F (RecordingTest, RgbPngReadsRgbAndDropsAlpha)
{
  const std::vector<std::uint8_t> rgb = rgbPattern (7, 5, 4);
  ASSERT_TRUE (writeRgb8Png (file ("rgb.png"), 7, 5, rgb));
  std::vector<unsigned char> rgba;
  for (std::size_t i = 0; i < rgb.size (); i += 3)
    rgba.insert (rgba.end (), {rgb[i], rgb[i + 1], rgb[i + 2], static_cast<unsigned char> (i)});
  ASSERT_TRUE (writeRawPng (file ("rgba.png").c_str (), 7, 5, 8, PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
                            rgba.data (), 7 * 4));

  int width = 0, height = 0;
  EXPECT_EQ (readRgbPng (file ("rgb.png"), width, height), rgb);
  EXPECT_EQ (width, 7);
  EXPECT_EQ (height, 5);
  EXPECT_EQ (readRgbPng (file ("rgba.png"), width, height), rgb);
}

TEST_F (RecordingTest, RgbPngRoundTripKeepsEveryValueAndLeavesNoTemporaryFile)
{
  const std::vector<std::uint8_t> rgb = rgbPattern (33, 17, 5);
  expectPngRoundTrip (temp_, "rgb.png", rgb, writeRgbPng, readRgbPng);
  int width = 0, height = 0;
  // An RGB image is not a depth frame, whoever wrote it.
  expectError ([&] { readDepthPng (file ("rgb.png"), width, height); }, {file ("rgb.png"), "found 8-bit RGB"});
  expectError ([&] { writeRgbPng (file ("no/such/folder/rgb.png"), rgb.data (), 33, 17); },
                 {file ("no/such/folder/rgb.png"), "cannot create"});
}

TEST_F (RecordingTest, EightBitGreyPngIsNotADepthFrame)
{
  ASSERT_TRUE (writeGrey8Png (file ("grey8.png"), 33, 17));
  int width, height;
  expectError ([&] { readDepthPng (file ("grey8.png"), width, height); },
                 {file ("grey8.png"), "expected 16-bit grey depth, found 8-bit"});
}

TEST_F (RecordingTest, RgbPngIsNotADepthFrame)
{
  ASSERT_TRUE (writeRgb8Png (file ("colour.png"), 33, 17, rgbPattern (33, 17, 0)));
  int width, height;
  expectError ([&] { readDepthPng (file ("colour.png"), width, height); },
                 {file ("colour.png"), "expected 16-bit grey depth, found 8-bit RGB"});
}

TEST_F (RecordingTest, DepthPngIsNotAnRgbImage)
{
  const std::vector<std::uint16_t> depth = depthPattern (33, 17, 0);
  writeDepthPng (file ("depth.png"), depth.data (), 33, 17);
  int width, height;
  expectError ([&] { readRgbPng (file ("depth.png"), width, height); },
                 {file ("depth.png"), "expected 8-bit RGB or RGBA, found 16-bit grey"});
}

TEST_F (RecordingTest, TruncatedPngIsRejected)
{
  // Scrambled values hardly compress, so half the file ends inside the image data.
  const std::vector<std::uint16_t> depth = depthPattern (64, 48, 5);
  writeDepthPng (file ("cut.png"), depth.data (), 64, 48);
  fs::resize_file (file ("cut.png"), fs::file_size (file ("cut.png")) / 2);
  int width, height;
  expectError ([&] { readDepthPng (file ("cut.png"), width, height); }, {file ("cut.png"), "truncated"});
}

TEST_F (RecordingTest, TextFileNamedPngIsRejected)
{
  writeText (file ("notes.png"), "depth frames go here\n");
  int width, height;
  expectError ([&] { readDepthPng (file ("notes.png"), width, height); }, {file ("notes.png"), "not a PNG"});
}

TEST_F (RecordingTest, MissingPngIsRejected)
{
  int width, height;
  expectError ([&] { readDepthPng (file ("absent.png"), width, height); },
                 {file ("absent.png"), "does not exist"});
}

TEST_F (RecordingTest, DepthPngIntoMissingFolderFailsWithoutLeavingFiles)
{
  const std::vector<std::uint16_t> depth = depthPattern (4, 3, 0);
  expectError ([&] { writeDepthPng (file ("no/such/folder/d.png"), depth.data (), 4, 3); },
                 {file ("no/such/folder/d.png"), "cannot create"});
  EXPECT_TRUE (fs::is_empty (dir_));
}

// ---------------------------------------------------------------------------------------------
// camera.yaml

TEST_F (RecordingTest, CameraYamlRoundTripIsExact)
{
  const CameraInfo a = camera33x17 ();
  saveCameraInfoYaml (file ("camera.yaml"), a);
  EXPECT_EQ (temp_.entries (), std::vector<std::string>{"camera.yaml"}); // no temporary file left
  const CameraInfo b = loadCameraInfoYaml (file ("camera.yaml"));
  EXPECT_EQ (b.width, 33);
  EXPECT_EQ (b.height, 17);
  for (int i = 0; i < 9; ++i)
    EXPECT_EQ (b.K[i], a.K[i]) << "K[" << i << "]";
  EXPECT_EQ (b.distortion_model, "plumb_bob");
  EXPECT_EQ (b.D, a.D);
  EXPECT_EQ (b.baseline_m, 0.0752);
  EXPECT_EQ (b.disparity_subpixel, 0.0625);

  CameraInfo rational = a;
  rational.distortion_model = "rational_polynomial";
  rational.D = {0.5, -0.125, 0.001, 0.002, 0.01, 0.25, -0.0625, 0.03125};
  saveCameraInfoYaml (file ("camera.yaml"), rational);
  const CameraInfo c = loadCameraInfoYaml (file ("camera.yaml"));
  EXPECT_EQ (c.distortion_model, "rational_polynomial");
  EXPECT_EQ (c.D, rational.D);
}

TEST_F (RecordingTest, RosCameraInfoWithoutOptionalKeysUsesDefaults)
{
  // As ROS's camera_calibration_parsers write it, with keys this library ignores.
  writeText (file ("camera.yaml"), "image_width: 640\n"
                                   "image_height: 480\n"
                                   "camera_name: depth_camera\n"
                                   "camera_matrix:\n"
                                   "  rows: 3\n"
                                   "  cols: 3\n"
                                   "  data: [525, 0, 319.5, 0, 524.5, 239.5, 0, 0, 1]\n"
                                   "distortion_model: plumb_bob\n"
                                   "distortion_coefficients:\n"
                                   "  rows: 1\n"
                                   "  cols: 5\n"
                                   "  data: [0.01, -0.02, 0, 0, 0]\n"
                                   "rectification_matrix:\n"
                                   "  rows: 3\n"
                                   "  cols: 3\n"
                                   "  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n");
  const CameraInfo info = loadCameraInfoYaml (file ("camera.yaml"));
  EXPECT_EQ (info.width, 640);
  EXPECT_EQ (info.height, 480);
  EXPECT_EQ (info.fx (), 525.0);
  EXPECT_EQ (info.fy (), 524.5);
  EXPECT_EQ (info.cx (), 319.5);
  EXPECT_EQ (info.cy (), 239.5);
  EXPECT_EQ (info.D, (std::vector<double> {0.01, -0.02, 0, 0, 0}));
  EXPECT_EQ (info.baseline_m, 0.075);
  EXPECT_EQ (info.disparity_subpixel, 0.125);
}

TEST_F (RecordingTest, MalformedCameraYamlIsRejected)
{
  writeText (file ("camera.yaml"), "image_width: [640\nimage_height: 480\n");
  expectError ([&] { loadCameraInfoYaml (file ("camera.yaml")); }, {file ("camera.yaml"), "not valid YAML"});
}

TEST_F (RecordingTest, BadCameraYamlContentNamesFileAndProblem)
{
  const std::string size = "image_width: 33\nimage_height: 17\n";
  const std::string k = "camera_matrix: {rows: 3, cols: 3, data: [60, 0, 16, 0, 60, 8, 0, 0, 1]}\n";
  const std::string d = "distortion_model: plumb_bob\ndistortion_coefficients: {rows: 1, cols: 5, data: [0, 0, 0, 0, 0]}\n";
  const struct
  {
    std::string yaml;
    std::string problem;
  } cases[] = {
    {size + "camera_matrix: {rows: 2, cols: 2, data: [60, 0, 0, 60]}\n" + d,
     "camera_matrix.data must have 9 numbers (found 4)"},
    {"image_width: 0\nimage_height: 17\n" + k + d, "image_width and image_height must be positive (found 0x17)"},
    {"image_width: 33.5\nimage_height: 17\n" + k + d, "image_width must be an integer (found '33.5')"},
    {"image_height: 17\n" + k + d, "missing key 'image_width'"},
    {size + "camera_matrix: {rows: 3, cols: 3, data: [0, 0, 16, 0, 60, 8, 0, 0, 1]}\n" + d,
     "focal lengths fx and fy must be positive (found fx 0, fy 60)"},
    {size + "camera_matrix: {rows: 3, cols: 3, data: [60, 0, 16, 0, .inf, 8, 0, 0, 1]}\n" + d,
     "camera_matrix.data[4] must be finite"},
    {size + "camera_matrix: {rows: 3, cols: 3, data: [60, 0, 16, 0, sixty, 8, 0, 0, 1]}\n" + d,
     "camera_matrix.data[4] must be a number (found 'sixty')"},
    {size + k + "distortion_model: plumb_bob\ndistortion_coefficients: {rows: 1, cols: 4, data: [0, 0, 0, 0]}\n",
     "must have 5 numbers for plumb_bob (found 4)"},
    {size + k + "distortion_model: rational_polynomial\ndistortion_coefficients: {data: [0, 0, 0, 0, 0, 0, 0, 0, 0]}\n",
     "must have at most 8 numbers (found 9)"},
    {size + k + d + "baseline_m: -0.075\n", "baseline_m must be positive and finite (found -0.075)"},
    {size + k + d + "disparity_subpixel: 0\n", "disparity_subpixel must be positive and finite (found 0)"},
    {"- image_width\n- image_height\n", "not a YAML map"},
  };
  for (const auto &c : cases)
  {
    SCOPED_TRACE (c.yaml);
    writeText (file ("camera.yaml"), c.yaml);
    expectError ([&] { loadCameraInfoYaml (file ("camera.yaml")); }, {file ("camera.yaml"), c.problem});
  }
}

// ---------------------------------------------------------------------------------------------
// Recording folder

TEST_F (RecordingTest, FolderReaderStreamsFramesInNameOrderWithRgb)
{
  const CameraInfo info = camera33x17 ();
  makeRecording (dir_ / "rec", info, {"000002", "000000", "000001"}, true);
  writeText (file ("rec/depth/notes.txt"), "not a frame\n");
  ASSERT_TRUE (RecordingFolderReader::isRecordingFolder (file ("rec")));

  RecordingFolderReader reader (file ("rec"));
  EXPECT_EQ (reader.size (), 3u);
  EXPECT_EQ (reader.cameraInfo ().fx (), info.fx ());
  EXPECT_EQ (reader.cameraInfo ().D, info.D);

  DepthFrame frame;
  for (unsigned i = 0; i < 3; ++i)
  {
    ASSERT_TRUE (reader.next (frame));
    EXPECT_EQ (frame.name, "00000" + std::to_string (i));
    EXPECT_EQ (frame.width, 33);
    EXPECT_EQ (frame.height, 17);
    EXPECT_EQ (frame.depth_mm, depthPattern (33, 17, i));
    EXPECT_EQ (frame.rgb, rgbPattern (33, 17, i));
  }
  EXPECT_FALSE (reader.next (frame));
  EXPECT_FALSE (reader.next (frame));
}

TEST_F (RecordingTest, FrameWithoutRgbHasEmptyRgb)
{
  makeRecording (dir_ / "rec", camera33x17 (), {"10", "11"}, true);
  fs::remove (dir_ / "rec" / "rgb" / "11.png");
  RecordingFolderReader reader (file ("rec"));
  DepthFrame frame;
  ASSERT_TRUE (reader.next (frame));
  EXPECT_EQ (frame.rgb, rgbPattern (33, 17, 10));
  ASSERT_TRUE (reader.next (frame));
  EXPECT_EQ (frame.name, "11");
  EXPECT_EQ (frame.depth_mm, depthPattern (33, 17, 11));
  EXPECT_TRUE (frame.rgb.empty ());
}

TEST_F (RecordingTest, IsRecordingFolderNeedsCameraYamlAndDepth)
{
  EXPECT_FALSE (RecordingFolderReader::isRecordingFolder (file ("absent")));
  fs::create_directories (dir_ / "rec" / "depth");
  EXPECT_FALSE (RecordingFolderReader::isRecordingFolder (file ("rec")));
  saveCameraInfoYaml (file ("rec/camera.yaml"), camera33x17 ());
  EXPECT_TRUE (RecordingFolderReader::isRecordingFolder (file ("rec")));
  fs::remove (dir_ / "rec" / "depth");
  EXPECT_FALSE (RecordingFolderReader::isRecordingFolder (file ("rec")));
}

TEST_F (RecordingTest, MissingFolderIsRejected)
{
  expectError ([&] { RecordingFolderReader reader (file ("absent")); }, {file ("absent"), "does not exist"});
}

TEST_F (RecordingTest, FolderWithoutCameraYamlIsRejected)
{
  makeRecording (dir_ / "rec", camera33x17 (), {"0"}, false);
  fs::remove (dir_ / "rec" / "camera.yaml");
  expectError ([&] { RecordingFolderReader reader (file ("rec")); },
                 {file ("rec/camera.yaml"), "does not exist"});
}

TEST_F (RecordingTest, FolderWithoutDepthFramesIsRejected)
{
  fs::create_directories (dir_ / "rec");
  saveCameraInfoYaml (file ("rec/camera.yaml"), camera33x17 ());
  expectError ([&] { RecordingFolderReader reader (file ("rec")); }, {file ("rec"), "no depth/ subfolder"});
  fs::create_directories (dir_ / "rec" / "depth");
  writeText (file ("rec/depth/readme.txt"), "frames come later\n");
  expectError ([&] { RecordingFolderReader reader (file ("rec")); }, {file ("rec"), "depth/ is empty"});
}

TEST_F (RecordingTest, FrameSizeDifferentFromCameraYamlIsRejectedAndSkippable)
{
  makeRecording (dir_ / "rec", camera33x17 (), {"1"}, false);
  const std::vector<std::uint16_t> narrow = depthPattern (32, 17, 0);
  writeDepthPng (file ("rec/depth/0.png"), narrow.data (), 32, 17);

  RecordingFolderReader reader (file ("rec"));
  DepthFrame frame;
  expectError ([&] { reader.next (frame); },
                 {file ("rec/depth/0.png"), "is 32x17 but camera.yaml says 33x17", file ("rec/camera.yaml")});
  // The bad frame was consumed, so a caller that skips it gets the next one.
  ASSERT_TRUE (reader.next (frame));
  EXPECT_EQ (frame.name, "1");
  EXPECT_EQ (frame.depth_mm, depthPattern (33, 17, 1));
  EXPECT_FALSE (reader.next (frame));
}

TEST_F (RecordingTest, RgbSizeDifferentFromCameraYamlIsRejected)
{
  makeRecording (dir_ / "rec", camera33x17 (), {"0"}, false);
  fs::create_directories (dir_ / "rec" / "rgb");
  ASSERT_TRUE (writeRgb8Png (file ("rec/rgb/0.png"), 33, 16, rgbPattern (33, 16, 0)));
  RecordingFolderReader reader (file ("rec"));
  DepthFrame frame;
  expectError ([&] { reader.next (frame); }, {file ("rec/rgb/0.png"), "is 33x16 but camera.yaml says 33x17"});
}

TEST_F (RecordingTest, BadDepthFrameInFolderNamesTheFile)
{
  makeRecording (dir_ / "rec", camera33x17 (), {"0"}, false);
  ASSERT_TRUE (writeGrey8Png (file ("rec/depth/0.png"), 33, 17));
  RecordingFolderReader reader (file ("rec"));
  DepthFrame frame;
  expectError ([&] { reader.next (frame); }, {file ("rec/depth/0.png"), "found 8-bit grey"});
}
