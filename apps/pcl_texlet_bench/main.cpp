/*
 * pcl_texlet_bench: texlets against PCL's normal estimators, in one run, at the same centres
 * with the same pixel neighbourhood; accuracy on simulated scenes with ground truth; the
 * paper's Table 1 and Fig. 8; time against the number of texlets and the neighbourhood size.
 * One study a file (studies.h); this one reads the command line, runs the studies asked for and
 * writes the JSON and the gnuplot data.
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 */
#include "../common/app_main.h"
#include "machine.h"
#include "methods.h"
#include "options.h"
#include "output_format.h"
#include "scenes.h"
#include "studies.h"

#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/features/texlet_parameters.h>
#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/kernels/pixel_disc.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using nlohmann::json;
using pcl_texlet_app::InputError;
using pcl_texlet_app::pclMessage;
using namespace pcl_texlet_bench;
using pcl::texlet::PlaneFitMethod;

namespace
{

/** Writes \a text to \a path through a temporary file in the same folder, renamed when complete. */
void
writeOutput (const std::string &path, const std::string &text)
{
  const fs::path target (path);
  if (!target.parent_path ().empty () && !fs::is_directory (target.parent_path ()))
    throw InputError ("the folder of '" + path + "' does not exist");
  pcl::texlet::writeFileAtomically (path, text);
}

PlaneFitMethod
fitFromName (const std::string &s)
{
  try
  {
    return pcl::texlet::planeFitMethodFromString (s);
  }
  catch (const pcl::PCLException &e)
  {
    throw InputError ("--fits: " + pclMessage (e.what ()));
  }
}

int
run (int argc, char **argv)
{
  Options o;
  CLI::App app ("Benchmark texlets against PCL's normal estimators (NormalEstimationOMP over the same pixel\n"
                "neighbourhood, IntegralImageNormalEstimation), at the same hexagonal centres; accuracy on\n"
                "simulated scenes with ground truth; the paper's Table 1 and Fig. 8; scaling.",
                kName);
  app.add_option ("INPUT", o.input, "organised PCD file to time on (default: the bundled real 640x480 frame)")
      ->capture_default_str ();
  app.add_option ("--scene", o.scene, "time on a simulated scene instead: plane, sphere, box");
  app.add_option ("--width", o.sim_width, "simulated scenes' width, pixels")->capture_default_str ();
  app.add_option ("--height", o.sim_height, "simulated scenes' height, pixels")->capture_default_str ();
  app.add_option ("-s,--spacing", o.setup.spacing, "hexagonal grid spacing, pixels")->capture_default_str ();
  app.add_option ("-r,--radius", o.setup.radius, "neighbourhood radius, pixels")->capture_default_str ();
  app.add_option ("-i,--iterations", o.setup.iterations, "RANSAC iterations")->capture_default_str ();
  app.add_option ("-n,--samples", o.setup.samples, "Monte Carlo samples")->capture_default_str ();
  app.add_option ("-j,--threads", o.setup.threads, "threads for every method that has them")->capture_default_str ();
  app.add_option ("--fits", o.fits, "plane fits of ours to compare: pca svd averaging")->capture_default_str ();
  app.add_option ("--repetitions", o.repetitions, "timed repetitions")->capture_default_str ();
  app.add_option ("--warmup", o.warmup, "untimed warm-up repetitions")->capture_default_str ();
  app.add_flag ("!--no-knn", o.organized_knn, "leave out NormalEstimationOMP with OrganizedNeighbor kNN");
  app.add_flag ("!--no-timing", o.timing, "skip the timing comparison");
  app.add_flag ("!--no-accuracy", o.accuracy, "skip the accuracy on simulated scenes");
  app.add_flag ("--table1", o.table1, "reproduce the paper's Table 1 on the input");
  app.add_flag ("--fig8", o.fig8, "reproduce the paper's Fig. 8 (plane fits against noise)");
  app.add_flag ("--scaling", o.scaling, "time against spacing (texlet count) and radius (disc size)");
  app.add_option ("--table1-repetitions", o.table1_reps, "timed repetitions per Table 1 row")->capture_default_str ();
  app.add_option ("--scaling-repetitions", o.scaling_reps, "timed repetitions per scaling point")->capture_default_str ();
  app.add_option ("--fig8-runs", o.fig8_runs, "noisy planes per noise level")->capture_default_str ();
  app.add_option ("--noise-model", o.noise_model,
                  "the texlets' depth noise model YAML (e.g. pcl_texlet_lab's model.yaml; default: the paper's Eq. 4)");
  app.add_flag ("--exact-window-form", o.setup.exact_window_form,
                "form every texlet's window-shared noise by the windows' sums (default: discs from tables)");
  app.add_option ("--json", o.json_path, "write every figure measured to this JSON file");
  app.add_option ("--data-dir", o.data_dir, "write gnuplot data files (timing, fig8, scaling) into this folder");
  app.add_flag ("-q,--quiet", o.quiet, "no progress lines");
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv))
    return 0;


  if (o.repetitions < 1 || o.warmup < 0 || o.table1_reps < 1 || o.scaling_reps < 1 || o.fig8_runs < 1)
    throw InputError ("repetitions and runs must be at least 1 (warm-up at least 0)");
  if (o.setup.threads < 1 || o.setup.threads > 1024)
    throw InputError ("--threads " + std::to_string (o.setup.threads) + " is not a sensible thread count");
  if (o.sim_width < 32 || o.sim_height < 32 || o.sim_width > 4096 || o.sim_height > 4096)
    throw InputError ("--width/--height must be 32..4096 pixels");
  std::vector<PlaneFitMethod> fits;
  for (const auto &f : o.fits)
    fits.push_back (fitFromName (f));
  if (fits.empty ())
    throw InputError ("--fits needs at least one plane fit");
  if (!o.scene.empty () && std::find (sceneNames ().begin (), sceneNames ().end (), o.scene) == sceneNames ().end ())
    throw InputError ("--scene '" + o.scene + "' is not one of plane, sphere, box");
  pcl::texlet::TexletParameters p;
  p.spacing = o.setup.spacing;
  p.radius = o.setup.radius;
  p.ransac_iterations = o.setup.iterations;
  p.samples = o.setup.samples;
  pcl::texlet::validate (p);
  if (!o.noise_model.empty ())
    o.setup.noise = pcl::texlet::loadNoiseModelYaml (o.noise_model);
  if (!o.json_path.empty () && !fs::is_directory (fs::absolute (o.json_path).parent_path ()))
    throw InputError ("the folder that should hold --json '" + o.json_path + "' does not exist");
  if (!o.data_dir.empty () && !fs::is_directory (o.data_dir))
    throw InputError ("--data-dir '" + o.data_dir + "' is not a folder");

  json j;
  j["machine"] = {{"cpu", cpuModel ()},
                  {"hardware_threads", std::thread::hardware_concurrency ()},
                  {"threads_used", o.setup.threads},
                  {"load_average_at_start", num (loadAverage ())}};
  j["settings"] = {{"spacing", o.setup.spacing}, {"radius", o.setup.radius},
                   {"disc_px", pcl::texlet::kernels::pixelDiscSize (o.setup.radius)},
                   {"ransac_iterations", o.setup.iterations}, {"montecarlo_samples", o.setup.samples},
                   {"threads", o.setup.threads},
                   {"noise_model", o.noise_model.empty () ? std::string ("paper") : o.noise_model},
                   {"exact_window_form", o.setup.exact_window_form}};
  const std::vector<MethodSpec> methods = comparisonMethods (fits, o.organized_knn);
  std::cout << "machine: " << cpuModel () << ", " << std::thread::hardware_concurrency () << " hardware threads; "
            << o.setup.threads << " threads used; load average " << fmt (loadAverage (), 2) << "\n";
  if (o.timing || o.table1 || o.scaling)
  {
    const Input in = loadInput (o);
    j["input"] = in.description;
    if (o.timing)
    {
      j["timing"] = runTiming (o, in, methods);
      if (!o.data_dir.empty ())
      {
        std::ostringstream d;
        d << "# index name wall: median_ms q1_ms q3_ms min_ms max_ms ratio_to_reference; CPU: median_ms q1_ms q3_ms "
             "ratio_to_reference\n";
        int k = 0;
        for (const auto &m : j["timing"]["methods"])
          d << k++ << " " << m["name"].get<std::string> () << " " << m["time_ms"]["median"] << " "
            << m["time_ms"]["q1"] << " " << m["time_ms"]["q3"] << " " << m["time_ms"]["min"] << " "
            << m["time_ms"]["max"] << " " << m["ratio_to_reference"] << " " << m["cpu_time_ms"]["median"] << " "
            << m["cpu_time_ms"]["q1"] << " " << m["cpu_time_ms"]["q3"] << " " << m["cpu_ratio_to_reference"] << "\n";
        writeOutput ((fs::path (o.data_dir) / "timing.dat").string (), d.str ());
      }
    }
    if (o.table1)
      j["table1"] = runTable1 (o, in);
    if (o.scaling)
    {
      std::string ds, dr;
      j["scaling"] = runScaling (o, in, ds, dr);
      if (!o.data_dir.empty ())
      {
        writeOutput ((fs::path (o.data_dir) / "scaling_spacing.dat").string (), ds);
        writeOutput ((fs::path (o.data_dir) / "scaling_radius.dat").string (), dr);
      }
    }
  }
  if (o.accuracy)
    j["accuracy"] = runAccuracy (o, methods);
  if (o.fig8)
  {
    std::string d;
    j["fig8"] = runFig8 (o, d);
    if (!o.data_dir.empty ())
      writeOutput ((fs::path (o.data_dir) / "fig8.dat").string (), d);
  }
  j["machine"]["load_average_at_end"] = num (loadAverage ());
  if (!o.json_path.empty ())
    writeOutput (o.json_path, j.dump (2) + "\n");
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
