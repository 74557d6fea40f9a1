/*
 * pcl_texlet_sensor_figures end to end: on a small image it writes every data file of
 * docs/sensor_model.md's figures, and the values in them show each effect as its closed form
 * says (checked here independently of the app: the depth lattice from f b and the 1/8 px step,
 * the drift from the exponential, the shadow width from the disparity jump); bad input exits 2
 * with one line on stderr.
 */
#include <gtest/gtest.h>

#include "support/app_run.h"
#include "support/temp_dir.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace
{

// The app's image: Kinect v1 focal length scaled with the width, 7.5 cm baseline.
const int kWidth = 160, kHeight = 120, kFrames = 12;
const double kF = 580.0 * kWidth / 640.0, kB = 0.075, kFb = kF * kB, kStep = 0.125;

using pcl_texlet_test::slurp;
using Result = pcl_texlet_test::AppResult;

/** Rows of numbers of a data file ('#' lines skipped, blank lines skipped, NaN kept). */
std::vector<std::vector<double>>
table (const fs::path &p)
{
  std::vector<std::vector<double>> rows;
  std::istringstream in (slurp (p));
  std::string line;
  while (std::getline (in, line))
  {
    if (line.empty () || line[0] == '#')
      continue;
    std::istringstream ls (line);
    std::vector<double> row;
    std::string word;
    while (ls >> word)
      row.push_back (word == "NaN" ? std::nan ("") : std::stod (word));
    rows.push_back (row);
  }
  return rows;
}

/** summary.txt as a map. */
std::map<std::string, double>
summary (const fs::path &p)
{
  std::map<std::string, double> m;
  std::istringstream in (slurp (p));
  std::string line;
  while (std::getline (in, line))
  {
    const auto eq = line.find (" = ");
    if (line.empty () || line[0] == '#' || eq == std::string::npos)
      continue;
    m[line.substr (0, eq)] = std::stod (line.substr (eq + 3));
  }
  return m;
}

double
sd (const std::vector<double> &v)
{
  double m = 0;
  for (const double x : v)
    m += x;
  m /= v.size ();
  double s = 0;
  for (const double x : v)
    s += (x - m) * (x - m);
  return std::sqrt (s / (v.size () - 1));
}

class SensorFiguresApp : public ::testing::Test
{
protected:
  static const fs::path &
  root () { return temp_->path (); }

  static Result
  run (const std::string &args) { return pcl_texlet_test::runApp (FIGURES_APP, args, root ()); }

  /** One run of every figure, shared by the tests of its values. */
  static void
  SetUpTestSuite ()
  {
    temp_ = std::make_unique<pcl_texlet_test::TempDir> ("sensor_figures");
    const Result r = run ((root () / "data").string () + " --width " + std::to_string (kWidth) + " --height " +
                          std::to_string (kHeight) + " --frames " + std::to_string (kFrames) + " --seed 3 -q");
    code_ = r.code;
    err_ = r.err;
  }

  static void
  TearDownTestSuite () { temp_.reset (); }

  static fs::path
  data (const std::string &file) { return root () / "data" / file; }

  static std::unique_ptr<pcl_texlet_test::TempDir> temp_;
  static int code_;
  static std::string err_;
};

std::unique_ptr<pcl_texlet_test::TempDir> SensorFiguresApp::temp_;
int SensorFiguresApp::code_ = -1;
std::string SensorFiguresApp::err_;

TEST_F (SensorFiguresApp, WritesEveryDataFileAndNoTemporaryOne)
{
  ASSERT_EQ (code_, 0) << err_;
  for (const char *f :
       {"base_noise_radius.dat", "base_noise_map.dat", "projector_shadows.dat", "projector_shadows_row_on.dat",
        "projector_shadows_row_off.dat", "axial_quadratic.dat", "radial.dat", "disparity_quantization_hist.dat",
        "disparity_quantization_lattice.dat", "disparity_quantization_staircase.dat", "incidence_angle.dat",
        "vertical_stripes_profile.dat", "vertical_stripes_map.dat", "depth_distortion_map.dat",
        "depth_distortion_model_map.dat", "depth_distortion_row.dat", "interference.dat",
        "interference_holes_map.dat", "temporal_drift.dat", "lateral_noise.dat", "lateral_noise_crop.dat",
        "intrinsics_row.dat", "intrinsics_tilt.dat", "summary.txt"})
    EXPECT_TRUE (fs::is_regular_file (data (f))) << f;
  EXPECT_EQ (pcl_texlet_test::temporariesIn (root () / "data"), std::vector<std::string> ());
  EXPECT_EQ (pcl_texlet_test::temporariesIn (root ()), std::vector<std::string> ());
}

TEST_F (SensorFiguresApp, QuantisedDepthsLieOnTheDisparityLattice)
{
  ASSERT_EQ (code_, 0) << err_;
  const auto hist = table (data ("disparity_quantization_hist.dat"));
  ASSERT_FALSE (hist.empty ());
  int base_values = 0, quantised_values = 0;
  double quantised_total = 0;
  for (const auto &row : hist)
  {
    ASSERT_EQ (row.size (), 3u);
    base_values += row[1] > 0 ? 1 : 0;
    if (row[2] > 0)
    {
      // Reported depth = round(1000 f b / (k step)) for a whole k.
      const double k = std::round (kFb / (1e-3 * row[0] * kStep));
      EXPECT_NEAR (row[0], std::round (1000.0 * kFb / (k * kStep)), 0.5) << row[0];
      ++quantised_values;
      quantised_total += row[2];
    }
  }
  EXPECT_NEAR (quantised_total, 1.0, 1e-3);
  // 1.5 m lies exactly on the lattice (f b / 1.5 = 29/4 px = 58 steps), so the steps here (z^2 step
  // / (f b) = 26 mm) swallow the ~1 mm base noise: one value, against several without.
  EXPECT_EQ (quantised_values, 1);
  EXPECT_GE (base_values, 4);
}

TEST_F (SensorFiguresApp, StripesSpreadTheColumnMeans)
{
  ASSERT_EQ (code_, 0) << err_;
  const auto rows = table (data ("vertical_stripes_profile.dat"));
  ASSERT_EQ (rows.size (), static_cast<std::size_t> (kWidth));
  std::vector<double> base, stripes;
  double largest_jump = 0, largest_base_jump = 0;
  for (std::size_t u = 0; u < rows.size (); ++u)
  {
    base.push_back (rows[u][1]);
    stripes.push_back (rows[u][2]);
    if (u > 0)
    {
      largest_jump = std::max (largest_jump, std::fabs (rows[u][2] - rows[u - 1][2]));
      largest_base_jump = std::max (largest_base_jump, std::fabs (rows[u][1] - rows[u - 1][1]));
    }
  }
  // Bands of offset SD 1/8 px (26 mm at 1.5 m here) against column means of ~1 mm noise over 120 rows.
  EXPECT_GT (sd (stripes), 10 * sd (base));
  EXPECT_GT (largest_jump, 10 * largest_base_jump);
}

TEST_F (SensorFiguresApp, DriftFollowsItsExponentialAndBaseHasNone)
{
  ASSERT_EQ (code_, 0) << err_;
  const auto rows = table (data ("temporal_drift.dat"));
  ASSERT_EQ (rows.size (), static_cast<std::size_t> (kFrames));
  for (const auto &row : rows)
  {
    const double offset = 0.2 * std::exp (-row[0] / 10.0);
    const double expected = 1000.0 * (kFb / (kFb / 1.5 + offset) - 1.5);
    EXPECT_NEAR (row[2], expected, 0.3) << "frame " << row[0];
    EXPECT_NEAR (row[1], 0.0, 0.3) << "frame " << row[0];
  }
}

TEST_F (SensorFiguresApp, ShadowsAreAsWideAsTheDisparityJumpAndGoneWithout)
{
  ASSERT_EQ (code_, 0) << err_;
  const auto rows = table (data ("projector_shadows.dat"));
  ASSERT_EQ (rows.size (), 5u);
  for (const auto &row : rows)
    // The shadow covers the pixel centres inside a band f b (1/z_front - 1/z_back) px wide.
    EXPECT_NEAR (row[1], kFb * (1 / 1.5 - 1 / row[0]), 1.0) << "wall at " << row[0] << " m";
  const auto s = summary (data ("summary.txt"));
  EXPECT_EQ (s.at ("projector_shadows.width_px_without_shadows_at_3m"), 0.0);
}

TEST_F (SensorFiguresApp, EffectsChangeWhatTheyShouldAndNothingElse)
{
  ASSERT_EQ (code_, 0) << err_;
  const auto s = summary (data ("summary.txt"));
  // Interference: no holes with one projector, more with each added one.
  EXPECT_EQ (s.at ("interference.holes_on_1_projectors"), 0.0);
  EXPECT_GT (s.at ("interference.holes_on_2_projectors"), 0.03);
  EXPECT_GT (s.at ("interference.holes_on_3_projectors"), s.at ("interference.holes_on_2_projectors"));
  EXPECT_EQ (s.at ("interference.holes_off_3_projectors"), 0.0);
  // Lateral noise moves edges and leaves every pixel away from them as it was.
  EXPECT_EQ (s.at ("lateral_noise.edge_position_sd_base_px"), 0.0);
  EXPECT_GT (s.at ("lateral_noise.edge_position_sd_lateral_px"), 0.3);
  EXPECT_EQ (s.at ("lateral_noise.pixels_changed_away_from_edge"), 0.0);
  EXPECT_GT (s.at ("lateral_noise.pixels_compared_away_from_edge"), 0.0);
  // Labelled focal length 1.088 x: a 45 degree wall fits at atan(1.088) = 47.41 degrees.
  EXPECT_NEAR (s.at ("intrinsics.fitted_tilt_labelled_deg_at_45"), 47.41, 0.1);
  EXPECT_NEAR (s.at ("intrinsics.fitted_tilt_true_deg_at_45"), 45.0, 0.1);
  // The axial term at 2 m: 0.02 px x 4 m^2 / (f b).
  EXPECT_NEAR (s.at ("axial_quadratic.axial_term_mm_at_2m"), 1000 * 0.02 * 4 / kFb, 0.01);
  EXPECT_GT (s.at ("axial_quadratic.sd_axial_mm_at_2m"), 2 * s.at ("axial_quadratic.sd_base_mm_at_2m"));
}

TEST_F (SensorFiguresApp, BadInputExitsTwoWithOneLine)
{
  const std::string out = (root () / "bad").string ();
  for (const std::string args : {out + " --width 0", out + " --frames 1", out + " --only nonsense", std::string (""),
                                 out + " --threads 5000", (root () / "no" / "such" / "folder").string ()})
  {
    const Result r = run (args);
    EXPECT_EQ (r.code, 2) << args;
    EXPECT_EQ (std::count (r.err.begin (), r.err.end (), '\n'), 1) << args << ": " << r.err;
    EXPECT_NE (r.err.find ("pcl_texlet_sensor_figures: error:"), std::string::npos) << r.err;
  }
  EXPECT_FALSE (fs::exists (root () / "bad"));
  // A file where the folder should be.
  std::ofstream (root () / "a_file") << "x";
  const Result r = run ((root () / "a_file").string ());
  EXPECT_EQ (r.code, 2);
  EXPECT_NE (r.err.find ("is not a folder"), std::string::npos) << r.err;
}

} // namespace
