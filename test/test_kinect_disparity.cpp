/*
 * Raw Kinect disparity folders (include/pcl_texlet/io/kinect_disparity_reader.h): 16-bit PGMs
 * and an OpenCV-style calibration YAML written here, read back and checked against the closed
 * form z = 1 / (c0 + c1 d); openRecording's choice; every kind of bad input rejected with a
 * pcl::IOException that names the file and the problem.
 */
#include "support/expect_error.h"
#include "support/read_all.h"
#include "support/temp_dir.h"

#include <pcl_texlet/io/frame_skipping_reader.h>
#include <pcl_texlet/io/kinect_disparity_calibration.h>
#include <pcl_texlet/io/kinect_disparity_reader.h>
#include <pcl_texlet/io/open_recording.h>
#include <pcl_texlet/io/pgm_image.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pcl::texlet;

namespace
{

using KinectDisparity = pcl_texlet_test::TempDirTest;
using pcl_texlet_test::expectError;
using pcl_texlet_test::TempDir;

// Herrera's published Kinect calibration (his toolbox's default dc): d = 760 is about 1.003 m, and
// c0 + c1 d reaches 0 at d = 1084.6, beyond which no depth is positive.
const double kC0 = 3.3309495161;
const double kC1 = -0.0030711016;

/** \brief A binary PGM of 16-bit \a samples (with a header comment, as some writers add), most
  * significant byte first unless \a little_endian (libfreenect's recorder).
  */
std::string
pgm (int width, int height, const std::vector<std::uint16_t> &samples, int maxval = 65535, bool little_endian = false)
{
  std::string bytes = "P5\n# raw disparity\n" + std::to_string (width) + " " + std::to_string (height) + "\n" +
                      std::to_string (maxval) + "\n";
  for (const std::uint16_t s : samples)
  {
    const char hi = static_cast<char> (s >> 8), lo = static_cast<char> (s & 0xFF);
    bytes += little_endian ? lo : hi;
    bytes += little_endian ? hi : lo;
  }
  return bytes;
}

/** \brief An OpenCV matrix as OpenCV and Herrera's save_calib_yml write it. */
std::string
cvMatrix (const std::string &key, int rows, int cols, const std::string &data)
{
  return key + ": !!opencv-matrix\n   rows: " + std::to_string (rows) + "\n   cols: " + std::to_string (cols) +
         "\n   dt: f\n   data: [ " + data + " ]\n";
}

const std::string kK = "585.5, 0., 318.25, 0., 583.75, 243.5, 0., 0., 1.";
const std::string kD = "-0.125, 0.25, 0.001, -0.002, 0.";

/** \brief The calibration file Herrera's toolbox writes (its keys, with %YAML:1.0) for the
  * depth camera, plus \a extra lines.
  */
std::string
herreraYaml (const std::string &extra = "")
{
  return "%YAML:1.0\n" + cvMatrix ("rsize1", 1, 2, "640., 480.") + cvMatrix ("rK1", 3, 3, "520., 0., 320., 0., 520., 240., 0., 0., 1.") +
         cvMatrix ("dK", 3, 3, kK) + cvMatrix ("dkc", 1, 5, kD) +
         cvMatrix ("dR", 3, 3, "1., 0., 0., 0., 1., 0., 0., 0., 1.") + cvMatrix ("dt", 3, 1, "0.025, 0., 0.") +
         cvMatrix ("dc", 1, 2, "3.3309495161, -0.0030711016") + extra;
}

/** \brief The depth in millimetres the closed form gives, rounded, 0 where it gives none. */
std::uint16_t
closedFormMm (std::uint16_t d)
{
  if (d >= 2047)
    return 0;
  const double z_mm = 1000.0 / (kC0 + kC1 * d);
  if (!(z_mm > 0) || z_mm >= 65535.5)
    return 0;
  return static_cast<std::uint16_t> (std::lround (z_mm));
}

/** \brief Disparities over the Kinect's range (0.5 m to beyond 10 m), fixed seed, with no-reading
  * pixels (2047), values above the 11 bits, and disparities whose depth is not positive or too far.
  */
std::vector<std::uint16_t>
disparities (int width, int height, unsigned seed)
{
  std::mt19937 rng (seed);
  std::uniform_int_distribution<int> d (400, 1060);
  std::vector<std::uint16_t> v (std::size_t (width) * height);
  for (std::uint16_t &s : v)
    s = static_cast<std::uint16_t> (d (rng));
  const std::uint16_t special[] = {2047, 2047, 4095, 65535, 0, 1084, 1085, 1500, 2046, 1060};
  for (std::size_t i = 0; i < std::size (special); ++i)
    v[(i * 37 + seed) % v.size ()] = special[i];
  return v;
}

using pcl_texlet_test::readAll;

TEST_F (KinectDisparity, DepthIsTheClosedFormOfTheCalibration)
{
  const int w = 40, h = 30;
  write ("calibration.yml", herreraYaml ());
  // Written out of order: the reader sorts by name.
  const char *names[] = {"0002-d", "0000-d", "0001-d"};
  std::vector<std::vector<std::uint16_t>> written (3);
  for (int i = 0; i < 3; ++i)
  {
    const int index = names[i][3] - '0';
    written[index] = disparities (w, h, 100 + index);
    write (std::string (names[i]) + ".pgm", pgm (w, h, written[index]));
  }

  KinectDisparityReader reader (dir_.string ());
  ASSERT_EQ (reader.size (), 3u);
  const std::vector<DepthFrame> frames = readAll (reader);
  ASSERT_EQ (frames.size (), 3u);
  std::size_t valid = 0, invalid = 0;
  for (int f = 0; f < 3; ++f)
  {
    const DepthFrame &frame = frames[f];
    EXPECT_EQ (frame.name, "000" + std::to_string (f) + "-d");
    ASSERT_EQ (frame.width, w);
    ASSERT_EQ (frame.height, h);
    ASSERT_EQ (frame.depth_mm.size (), std::size_t (w) * h);
    EXPECT_TRUE (frame.rgb.empty ());
    for (std::size_t i = 0; i < frame.depth_mm.size (); ++i)
    {
      const std::uint16_t d = written[f][i];
      ASSERT_EQ (frame.depth_mm[i], closedFormMm (d)) << "frame " << f << " pixel " << i << " disparity " << d;
      if (frame.depth_mm[i] == 0)
      {
        ++invalid;
        continue;
      }
      ++valid;
      // Within half a millimetre (the storage resolution) of the exact depth.
      EXPECT_LE (std::fabs (frame.depth_mm[i] - 1000.0 / (kC0 + kC1 * d)), 0.5);
    }
  }
  // Per frame: 2047 twice, 4095, 65535, 1084 (533 m, beyond 16 bits), 1085, 1500 and 2046 (negative).
  EXPECT_EQ (invalid, 3u * 8u);
  EXPECT_EQ (valid, 3u * (w * h - 8u));

  // A few by hand: d = 760 is a metre, 2047 and the values the closed form has no depth for are 0.
  const auto at = [&] (std::uint16_t d) {
    write ("one/calibration.yml", herreraYaml ());
    write ("one/0000-d.pgm", pgm (1, 1, {d}));
    KinectDisparityReader one (file ("one"));
    DepthFrame frame;
    EXPECT_TRUE (one.next (frame));
    return frame.depth_mm.at (0);
  };
  fs::create_directories (file ("one"));
  EXPECT_EQ (at (760), 1003); // 1 / (3.3309495161 - 0.0030711016 * 760) = 1.003097 m
  EXPECT_EQ (at (400), 476);  // 0.475622 m
  EXPECT_EQ (at (0), 300);    // 1 / c0 = 0.300215 m
  EXPECT_EQ (at (2047), 0);
  EXPECT_EQ (at (2046), 0);   // negative depth
  EXPECT_EQ (at (1084), 0);   // 533 m, beyond 16-bit millimetres
  EXPECT_EQ (at (4095), 0);
}

TEST_F (KinectDisparity, IntrinsicsAndStepComeFromTheCalibration)
{
  write ("calibration.yml", herreraYaml ());
  write ("0000-d.pgm", pgm (8, 6, std::vector<std::uint16_t> (48, 700)));
  const KinectDisparityReader reader (dir_.string ());
  const CameraInfo &info = reader.cameraInfo ();
  const double K[9] = {585.5, 0, 318.25, 0, 583.75, 243.5, 0, 0, 1};
  for (int i = 0; i < 9; ++i)
    EXPECT_EQ (info.K[i], K[i]) << i; // dK, not the colour camera's rK1
  EXPECT_EQ (info.distortion_model, "plumb_bob");
  EXPECT_EQ (info.D, (std::vector<double>{-0.125, 0.25, 0.001, -0.002, 0.0}));
  EXPECT_EQ (info.width, 8); // from the first frame: the toolbox stores no depth image size
  EXPECT_EQ (info.height, 6);
  EXPECT_EQ (reader.calibration ().c0, kC0);
  EXPECT_EQ (reader.calibration ().c1, kC1);
  EXPECT_EQ (info.baseline_m, CameraInfo ().baseline_m);
  EXPECT_DOUBLE_EQ (info.disparity_subpixel, 585.5 * 0.075 * 0.0030711016); // about 1/8 px, the Kinect's step

  // The plain names, scalars c0 and c1, a size and a baseline; "calib.yaml", a "---" after %YAML:1.0.
  TempDir plain ("KinectDisparity_plain");
  plain.write ("calib.yaml", "%YAML:1.0\n---\nimage_width: 8\nimage_height: 6\n" + cvMatrix ("camera_matrix", 3, 3, kK) +
                                 "distortion_coefficients: [-0.125, 0.25, 0.001, -0.002]\nc0: 3.3309495161\n"
                                 "c1: -0.0030711016\nbaseline_m: 0.0757\n");
  plain.write ("a.pgm", pgm (8, 6, std::vector<std::uint16_t> (48, 760)));
  const KinectDisparityReader plain_reader (plain.path ().string ());
  EXPECT_EQ (plain_reader.cameraInfo ().fx (), 585.5);
  EXPECT_EQ (plain_reader.cameraInfo ().D, (std::vector<double>{-0.125, 0.25, 0.001, -0.002, 0.0}));
  EXPECT_EQ (plain_reader.cameraInfo ().baseline_m, 0.0757);
  EXPECT_DOUBLE_EQ (plain_reader.cameraInfo ().disparity_subpixel, 585.5 * 0.0757 * 0.0030711016);
  EXPECT_EQ (plain_reader.calibration ().c0, kC0);
  EXPECT_EQ (plain_reader.calibration ().c1, kC1);

  // depth_calibration = [c0 c1], K without a tag (ROS-like map), no distortion at all.
  const fs::path other = plain.path () / "other.yml";
  std::ofstream (other) << "K: {rows: 3, cols: 3, data: [" << kK << "]}\ndepth_calibration: [3.3309495161, -0.0030711016]\n";
  const KinectDisparityCalibration c = loadKinectDisparityCalibration (other.string ());
  EXPECT_EQ (c.c0, kC0);
  EXPECT_EQ (c.c1, kC1);
  EXPECT_EQ (c.info.K[5], 243.5);
  EXPECT_EQ (c.info.D, std::vector<double> (5, 0.0));
  EXPECT_EQ (c.info.width, 0); // no size: the reader takes the first frame's
}

TEST_F (KinectDisparity, LittleEndianAndMaxval2047FramesReadAsTheToolboxReadsThem)
{
  const int w = 16, h = 12;
  const std::vector<std::uint16_t> d = disparities (w, h, 7);
  write ("calibration.yml", herreraYaml ());
  write ("0000-d.pgm", pgm (w, h, d));                    // big-endian, as the PGM specification says
  write ("0001-d.pgm", pgm (w, h, d, 65535, true));       // libfreenect's recorder: host order
  write ("0002-d.pgm", pgm (w, h, d, 2047));              // maxval 2047
  KinectDisparityReader reader (dir_.string ());
  const std::vector<DepthFrame> frames = readAll (reader);
  ASSERT_EQ (frames.size (), 3u);
  EXPECT_EQ (frames[1].depth_mm, frames[0].depth_mm);
  EXPECT_EQ (frames[2].depth_mm, frames[0].depth_mm);
  for (std::size_t i = 0; i < d.size (); ++i)
    EXPECT_EQ (frames[0].depth_mm[i], closedFormMm (d[i]));

  // readPgm16 itself keeps the samples as stored.
  int pw = 0, ph = 0;
  EXPECT_EQ (readPgm16 (file ("0000-d.pgm"), pw, ph), d);
  EXPECT_EQ (pw, w);
  EXPECT_EQ (ph, h);
}

TEST_F (KinectDisparity, HerreraDisparityDistortionIsCorrected)
{
  // d' = d + beta(u, v) exp (alpha0 - alpha1 d), as the toolbox's undistort_disparity.
  const double a0 = 1.5, a1 = 0.002;
  const std::vector<double> beta = {0.0, 2.5, -3.0, 4.0, 0.75, -1.25};
  write ("calibration.yml", herreraYaml (cvMatrix ("dc_alpha", 1, 2, "1.5, 0.002") +
                                         cvMatrix ("dc_beta", 2, 3, "0., 2.5, -3., 4., 0.75, -1.25")));
  const std::vector<std::uint16_t> d = {700, 800, 900, 2047, 650, 1000};
  write ("0000-d.pgm", pgm (3, 2, d));
  KinectDisparityReader reader (dir_.string ());
  DepthFrame frame;
  ASSERT_TRUE (reader.next (frame));
  for (std::size_t i = 0; i < d.size (); ++i)
  {
    if (d[i] == 2047)
    {
      EXPECT_EQ (frame.depth_mm[i], 0);
      continue;
    }
    const double corrected = d[i] + beta[i] * std::exp (a0 - a1 * d[i]);
    EXPECT_EQ (frame.depth_mm[i], static_cast<std::uint16_t> (std::lround (1000.0 / (kC0 + kC1 * corrected)))) << i;
  }
  EXPECT_EQ (frame.depth_mm[0], closedFormMm (700)); // beta 0: no correction
  EXPECT_NE (frame.depth_mm[1], closedFormMm (800));

  // dc_beta must have the frames' size.
  write ("0000-d.pgm", pgm (4, 2, std::vector<std::uint16_t> (8, 700)));
  expectError ([&] { KinectDisparityReader r (dir_.string ()); }, {file ("calibration.yml"), "dc_beta is 2x3", "4x2"});
}

TEST_F (KinectDisparity, OpenRecordingRecognisesTheFolder)
{
  write ("calibration.yml", herreraYaml ());
  write ("0000-d.pgm", pgm (4, 3, std::vector<std::uint16_t> (12, 760)));
  write ("0001-d.pgm", pgm (4, 3, std::vector<std::uint16_t> (12, 2047)));
  // The toolbox's colour images beside them are not frames (8-bit, and named -c1).
  write ("0000-c1.pgm", "P5\n4 3\n255\n" + std::string (12, '\x80'));
  EXPECT_EQ (recordingKind (dir_.string ()), RecordingKind::kinect_disparity_folder);
  const RecordingReader::Ptr reader = openRecording (dir_.string ());
  ASSERT_NE (dynamic_cast<KinectDisparityReader *> (reader.get ()), nullptr);
  EXPECT_EQ (reader->size (), 2u);
  const std::vector<DepthFrame> frames = readAll (*reader);
  ASSERT_EQ (frames.size (), 2u);
  EXPECT_EQ (frames[0].depth_mm, std::vector<std::uint16_t> (12, 1003));
  EXPECT_EQ (frames[1].depth_mm, std::vector<std::uint16_t> (12, 0));

  // Either half is recognised, so that the reader names the other.
  TempDir frames_only ("KinectDisparity_frames_only");
  frames_only.write ("a.pgm", pgm (4, 3, std::vector<std::uint16_t> (12, 760)));
  EXPECT_EQ (recordingKind (frames_only.path ().string ()), RecordingKind::kinect_disparity_folder);
  expectError ([&] { openRecording (frames_only.path ().string ()); },
               {frames_only.path ().string (), "no calibration file", "calibration.yml"});
  TempDir calibration_only ("KinectDisparity_calibration_only");
  calibration_only.write ("calib.yml", herreraYaml ());
  EXPECT_EQ (recordingKind (calibration_only.path ().string ()), RecordingKind::kinect_disparity_folder);
  expectError ([&] { openRecording (calibration_only.path ().string ()); },
               {calibration_only.path ().string (), "holds no raw disparity frames (*.pgm)"});
  // An empty folder is none, and no folder at all is named.
  TempDir empty ("KinectDisparity_empty");
  expectError ([&] { openRecording (empty.path ().string ()); }, {empty.path ().string (), "is empty"});
  expectError ([&] { KinectDisparityReader r (empty.path ().string ()); }, {empty.path ().string (), "no calibration file"});
  expectError ([&] { KinectDisparityReader r (file ("absent")); }, {file ("absent"), "does not exist"});
  // An explicit calibration file elsewhere.
  const KinectDisparityReader explicit_calibration (frames_only.path ().string (), file ("calibration.yml"));
  EXPECT_EQ (explicit_calibration.size (), 1u);
}

TEST_F (KinectDisparity, BadCalibrationsNameTheFileAndTheProblem)
{
  write ("0000-d.pgm", pgm (2, 2, {700, 700, 700, 700}));
  const std::string yml = file ("calibration.yml");
  const auto expectBad = [&] (const std::string &text, std::initializer_list<std::string> needles) {
    write ("calibration.yml", text);
    std::vector<std::string> all (needles);
    all.push_back (yml);
    try
    {
      KinectDisparityReader reader (dir_.string ());
      ADD_FAILURE () << "accepted: " << text;
    }
    catch (const pcl::IOException &e)
    {
      for (const std::string &needle : all)
        EXPECT_NE (std::string (e.what ()).find (needle), std::string::npos) << "'" << needle << "' not in: " << e.what ();
    }
  };
  const std::string k = cvMatrix ("dK", 3, 3, kK);
  const std::string dc = cvMatrix ("dc", 1, 2, "3.3309495161, -0.0030711016");

  expectError ([&] { loadKinectDisparityCalibration (file ("absent.yml")); }, {file ("absent.yml"), "does not exist"});
  expectBad ("%YAML:1.0\n\ndK: [1, 2\n", {"not valid YAML (line 4"}); // counted in the file, %YAML line included
  expectBad ("%YAML:1.0\n- 1\n- 2\n", {"not a YAML map"});
  expectBad ("%YAML:1.0\n" + dc, {"missing the depth camera matrix", "'dK'", "'camera_matrix'", "'K'"});
  expectBad ("%YAML:1.0\n" + k, {"missing the depth calibration", "'dc'", "'c0'", "'c1'"});
  expectBad ("%YAML:1.0\n" + k + "c0: 3.33\n", {"missing the depth calibration", "missing 'c1'"});
  expectBad ("%YAML:1.0\n" + k + "c1: -0.003\n", {"missing 'c0'"});
  expectBad ("%YAML:1.0\n" + k + "c0: 3.33\nc1: 0\n", {"c1 is 0"});
  expectBad ("%YAML:1.0\n" + k + cvMatrix ("dc", 1, 2, "3.33, 0."), {"dc = [c0 c1]", "c1 is 0"});
  expectBad ("%YAML:1.0\n" + k + "c0: 3.33\nc1: .nan\n", {"c0, c1 must be finite"});
  expectBad ("%YAML:1.0\n" + k + "c0: .inf\nc1: -0.003\n", {"must be finite"});
  expectBad ("%YAML:1.0\n" + k + "c0: 1e400\nc1: -0.003\n", {"c0 must be a number", "1e400"});
  expectBad ("%YAML:1.0\n" + k + "c0: three\nc1: -0.003\n", {"c0 must be a number", "three"});
  expectBad ("%YAML:1.0\n" + k + cvMatrix ("dc", 1, 2, "3.33, .nan"), {"dc.data[1] must be finite"});
  expectBad ("%YAML:1.0\n" + k + cvMatrix ("dc", 1, 3, "3.33, -0.003, 1."), {"dc must be 2 numbers"});
  expectBad ("%YAML:1.0\n" + k + cvMatrix ("dc", 1, 3, "3.33, -0.003"), {"dc is declared 1x3", "has 2 numbers"});
  expectBad ("%YAML:1.0\n" + k + dc + "c0: 3.33\nc1: -0.003\n", {"both 'dc' and c0/c1"});
  expectBad ("%YAML:1.0\n" + k + cvMatrix ("K", 3, 3, kK) + dc, {"both 'dK' and 'K'"});
  expectBad ("%YAML:1.0\n" + cvMatrix ("dK", 2, 2, "1., 0., 0., 1.") + dc, {"dK must be a 3x3 matrix"});
  expectBad ("%YAML:1.0\n" + cvMatrix ("dK", 3, 3, "-585., 0., 320., 0., 585., 240., 0., 0., 1.") + dc,
             {"focal lengths fx and fy must be positive"});
  expectBad ("%YAML:1.0\ndK: 585\n" + dc, {"dK must be a matrix"});
  expectBad ("%YAML:1.0\n" + k + dc + cvMatrix ("dkc", 1, 8, "0.1, 0., 0., 0., 0., 0.5, 0., 0."),
             {"dkc has 8 coefficients", "plumb_bob"});
  expectBad ("%YAML:1.0\n" + k + dc + cvMatrix ("dkc", 1, 2, "0.1, 0."), {"dkc must be a row of 4 or 5"});
  expectBad ("%YAML:1.0\n" + k + dc + cvMatrix ("dc_alpha", 1, 2, "1., 0.1"), {"'dc_alpha' without 'dc_beta'"});
  expectBad ("%YAML:1.0\n" + k + dc + "image_width: 2\n", {"'image_width' without 'image_height'"});
  expectBad ("%YAML:1.0\n" + k + dc + "image_width: 2\nimage_height: -2\n", {"image_width and image_height must be"});
  expectBad ("%YAML:1.0\n" + k + dc + "baseline_m: 0\n", {"baseline_m must be positive"});

  // A calibration size the frames do not have is the frames' error, when they are read.
  write ("calibration.yml", "%YAML:1.0\n" + k + dc + "image_width: 640\nimage_height: 480\n");
  KinectDisparityReader reader (dir_.string ());
  DepthFrame frame;
  expectError ([&] { reader.next (frame); }, {file ("0000-d.pgm"), "is 2x2 but the calibration says 640x480", yml});
}

TEST_F (KinectDisparity, BadFramesAreNamedAndSkippedPast)
{
  write ("calibration.yml", herreraYaml ());
  const std::vector<std::uint16_t> good (12, 760);
  const std::string ok = pgm (4, 3, good);
  write ("00-d.pgm", ok);
  write ("01-d.pgm", "P2\n4 3\n2047\n760 760 760 760 760 760 760 760 760 760 760 760\n");
  write ("02-d.pgm", "P5\n4 3\n255\n" + std::string (12, '\x10'));
  write ("03-d.pgm", ok.substr (0, ok.size () - 5));
  write ("04-d.pgm", pgm (5, 3, std::vector<std::uint16_t> (15, 760)));
  write ("05-d.pgm", "not an image at all\n");
  write ("06-d.pgm", "P5\n100000 100000\n65535\n");
  write ("07-d.pgm", "P5\n4 3\n");
  write ("08-d.pgm", "");
  write ("09-d.pgm", "P6\n4 3\n255\n" + std::string (36, '\x10'));
  write ("10-d.pgm", ok);

  KinectDisparityReader reader (dir_.string ());
  ASSERT_EQ (reader.size (), 11u);
  DepthFrame frame;
  ASSERT_TRUE (reader.next (frame));
  EXPECT_EQ (frame.depth_mm, std::vector<std::uint16_t> (12, 1003));
  const auto bad = [&] (const std::string &name, std::initializer_list<std::string> needles) {
    std::vector<std::string> all (needles);
    all.push_back (file (name));
    try
    {
      reader.next (frame);
      ADD_FAILURE () << name << " was read";
    }
    catch (const pcl::IOException &e)
    {
      for (const std::string &needle : all)
        EXPECT_NE (std::string (e.what ()).find (needle), std::string::npos) << "'" << needle << "' not in: " << e.what ();
    }
  };
  bad ("01-d.pgm", {"not a binary grey PGM", "'P2'", "expected 'P5'"});
  bad ("02-d.pgm", {"8-bit PGM (maxval 255)"});
  bad ("03-d.pgm", {"truncated", "needs 24 bytes of pixel data, found 19"});
  bad ("04-d.pgm", {"raw disparity PGM", "is 5x3 but the first frame", "is 4x3"});
  bad ("05-d.pgm", {"not a PGM file"});
  bad ("06-d.pgm", {"100000x100000 beyond 16384"});
  bad ("07-d.pgm", {"header ends before its maxval"});
  bad ("08-d.pgm", {"not a PGM file"});
  bad ("09-d.pgm", {"'P6'"});
  // Every bad frame was moved past: the last, good one is still read.
  ASSERT_TRUE (reader.next (frame));
  EXPECT_EQ (frame.name, "10-d");
  EXPECT_EQ (frame.depth_mm, std::vector<std::uint16_t> (12, 1003));
  EXPECT_FALSE (reader.next (frame));

  // FrameSkippingReader passes over them and counts them.
  FrameSkippingReader skipping (std::make_shared<KinectDisparityReader> (dir_.string ()));
  EXPECT_EQ (readAll (skipping).size (), 2u);
  EXPECT_EQ (skipping.skipped (), 9u);

  // A bad first frame is the recording's error when it gives the size.
  TempDir first ("KinectDisparity_bad_first");
  first.write ("calibration.yml", herreraYaml ());
  first.write ("0000-d.pgm", "P5\n4 3\n255\n" + std::string (12, '\x10'));
  expectError ([&] { KinectDisparityReader r (first.path ().string ()); }, {first.file ("0000-d.pgm"), "8-bit PGM"});
}

} // namespace
