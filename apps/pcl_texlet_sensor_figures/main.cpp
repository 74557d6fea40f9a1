/*
 * pcl_texlet_sensor_figures: the measurements behind docs/sensor_model.md.
 *
 * For each physical effect of the simulator it simulates a small scene (mostly a wall 1.5 m
 * away) with the base noise alone and with the effect added, measures the quantity in which
 * the effect shows, and writes it, beside the closed-form prediction from the effect's
 * parameters, as gnuplot data files (columns named in a '#' header). summary.txt lists the key
 * numbers. scripts/make_sensor_model_figures.sh draws the PNGs from these files. One study a
 * file (studies.h); this one reads the command line and runs the studies asked for.
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 * Every file is written to a temporary name and renamed, so no half-written file is left.
 */
#include "../common/app_main.h"
#include "../common/folder_guard.h"
#include "figures.h"
#include "studies.h"

#include <pcl_texlet/noise/effects/axial_quadratic.h>
#include <pcl_texlet/noise/effects/depth_distortion.h>
#include <pcl_texlet/noise/effects/disparity_quantization.h>
#include <pcl_texlet/noise/effects/incidence_angle.h>
#include <pcl_texlet/noise/effects/interference.h>
#include <pcl_texlet/noise/effects/intrinsics.h>
#include <pcl_texlet/noise/effects/lateral_noise.h>
#include <pcl_texlet/noise/effects/radial.h>
#include <pcl_texlet/noise/effects/temporal_drift.h>
#include <pcl_texlet/noise/effects/vertical_stripes.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pcl::texlet;
using namespace pcl_texlet_sensor_figures;

using pcl_texlet_app::InputError;

namespace
{

const char *const kName = "pcl_texlet_sensor_figures";

/** A figure's name (--only) and its study. */
struct Figure
{
  std::string name;
  void (*measure) (Figures &);
};

/** The figures in the order the document shows them. */
const std::vector<Figure> &
figureList ()
{
  static const std::vector<Figure> figures = {{"base_noise", measureBaseNoise},
                                              {"projector_shadows", measureProjectorShadows},
                                              {effects::AxialQuadratic::kName, measureAxialQuadratic},
                                              {effects::Radial::kName, measureRadial},
                                              {effects::DisparityQuantization::kName, measureDisparityQuantization},
                                              {effects::IncidenceAngle::kName, measureIncidenceAngle},
                                              {effects::VerticalStripes::kName, measureVerticalStripes},
                                              {effects::DepthDistortion::kName, measureDepthDistortion},
                                              {effects::Interference::kName, measureInterference},
                                              {effects::TemporalDrift::kName, measureTemporalDrift},
                                              {effects::LateralNoise::kName, measureLateralNoise},
                                              {effects::Intrinsics::kName, measureIntrinsics}};
  return figures;
}

int
run (int argc, char **argv)
{
  Options o;
  CLI::App app ("Measure what each physical effect of the simulator does to a simulated wall, beside the closed-form\n"
                "prediction, and write gnuplot data files (see docs/sensor_model.md and\n"
                "scripts/make_sensor_model_figures.sh, which draws them).",
                kName);
  std::string names;
  for (const Figure &f : figureList ())
    names += (names.empty () ? "" : ", ") + f.name;
  app.add_option ("OUTPUT", o.output, "folder for the data files (created if missing)");
  app.add_option ("--width", o.width, "image width, pixels (focal length 580 x width / 640)")->capture_default_str ();
  app.add_option ("--height", o.height, "image height, pixels")->capture_default_str ();
  app.add_option ("--frames", o.frames, "frames per simulated recording")->capture_default_str ();
  app.add_option ("--seed", o.seed, "random seed")->capture_default_str ();
  app.add_option ("--only", o.only, "make only these figures (repeatable): " + names)->allow_extra_args (false);
  app.add_option ("-j,--threads", o.threads, "threads (0: all)")->capture_default_str ();
  app.add_flag ("-q,--quiet", o.quiet, "no progress on stdout");
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv))
    return 0;

  if (o.output.empty ())
    throw InputError ("OUTPUT is required (the folder for the data files)");
  if (o.width < 32 || o.height < 24 || o.width > 4096 || o.height > 4096)
    throw InputError ("--width and --height must be between 32x24 and 4096x4096 (got " + std::to_string (o.width) +
                      "x" + std::to_string (o.height) + ")");
  if (o.frames < 2 || o.frames > 10000)
    throw InputError ("--frames must be between 2 and 10000 (got " + std::to_string (o.frames) +
                      "): a temporal SD needs two frames");
  if (o.threads > 1024)
    throw InputError ("--threads " + std::to_string (o.threads) + " is not a sensible thread count");
  std::vector<const Figure *> todo;
  if (o.only.empty ())
    for (const Figure &f : figureList ())
      todo.push_back (&f);
  for (const auto &n : o.only)
  {
    const auto &list = figureList ();
    const auto it = std::find_if (list.begin (), list.end (), [&] (const Figure &f) { return n == f.name; });
    if (it == list.end ())
      throw InputError ("--only: unknown figure '" + n + "' (known: " + names + ")");
    todo.push_back (&*it);
  }

  std::error_code ec;
  const fs::path out = fs::absolute (o.output, ec);
  if (fs::exists (out, ec) && !fs::is_directory (out, ec))
    throw InputError ("OUTPUT '" + o.output + "' exists and is not a folder");
  const bool made = !fs::exists (out, ec);
  if (made)
  {
    if (!fs::is_directory (out.parent_path (), ec))
      throw InputError ("the folder that should hold OUTPUT '" + o.output + "' does not exist");
    if (!fs::create_directory (out, ec))
      throw InputError ("cannot create OUTPUT '" + o.output + "': " + ec.message ());
  }

  // A failed run removes the folder it made; one that existed keeps the complete files written.
  pcl_texlet_app::FolderGuard guard (made ? out : fs::path ());
  Figures figures (o, out);
  for (std::size_t k = 0; k < todo.size (); ++k)
  {
    if (!o.quiet)
      std::cout << "[" << k + 1 << "/" << todo.size () << "] " << todo[k]->name << std::endl;
    todo[k]->measure (figures);
  }
  figures.writeSummary ();
  guard.release ();
  if (!o.quiet)
    std::cout << "data files and summary.txt in " << o.output << std::endl;
  return 0;
}


} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
