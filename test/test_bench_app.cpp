/*
 * pcl_texlet_bench: the benchmark's figures on small simulated scenes are checked against the
 * scenes' ground truth and against each other (no timing is asserted: times are only
 * required to be there); bad input exits 2 with one line.
 */
#include <pcl_texlet/kernels/hex_grid.h>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include "support/app_run.h"
#include "support/temp_dir.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using nlohmann::json;

namespace
{

using Result = pcl_texlet_test::AppResult;
using pcl_texlet_test::slurp;

Result
runBench (const fs::path &dir, const std::string &args)
{
  return pcl_texlet_test::runApp (BENCH_APP, args, dir);
}

/** One run of the whole tool on a 160x120 simulated plane, shared by the tests below. */
class BenchOnSimulatedScenes : public ::testing::Test
{
protected:
  static void
  SetUpTestSuite ()
  {
    temp_ = std::make_unique<pcl_texlet_test::TempDir> ("bench_scenes");
    dir_ = temp_->path ();
    const Result r = runBench (dir_, "--scene plane --width 160 --height 120 --repetitions 2 --warmup 1 -n 5 "
                                     "--fig8 --fig8-runs 4 -q --json " + (dir_ / "bench.json").string () +
                                     " --data-dir " + dir_.string ());
    code_ = r.code;
    stdout_ = r.out;
    stderr_ = r.err;
    if (r.code == 0)
      j_ = json::parse (slurp (dir_ / "bench.json"));
  }

  static void
  TearDownTestSuite () { temp_.reset (); }

  void
  SetUp () override { ASSERT_EQ (code_, 0) << stderr_; }

  static const json &
  method (const json &list, const std::string &name)
  {
    for (const auto &m : list)
      if (m["name"] == name)
        return m;
    ADD_FAILURE () << "no method " << name;
    static const json none;
    return none;
  }

  static inline std::unique_ptr<pcl_texlet_test::TempDir> temp_;
  static inline fs::path dir_;
  static inline int code_ = -1;
  static inline std::string stdout_, stderr_;
  static inline json j_;
};

TEST_F (BenchOnSimulatedScenes, EveryMethodIsTimedAtTheSameHexagonalCentres)
{
  const auto grid = pcl::texlet::kernels::makeHexGrid (160, 120, 6);
  const json &t = j_["timing"];
  EXPECT_EQ (t["centres"].get<int> (), grid.size ());
  // 3 uncertainties x 3 fits of ours, then NormalEstimationOMP twice and the integral image twice.
  ASSERT_EQ (t["methods"].size (), 13u);
  std::set<std::string> names;
  for (const auto &m : t["methods"])
  {
    names.insert (m["name"].get<std::string> ());
    EXPECT_EQ (m["centres"].get<int> (), grid.size ()) << m["name"];
    EXPECT_GT (m["normals"].get<int> (), grid.size () / 2) << m["name"];
    EXPECT_LE (m["normals"].get<int> (), grid.size ()) << m["name"];
    EXPECT_EQ (m["times_ms"].size (), 2u) << m["name"];
    EXPECT_GT (m["time_ms"]["median"].get<double> (), 0.0) << m["name"];
    EXPECT_LE (m["time_ms"]["min"].get<double> (), m["time_ms"]["max"].get<double> ()) << m["name"];
    EXPECT_GT (m["ratio_to_reference"].get<double> (), 0.0) << m["name"];
    EXPECT_GT (m["cpu_time_ms"]["median"].get<double> (), 0.0) << m["name"];
    EXPECT_GT (m["cpu_ratio_to_reference"].get<double> (), 0.0) << m["name"];
  }
  EXPECT_EQ (names.size (), 13u);
  for (const char *n : {"texlet/none/pca", "texlet/analytic/svd", "texlet/montecarlo/averaging", "pcl/ne_omp_disc",
                        "pcl/ne_omp_organized_knn", "pcl/integral_covariance", "pcl/integral_average_3d_gradient"})
    EXPECT_EQ (names.count (n), 1u) << n;
  EXPECT_EQ (t["reference"], "pcl/ne_omp_disc");
  EXPECT_DOUBLE_EQ (method (t["methods"], "pcl/ne_omp_disc")["ratio_to_reference"].get<double> (), 1.0);
  EXPECT_DOUBLE_EQ (method (t["methods"], "pcl/ne_omp_disc")["cpu_ratio_to_reference"].get<double> (), 1.0);
  ASSERT_EQ (t["targets"].size (), 3u);
  // PCL's estimators use every neighbour; RANSAC keeps most of a plane's points.
  EXPECT_DOUBLE_EQ (method (t["methods"], "pcl/ne_omp_disc")["inlier_share"].get<double> (), 1.0);
  const double share = method (t["methods"], "texlet/none/pca")["inlier_share"].get<double> ();
  EXPECT_GT (share, 0.6);
  EXPECT_LE (share, 1.0);
  EXPECT_TRUE (method (t["methods"], "pcl/integral_covariance")["inlier_share"].is_null ());
}

TEST_F (BenchOnSimulatedScenes, NormalEstimationOmpSeesExactlyTheTexletNeighbourhood)
{
  const json &c = j_["timing"]["neighbourhood_check"];
  const int n = c["centres"].get<int> ();
  EXPECT_EQ (c["support_equal"].get<int> (), n);
  EXPECT_EQ (c["centre_equal"].get<int> (), n);
  EXPECT_GT (c["compared"].get<int> (), n / 2);
  // The same points give the same plane: float (PCL) against double (ours) rounding only.
  EXPECT_LT (c["median_angle_deg"].get<double> (), 1e-3);
  EXPECT_LT (c["p99_angle_deg"].get<double> (), 0.05);
}

TEST_F (BenchOnSimulatedScenes, AccuracyAgainstGroundTruthIsSane)
{
  const json &a = j_["accuracy"];
  ASSERT_EQ (a["scenes"].size (), 3u);
  const json &plane = a["scenes"][0];
  ASSERT_EQ (plane["name"], "plane");
  EXPECT_EQ (plane["near_edge_centres"].get<int> (), 0); // an infinite wall fills the image
  for (const auto &m : plane["methods"])
  {
    const double mean = m["all"]["mean_deg"].get<double> (), p95 = m["all"]["p95_deg"].get<double> ();
    // The paper's noise is about 1 mm at 1.2 m; a 113-pixel patch sees a few tenths of a degree.
    EXPECT_GT (mean, 0.0) << m["name"];
    EXPECT_LT (mean, 3.0) << m["name"];
    EXPECT_LT (p95, 6.0) << m["name"];
    EXPECT_GE (p95, mean) << m["name"];
  }
  EXPECT_LT (method (plane["methods"], "texlet/none/pca")["all"]["mean_deg"].get<double> (), 1.0);
  // The uncertainty method does not change the normal.
  EXPECT_EQ (method (plane["methods"], "texlet/none/svd")["all"], method (plane["methods"], "texlet/montecarlo/svd")["all"]);
  // Normal averaging uses 7 points, PCA 113: averaging is worse (the paper's Fig. 8).
  EXPECT_GT (method (plane["methods"], "texlet/none/averaging")["all"]["mean_deg"].get<double> (),
             method (plane["methods"], "texlet/none/pca")["all"]["mean_deg"].get<double> ());

  // At the box's edges RANSAC keeps one surface; a plain fit over the disc mixes both.
  const json &box = a["scenes"][2];
  ASSERT_EQ (box["name"], "box");
  EXPECT_GT (box["near_edge_centres"].get<int> (), 20);
  const double ours = method (box["methods"], "texlet/none/pca")["near_edges"]["mean_deg"].get<double> ();
  const double pcl_disc = method (box["methods"], "pcl/ne_omp_disc")["near_edges"]["mean_deg"].get<double> ();
  EXPECT_LT (ours, pcl_disc);
  EXPECT_EQ (a["overall"].size (), 13u);
}

TEST_F (BenchOnSimulatedScenes, Fig8PcaMatchesSvdAndAveragingIsWorse)
{
  const json &levels = j_["fig8"]["levels"];
  ASSERT_GE (levels.size (), 3u);
  // No noise: every fit recovers the plane.
  for (const char *f : {"averaging", "pca", "svd"})
    EXPECT_LT (levels[0][f]["mean_deg"].get<double> (), 0.01) << f;
  for (const auto &l : levels)
  {
    const double sigma = l["sigma_mm"].get<double> ();
    if (sigma <= 0.0 || sigma > 2.0)
      continue;
    const double pca = l["pca"]["mean_deg"].get<double> (), svd = l["svd"]["mean_deg"].get<double> ();
    EXPECT_NEAR (pca, svd, 1e-3 * pca) << sigma;
    EXPECT_GT (l["averaging"]["mean_deg"].get<double> (), 1.5 * pca) << sigma;
    EXPECT_GT (l["pca"]["var_deg2"].get<double> (), 0.0) << sigma;
  }
  EXPECT_TRUE (fs::exists (dir_ / "fig8.dat"));
  EXPECT_TRUE (fs::exists (dir_ / "timing.dat"));
}

class BenchBadInput : public pcl_texlet_test::TempDirTest
{
protected:
  void
  expectRejected (const std::string &args, const std::string &needle)
  {
    const fs::path out = dir_ / "out.json";
    const Result r = runBench (dir_, args + " -q --no-accuracy --json " + out.string ());
    EXPECT_EQ (r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ (std::count (r.err.begin (), r.err.end (), '\n'), 1) << r.err;
    EXPECT_NE (r.err.find (needle), std::string::npos) << "stderr: " << r.err << " should mention " << needle;
    EXPECT_FALSE (fs::exists (out));
  }
};

TEST_F (BenchBadInput, MissingCorruptOrUnorganisedInput)
{
  expectRejected ((dir_ / "nothing.pcd").string (), "does not exist");
  std::ofstream (dir_ / "garbage.pcd") << "this is not a point cloud\n";
  expectRejected ((dir_ / "garbage.pcd").string (), "garbage.pcd");
  pcl::PointCloud<pcl::PointXYZ> flat;
  for (int i = 0; i < 50; ++i)
    flat.push_back (pcl::PointXYZ (0.01f * i, 0.0f, 1.0f));
  pcl::io::savePCDFileBinary ((dir_ / "flat.pcd").string (), flat);
  expectRejected ((dir_ / "flat.pcd").string (), "not an organised cloud");
}

TEST_F (BenchBadInput, BadOptions)
{
  expectRejected ("--scene teapot", "teapot");
  expectRejected ("--scene plane --threads 0", "--threads");
  expectRejected ("--scene plane --spacing 1", "spacing");
  expectRejected ("--scene plane --radius 0", "radius");
  expectRejected ("--scene plane --repetitions 0", "repetitions");
  expectRejected ("--scene plane --fits lsq", "lsq");
  expectRejected ("--scene plane --width 8", "--width");
  expectRejected ("--scene plane --data-dir " + (dir_ / "no_such_folder").string (), "no_such_folder");
  expectRejected ("--scene plane --noise-model " + (dir_ / "no_model.yaml").string (), "no_model.yaml");
  std::ofstream (dir_ / "bad_model.yaml") << "terms:\n  - name: spatial_correlation\n    parameters: {share: 1}\n";
  expectRejected ("--scene plane --noise-model " + (dir_ / "bad_model.yaml").string (), "bad_model.yaml");
}

} // namespace
