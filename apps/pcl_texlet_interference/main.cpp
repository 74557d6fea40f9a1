/*
 * pcl_texlet_interference: the paper's interference study (Sect. 4). Texlets of several
 * sensors in one reference frame, the relations of every pair (normal distance, angle) against
 * a known object's expected relations, per neighbourhood radius and number of active
 * projectors: quality histograms (Fig. 11), inlier table (inliers.json), inlier percentage
 * against radius (Fig. 13) and a self-contained report.html.
 *
 * Input: recordings (one folder per sensor, repeatable --recordings for several projector
 * counts) with an extrinsics YAML or the simulator's meta.yaml poses; or --simulate, the
 * paper's setup (three sensors in a triangle around the box, 1, 2 or 3 projectors active).
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 * The output folder is written under a temporary name and renamed when complete.
 */
#include "../common/app_main.h"
#include "../common/folder_guard.h"
#include "study_report.h"

#include <pcl_texlet/relations/extrinsics.h>
#include "interference_study.h"
#include <pcl_texlet/report/relation_plots.h>

#ifdef PCL_TEXLET_INTERFERENCE_WITH_GPU
#include <pcl_texlet/gpu/containers/cuda_error.h>
#include <pcl_texlet/gpu/texlet_relations.h>
#endif

#include <pcl/console/print.h>
#include <pcl/exceptions.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;
using namespace pcl::texlet;
using nlohmann::json;
using pcl_texlet_app::InputError;
using pcl_texlet_interference::CellResult;

namespace
{

const char *const kName = "pcl_texlet_interference";

struct Options
{
  std::string output;
  bool simulate = false;
  std::vector<std::string> recording_sets;         ///< comma-separated folders, one string per set
  std::vector<std::vector<std::string>> recordings; ///< recording_sets split
  std::string extrinsics, object;
  std::vector<int> projectors;
  std::vector<int> radii{2, 4, 6, 8, 10};
  std::vector<int> histogram_radii; ///< radii whose histograms are drawn (default: all)
  int spacing = 4;
  std::size_t frames = 1;
  std::uint32_t seed = 0;
  int width = 640, height = 480;
  double distance = 1.0, elevation = 45.0, plate_mm = 350.0;
  double noise_gain = 1.0, dropout_rate = 0.1;
  double angle_tol = NAN, distance_tol_mm = NAN;
  double max_distance_mm = 300.0, distance_bin_mm = 2.0, angle_bin_deg = 1.0;
  unsigned threads = 0;
  std::string backend = "cpu"; ///< where the relations are accumulated: cpu or gpu
  bool no_plots = false, quiet = false;
};

using pcl_texlet_app::OutputFolder;

void
writeText (const fs::path &path, const std::string &text)
{
  std::ofstream out (path, std::ios::binary);
  out << text;
  if (!out)
    throw pcl::IOException ("cannot write '" + path.string () + "'");
}

void
checkOptions (Options &o, const CLI::App &app)
{
  if (o.output.empty ())
    throw InputError ("OUTPUT is required (the folder to create)");
  if (o.simulate == !o.recordings.empty ())
    throw InputError ("give either --simulate or --recordings (one folder per sensor)");
  if (o.radii.empty ())
    throw InputError ("--radii needs at least one radius");
  for (int r : o.radii)
    if (r < 1 || r > 100)
      throw InputError ("--radii: radius " + std::to_string (r) + " is outside 1-100 pixels");
  for (int r : o.histogram_radii)
    if (std::find (o.radii.begin (), o.radii.end (), r) == o.radii.end ())
      throw InputError ("--histogram-radii: radius " + std::to_string (r) + " is not one of --radii");
  if (o.spacing < 2 || o.spacing > 100)
    throw InputError ("--spacing must be between 2 and 100 pixels (got " + std::to_string (o.spacing) + ")");
  if (o.frames < 1 || o.frames > 1000)
    throw InputError ("--frames must be between 1 and 1000 (got " + std::to_string (o.frames) + ")");
  if (o.width < 16 || o.height < 16 || o.width > 4096 || o.height > 4096)
    throw InputError ("--width and --height must be between 16 and 4096 pixels");
  if (!(o.distance > 0.3 && o.distance < 10))
    throw InputError ("--distance must be between 0.3 and 10 metres");
  if (!(o.elevation > 0 && o.elevation < 90))
    throw InputError ("--elevation must be between 0 and 90 degrees");
  if (!(o.noise_gain >= 0) || !(o.dropout_rate >= 0))
    throw InputError ("--interference-gain and --interference-dropout must be >= 0");
  if (app.count ("--angle-tol") && !(o.angle_tol > 0 && o.angle_tol < 90))
    throw InputError ("--angle-tol must be between 0 and 90 degrees");
  if (app.count ("--distance-tol") && !(o.distance_tol_mm > 0))
    throw InputError ("--distance-tol must be positive (mm)");
  if (!(o.max_distance_mm > 0) || !(o.distance_bin_mm > 0) || !(o.angle_bin_deg > 0) ||
      o.max_distance_mm / o.distance_bin_mm > 10000 || 180.0 / o.angle_bin_deg > 10000)
    throw InputError ("--max-distance, --distance-bin and --angle-bin must be positive, with at most 10000 bins per axis");
  if (o.threads > 1024)
    throw InputError ("--threads " + std::to_string (o.threads) + " is not a sensible thread count");
  if (o.backend == "gpu")
  {
#ifdef PCL_TEXLET_INTERFERENCE_WITH_GPU
    if (pcl::texlet::gpu::cudaDeviceCount () == 0)
      throw InputError ("--backend gpu: the GPU backend is not available: no CUDA device found");
#else
    throw InputError ("--backend gpu: the GPU backend is not available: this build has no CUDA backend (nvcc was not "
                      "found when it was configured)");
#endif
  }
  if (o.simulate)
  {
    if (o.projectors.empty ())
      o.projectors = {1, 2, 3};
    for (int p : o.projectors)
      if (p < 1 || p > 3)
        throw InputError ("--projectors: the simulated setup has 3 sensors; " + std::to_string (p) +
                          " active projectors is not 1, 2 or 3");
    if (!o.extrinsics.empty ())
      throw InputError ("--extrinsics applies to --recordings; the simulated setup knows its poses");
  }
  else
  {
    for (const auto &set : o.recordings)
      if (set.empty ())
        throw InputError ("--recordings needs at least one folder");
    if (!o.projectors.empty () && o.projectors.size () != o.recordings.size ())
      throw InputError ("--projectors gives " + std::to_string (o.projectors.size ()) + " counts for " +
                        std::to_string (o.recordings.size ()) + " --recordings sets (one count per set)");
    for (int p : o.projectors)
      if (p < 1)
        throw InputError ("--projectors must be positive");
  }
}

std::string
cellName (int projectors, int radius)
{
  return "histogram_p" + std::to_string (projectors) + "_r" + std::to_string (radius) + ".png";
}

int
run (int argc, char **argv)
{
  Options o;
  CLI::App app ("The paper's interference study (Sect. 4): relations (normal distance, angle) of every texlet pair\n"
                "against a known object, per neighbourhood radius and number of active projectors.\n"
                "OUTPUT (a new folder): histogram_pP_rR.png (Fig. 11), inliers_vs_radius.png (Fig. 13),\n"
                "inliers.json and report.html.",
                kName);
  app.add_option ("OUTPUT", o.output, "folder to create (must not exist)");
  app.add_flag ("--simulate", o.simulate,
                "the simulated setup: three sensors in a triangle around the paper's box on a plate");
  // Lists are comma-separated (one token per option), so that OUTPUT after them is never taken
  // for one more item.
  app.add_option ("--recordings", o.recording_sets,
                  "recordings of one scene, one folder per sensor, comma-separated: DIR0,DIR1,DIR2 "
                  "(repeatable: one set per projector count)")
      ->allow_extra_args (false);
  app.add_option ("--extrinsics", o.extrinsics,
                  "YAML with a 4x4 pose per sensor, matched by folder name (default: each recording's meta.yaml)");
  app.add_option ("--object", o.object, "known object YAML (default: the paper's Table 2 box on a 350 mm plate)");
  app.add_option ("--projectors", o.projectors,
                  "comma-separated; simulate: active projector counts to run (default 1,2,3); recordings: the count "
                  "of each set (default: meta.yaml's projectors, else 1)")
      ->delimiter (',')
      ->allow_extra_args (false);
  app.add_option ("--radii", o.radii, "neighbourhood radii, pixels, comma-separated")
      ->delimiter (',')
      ->allow_extra_args (false)
      ->capture_default_str ();
  app.add_option ("--histogram-radii", o.histogram_radii, "radii whose histograms are drawn, comma-separated (default: all)")
      ->delimiter (',')
      ->allow_extra_args (false);
  app.add_option ("--spacing", o.spacing, "hexagonal grid spacing, pixels")->capture_default_str ();
  app.add_option ("--frames", o.frames, "frames per sensor (texlets of all are merged)")->capture_default_str ();
  app.add_option ("--seed", o.seed, "simulation seed")->capture_default_str ();
  app.add_option ("--width", o.width, "simulated image width, pixels")->capture_default_str ();
  app.add_option ("--height", o.height, "simulated image height, pixels")->capture_default_str ();
  app.add_option ("--distance", o.distance, "simulated sensors' distance to the box centre, metres")
      ->capture_default_str ();
  app.add_option ("--elevation", o.elevation, "simulated sensors' elevation, degrees")->capture_default_str ();
  app.add_option ("--plate", o.plate_mm, "simulated base plate side, mm")->capture_default_str ();
  app.add_option ("--interference-gain", o.noise_gain, "interference effect: noise_gain")->capture_default_str ();
  app.add_option ("--interference-dropout", o.dropout_rate, "interference effect: dropout_rate")->capture_default_str ();
  app.add_option ("--angle-tol", o.angle_tol, "inlier box half width, degrees (default: the object's, 10)");
  app.add_option ("--distance-tol", o.distance_tol_mm, "inlier box margin, mm (default: the object's, 5)");
  app.add_option ("--max-distance", o.max_distance_mm, "histogram distance axis, mm")->capture_default_str ();
  app.add_option ("--distance-bin", o.distance_bin_mm, "histogram distance bin, mm")->capture_default_str ();
  app.add_option ("--angle-bin", o.angle_bin_deg, "histogram angle bin, degrees")->capture_default_str ();
  app.add_option ("-j,--threads", o.threads, "threads (0: all)")->capture_default_str ();
  app.add_option ("--backend", o.backend, "where the texlet relations are accumulated: cpu (OpenMP) or gpu (CUDA)")
      ->check (CLI::IsMember ({"cpu", "gpu"}))
      ->capture_default_str ();
  app.add_flag ("--no-plots", o.no_plots, "no PNG images (and no images in report.html)");
  app.add_flag ("-q,--quiet", o.quiet, "no progress on stdout");
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv))
    return 0;

  for (const auto &set : o.recording_sets)
  {
    std::vector<std::string> folders;
    std::stringstream list (set);
    for (std::string folder; std::getline (list, folder, ',');)
      if (!folder.empty ())
        folders.push_back (folder);
    o.recordings.push_back (folders);
  }
  checkOptions (o, app);
  const fs::path out = pcl_texlet_app::newOutputFolder (o.output, "results are never written over others");
  if (!o.no_plots && !gnuplotAvailable ())
    throw InputError ("gnuplot with the pngcairo terminal is not available (install gnuplot, or use --no-plots)");

  KnownObject object;
  SimulatedSetup sim;
  json setup;
  if (o.simulate)
  {
    sim.width = o.width;
    sim.height = o.height;
    sim.distance_m = o.distance;
    sim.elevation_deg = o.elevation;
    sim.plate_m = 1e-3 * o.plate_mm;
    sim.interference.noise_gain = o.noise_gain;
    sim.interference.dropout_rate = o.dropout_rate;
    sim.seed = o.seed;
    sim.frames = o.frames;
    sim.threads = o.threads;
    object = simulatedObject (sim);
    setup = {{"source", "simulated"},
             {"sensors", 3},
             {"image", {o.width, o.height}},
             {"distance_m", o.distance},
             {"elevation_deg", o.elevation},
             {"plate_mm", o.plate_mm},
             {effects::Interference::kName, {{"noise_gain", o.noise_gain}, {"dropout_rate", o.dropout_rate}}},
             {"seed", o.seed}};
  }
  else
  {
    object = paperBoxObject ();
    setup = {{"source", "recordings"}, {"recordings", o.recordings}};
    if (!o.extrinsics.empty ())
      setup["extrinsics"] = fs::absolute (o.extrinsics).string ();
  }
  if (!o.object.empty ())
  {
    object = loadKnownObjectYaml (o.object);
    setup["object_file"] = fs::absolute (o.object).string ();
  }
  if (!std::isnan (o.angle_tol))
    object.angle_tol_deg = o.angle_tol;
  if (!std::isnan (o.distance_tol_mm))
    object.distance_tol_m = 1e-3 * o.distance_tol_mm;
  setup["frames_per_sensor"] = o.frames;
  setup["spacing_px"] = o.spacing;
  setup["radii_px"] = o.radii;

  std::vector<SensorExtrinsics> extrinsics;
  if (!o.extrinsics.empty ())
    extrinsics = loadExtrinsicsYaml (o.extrinsics);

  RelationParameters rel;
  rel.axes.distance_max = static_cast<float> (1e-3 * o.max_distance_mm);
  rel.axes.distance_bins = static_cast<int> (std::lround (o.max_distance_mm / o.distance_bin_mm));
  rel.axes.angle_bins = static_cast<int> (std::lround (180.0 / o.angle_bin_deg));
  rel.threads = o.threads;
#ifdef PCL_TEXLET_INTERFERENCE_WITH_GPU
  if (o.backend == "gpu")
    rel.backend = [] (const auto &in, const auto &config, auto &counts) {
      pcl::texlet::gpu::accumulateRelations (in, config, counts);
    };
#endif
  setup["relation_backend"] = o.backend;

  // Recordings first, so bad input fails before any long computation.
  std::vector<std::pair<int, std::vector<SensorRecording>>> sets;
  if (!o.simulate)
    for (std::size_t k = 0; k < o.recordings.size (); ++k)
    {
      int p = o.projectors.empty () ? 0 : o.projectors[k];
      if (p == 0)
        for (const auto &folder : o.recordings[k])
          p = std::max (p, projectorsFromMetaYaml ((fs::path (folder) / "meta.yaml").string (), 1));
      sets.emplace_back (p, loadSensorRecordings (o.recordings[k], extrinsics, o.frames));
    }

  OutputFolder folder (out, o.output);
  const fs::path tmp = folder.temporary ();

  const std::vector<int> projector_counts = o.simulate ? o.projectors : std::vector<int> ();
  const std::size_t set_count = o.simulate ? projector_counts.size () : sets.size ();
  std::vector<CellResult> results;
  for (std::size_t k = 0; k < set_count; ++k)
  {
    int projectors = 0;
    std::vector<SensorRecording> recordings;
    if (o.simulate)
    {
      projectors = projector_counts[k];
      if (!o.quiet)
        std::cout << "simulating 3 sensors with " << projectors << " active projector(s) ..." << std::endl;
      recordings = simulateInterferenceRecordings (sim, projectors);
    }
    else
    {
      projectors = sets[k].first;
      recordings = std::move (sets[k].second);
    }
    for (int radius : o.radii)
    {
      const auto t0 = std::chrono::steady_clock::now ();
      CellResult r;
      r.cell = runInterferenceCell (recordings, projectors, studyTexletParameters (radius, o.spacing), object, rel);
      r.seconds = std::chrono::duration<double> (std::chrono::steady_clock::now () - t0).count ();
      const bool draw = !o.no_plots && (o.histogram_radii.empty () || std::find (o.histogram_radii.begin (),
                                                                                 o.histogram_radii.end (), radius) !=
                                                                          o.histogram_radii.end ());
      if (draw)
      {
        r.histogram_png = cellName (projectors, radius);
        writeRelationHistogramPng (r.cell.statistics, (tmp / r.histogram_png).string (),
                                   std::to_string (projectors) + " active projector" + (projectors > 1 ? "s" : "") +
                                       ", radius " + std::to_string (radius) + " px");
      }
      if (!o.quiet)
        std::cout << "  projectors " << projectors << ", radius " << std::setw (2) << radius << ": "
                  << std::setw (6) << r.cell.statistics.texlets << " texlets, " << std::fixed << std::setprecision (1)
                  << r.cell.statistics.inlierPercent () << " % inliers (" << std::setprecision (2) << r.seconds
                  << " s)" << std::defaultfloat << std::endl;
      results.push_back (std::move (r));
    }
  }

  // Fig. 13: one curve per projector count.
  std::string curves_png;
  if (!o.no_plots)
  {
    std::map<int, InlierCurve> curves;
    for (const auto &r : results)
    {
      InlierCurve &c = curves[r.cell.projectors];
      c.label = std::to_string (r.cell.projectors) + " active projector" + (r.cell.projectors > 1 ? "s" : "");
      c.radius_px.push_back (r.cell.radius);
      c.percent.push_back (r.cell.statistics.inlierPercent ());
    }
    std::vector<InlierCurve> list;
    for (auto &kv : curves)
      list.push_back (kv.second);
    curves_png = "inliers_vs_radius.png";
    writeInlierCurvesPng (list, (tmp / curves_png).string (), "Inlier relations against neighbourhood radius");
  }

  const json j = pcl_texlet_interference::studyJson (setup, object, results);
  writeText (tmp / "inliers.json", j.dump (2) + "\n");
  writeText (tmp / "report.html", pcl_texlet_interference::studyHtml (j, tmp.string (), curves_png));

  folder.publish ();
  if (!o.quiet)
    std::cout << "output: " << o.output << " (inliers.json, report.html"
              << (o.no_plots ? "" : ", histogram_p*_r*.png, inliers_vs_radius.png") << ")" << std::endl;
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
