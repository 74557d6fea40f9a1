/*
 * pcl_texlet_interference end to end: the simulated study's histograms, inlier table and HTML
 * report; recordings written by pcl_texlet_sim read back with meta.yaml poses or an extrinsics
 * file; bad input (exit code 2, one line on stderr, no output left behind).
 */
#include <pcl_texlet/relations/extrinsics.h>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include "support/app_test.h"
#include "support/temp_dir.h"

#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using nlohmann::json;

namespace
{

using pcl_texlet_test::slurp;

bool
isPng (const fs::path &p)
{
  const std::string bytes = slurp (p);
  return bytes.size () > 1000 && bytes.compare (0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

std::size_t
occurrences (const std::string &text, const std::string &needle)
{
  std::size_t n = 0;
  for (std::size_t pos = text.find (needle); pos != std::string::npos; pos = text.find (needle, pos + 1))
    ++n;
  return n;
}

class InterferenceApp : public pcl_texlet_test::AppTest
{
protected:
  InterferenceApp () : AppTest (INTERFERENCE_APP) {}

  using AppTest::run;

  /** Runs another app (the simulator) with its output captured here too. */
  Result
  run (const std::string &app, const std::string &args) const
  {
    return pcl_texlet_test::runApp (app, args, dir_);
  }

  /** The simulator's box scene recorded by all three sensors (3 active projectors), QVGA. */
  fs::path
  recordBox (const std::string &name)
  {
    const fs::path out = dir_ / name;
    const Result r = run (SIM_APP, "--scene box --distance 1.0 --elevation 45 --projectors 3 --record all --frames 1 "
                                   "--effect interference --width 320 --height 240 --seed 3 -q " +
                                       out.string ());
    EXPECT_EQ (r.code, 0) << r.err;
    return out;
  }
};

} // namespace

TEST_F (InterferenceApp, HelpListsTheOptions)
{
  const Result r = run ("--help");
  EXPECT_EQ (r.code, 0);
  for (const char *option : {"--simulate", "--recordings", "--extrinsics", "--object", "--projectors", "--radii",
                             "--histogram-radii", "--angle-tol", "--distance-tol", "--threads"})
    EXPECT_NE (r.out.find (option), std::string::npos) << option;
}

TEST_F (InterferenceApp, SimulatedStudyWritesHistogramsTableAndReport)
{
  const fs::path out = dir_ / "study";
  const Result r = run ("--simulate --width 320 --height 240 --radii 3,8 --projectors 1,3 --histogram-radii 8 -j 2 " +
                          out.string ());
  ASSERT_EQ (r.code, 0) << r.err;
  EXPECT_NE (r.out.find ("projectors 3, radius  8"), std::string::npos) << r.out; // progress
  EXPECT_EQ (leftovers (), std::vector<std::string> ({"study"})) << "no temporary folder is left";
  for (const char *png : {"histogram_p1_r8.png", "histogram_p3_r8.png", "inliers_vs_radius.png"})
    EXPECT_TRUE (isPng (out / png)) << png;
  EXPECT_FALSE (fs::exists (out / "histogram_p1_r3.png")); // not among --histogram-radii

  const json j = json::parse (slurp (out / "inliers.json"));
  EXPECT_EQ (j["setup"]["source"], "simulated");
  EXPECT_EQ (j["object"]["relations"].size (), 5u);
  ASSERT_EQ (j["cells"].size (), 4u);
  std::map<std::pair<int, int>, json> cells;
  for (const auto &c : j["cells"])
  {
    cells[{c["projectors"].get<int> (), c["radius_px"].get<int> ()}] = c;
    EXPECT_EQ (c["texlets_per_sensor"].size (), 3u);
    EXPECT_EQ (c["relations"].get<std::uint64_t> (),
               c["texlets"].get<std::uint64_t> () * (c["texlets"].get<std::uint64_t> () - 1));
    EXPECT_EQ (c["faces"].size (), 6u);
  }
  const auto percent = [&] (int p, int radius) { return cells[std::make_pair (p, radius)]["inlier_percent"].get<double> (); };
  for (int radius : {3, 8})
    EXPECT_LT (percent (3, radius), percent (1, radius)) << radius;
  for (int p : {1, 3})
    EXPECT_GT (percent (p, 8), percent (p, 3)) << p;
  for (const auto &peak : cells[std::make_pair (1, 8)]["peaks"])
  {
    EXPECT_NEAR (peak["peak_distance_mm"].get<double> (), peak["expected_distance_mm"].get<double> (), 2.0) << peak;
    EXPECT_NEAR (peak["peak_angle_deg"].get<double> (), peak["expected_angle_deg"].get<double> (), 1.0) << peak;
  }

  const std::string html = slurp (out / "report.html");
  EXPECT_EQ (occurrences (html, "src=\"data:image/png;base64,"), 3u); // self-contained: two maps, one curve plot
  EXPECT_EQ (occurrences (html, "src=\"histogram"), 0u);
  EXPECT_NE (html.find ("top vs ground"), std::string::npos);
}

TEST_F (InterferenceApp, RecordingsFromTheSimulatorWithMetaPosesOrExtrinsics)
{
  const fs::path rec = recordBox ("rec");
  const std::string folders = (rec / "sensor_0").string () + "," + (rec / "sensor_1").string () + "," +
                              (rec / "sensor_2").string ();
  Result r = run ("--recordings " + folders + " --radii 6 --no-plots -q " + (dir_ / "meta").string ());
  ASSERT_EQ (r.code, 0) << r.err;
  const json a = json::parse (slurp (dir_ / "meta" / "inliers.json"));
  ASSERT_EQ (a["cells"].size (), 1u);
  EXPECT_EQ (a["cells"][0]["projectors"], 3); // from meta.yaml
  EXPECT_FALSE (fs::exists (dir_ / "meta" / "inliers_vs_radius.png"));
  // The box's point relations are where Table 2 puts them (the big table adds outliers, not peaks).
  for (const auto &peak : a["cells"][0]["peaks"])
  {
    EXPECT_NEAR (peak["peak_distance_mm"].get<double> (), peak["expected_distance_mm"].get<double> (), 2.0) << peak;
    EXPECT_NEAR (peak["peak_angle_deg"].get<double> (), peak["expected_angle_deg"].get<double> (), 2.0) << peak;
  }

  // The same poses from an extrinsics file give the same relations.
  std::vector<pcl::texlet::SensorExtrinsics> ext (3);
  for (int s = 0; s < 3; ++s)
  {
    ext[s].name = "sensor_" + std::to_string (s);
    ASSERT_TRUE (pcl::texlet::poseFromMetaYaml ((rec / ext[s].name / "meta.yaml").string (), ext[s].pose));
    fs::remove (rec / ext[s].name / "meta.yaml");
  }
  pcl::texlet::saveExtrinsicsYaml ((dir_ / "extrinsics.yaml").string (), ext);
  r = run ("--recordings " + folders + " --extrinsics " + (dir_ / "extrinsics.yaml").string () +
             " --projectors 3 --radii 6 --no-plots -q " + (dir_ / "ext").string ());
  ASSERT_EQ (r.code, 0) << r.err;
  const json b = json::parse (slurp (dir_ / "ext" / "inliers.json"));
  EXPECT_EQ (b["cells"][0]["inliers"], a["cells"][0]["inliers"]);
  EXPECT_EQ (b["cells"][0]["relations"], a["cells"][0]["relations"]);

  // Without meta.yaml and without extrinsics there is no pose: named in the error.
  expectRejected ("--recordings " + folders + " --radii 6 --no-plots " + (dir_ / "none").string (), "no pose");
  // Extrinsics without one of the sensors.
  ext.pop_back ();
  pcl::texlet::saveExtrinsicsYaml ((dir_ / "two.yaml").string (), ext);
  expectRejected ("--recordings " + folders + " --extrinsics " + (dir_ / "two.yaml").string () + " --no-plots " +
                      (dir_ / "none").string (),
                  "sensor_2");
}

TEST_F (InterferenceApp, BadInputExitsTwoWithOneLine)
{
  const std::string out = (dir_ / "out").string ();
  expectRejected ("", "OUTPUT is required");
  expectRejected ("--simulate --recordings a,b " + out, "either --simulate or --recordings");
  expectRejected (out, "either --simulate or --recordings");
  fs::create_directories (dir_ / "exists");
  expectRejected ("--simulate " + (dir_ / "exists").string (), "already exists");
  expectRejected ("--simulate --radii 0 " + out, "radius 0");
  expectRejected ("--simulate --radii 6 --histogram-radii 5 " + out, "--histogram-radii");
  expectRejected ("--simulate --projectors 4 " + out, "4 active projectors");
  expectRejected ("--simulate --spacing 1 " + out, "--spacing");
  expectRejected ("--simulate --angle-tol 0 " + out, "--angle-tol");
  expectRejected ("--simulate --frames 0 " + out, "--frames");
  expectRejected ("--simulate --no-such-option " + out, "no-such-option");
  expectRejected ("--simulate " + (dir_ / "missing" / "out").string (), "does not exist");
  expectRejected ("--recordings " + (dir_ / "nowhere").string () + " --extrinsics " + (dir_ / "e.yaml").string () + " " +
                      out,
                  "e.yaml");
  std::ofstream (dir_ / "broken.yaml") << "sensors: [a: {";
  expectRejected ("--recordings " + (dir_ / "nowhere").string () + " --extrinsics " + (dir_ / "broken.yaml").string () +
                      " " + out,
                  "not valid YAML");
  std::ofstream (dir_ / "ok.yaml") << "sensors:\n  - {name: nowhere, pose: [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}\n";
  expectRejected ("--recordings " + (dir_ / "nowhere").string () + " --extrinsics " + (dir_ / "ok.yaml").string () + " " +
                      out,
                  "nowhere");
  expectRejected ("--simulate --object " + (dir_ / "object.yaml").string () + " " + out, "object.yaml");
  expectRejected ("--simulate --extrinsics " + (dir_ / "ok.yaml").string () + " " + out, "--extrinsics");
  expectRejected ("--recordings a --recordings b --projectors 1 " + out, "one count per set");
  expectRejected ("--recordings , " + out, "at least one folder");
}

TEST_F (InterferenceApp, GpuBackendRunsOrSaysWhyNot)
{
  // --backend gpu: the relations on the CUDA backend, the same study as on the CPU; without a
  // device (or a build without CUDA) one line naming the reason, exit 2, no output.
  const std::string args = "--simulate --width 160 --height 120 --radii 4 --projectors 1,2 --no-plots -q ";
  const fs::path cpu_out = dir_ / "cpu", gpu_out = dir_ / "gpu";
  const Result gpu = run ("--backend gpu " + args + gpu_out.string ());
  if (gpu.code == 2)
  {
    EXPECT_EQ (occurrences (gpu.err, "\n"), 1u) << gpu.err;
    EXPECT_NE (gpu.err.find ("--backend gpu: the GPU backend is not available: "), std::string::npos) << gpu.err;
    EXPECT_TRUE (gpu.err.find ("no CUDA device found") != std::string::npos ||
                 gpu.err.find ("this build has no CUDA backend") != std::string::npos)
        << gpu.err;
    EXPECT_FALSE (fs::exists (gpu_out));
  }
  else
  {
    ASSERT_EQ (gpu.code, 0) << gpu.err;
    const Result cpu = run ("--backend cpu " + args + cpu_out.string ());
    ASSERT_EQ (cpu.code, 0) << cpu.err;
    const json g = json::parse (slurp (gpu_out / "inliers.json")), c = json::parse (slurp (cpu_out / "inliers.json"));
    EXPECT_EQ (g["setup"]["relation_backend"], "gpu");
    ASSERT_EQ (g["cells"].size (), c["cells"].size ());
    for (std::size_t k = 0; k < c["cells"].size (); ++k)
    {
      EXPECT_EQ (g["cells"][k]["texlets"], c["cells"][k]["texlets"]);
      // Only relations within an ulp of a box's angle edge may be sorted differently.
      EXPECT_NEAR (g["cells"][k]["inlier_percent"].get<double> (), c["cells"][k]["inlier_percent"].get<double> (), 0.01);
    }
  }
  expectRejected ("--simulate --backend tpu " + (dir_ / "out").string (), "--backend");
}
