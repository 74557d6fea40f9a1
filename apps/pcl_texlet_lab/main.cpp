/*
 * pcl_texlet_lab: compare the sensor's noise model with recordings, see where it fails, learn
 * which physical effect is missing, add it, refit, and watch the error fall.
 *
 *   pcl_texlet_lab [--model paper | MODEL.yaml] [--add EFFECT]... [--auto N] --report OUTDIR RECORDING...
 *
 * RECORDING: anything openRecording reads (recording folder, PCD folder, grabber TIFF folder,
 * .oni). Writes OUTDIR/report.html, report.json, model.yaml and the PNG plots.
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 */
#include "../common/app_main.h"
#include "evenly_spaced_frames.h"
#include <pcl_texlet/io/frame_skipping_reader.h>
#include <pcl_texlet/io/open_recording.h>
#include <pcl_texlet/report/lab_report.h>
#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <pcl/exceptions.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

using pcl_texlet_app::InputError;
namespace lab = pcl::texlet::lab;

namespace
{

const char *const kName = "pcl_texlet_lab";

/** ", texlet NEES P x (r x ideal), N y (r x ideal)" for the text summary. */
std::string
texletText (const lab::LabMetrics &m)
{
  std::ostringstream s;
  s << std::setprecision (4) << ", texlet NEES P " << m.texlets.nees_p << " (" << m.texlets.ratioP ()
    << " x ideal), N " << m.texlets.nees_n << " (" << m.texlets.ratioN () << " x ideal, " << m.texlets.texlets
    << " texlets)";
  return s.str ();
}

/** "sd_rmse x mm, bias_rmse y mm (spatial SD z mm, model w mm)" for the text summary; single
  * frames have no temporal SD to compare.
  */
std::string
errorsText (const lab::LabMetrics &m)
{
  std::ostringstream s;
  if (std::isfinite (m.sd_rmse_mm))
  {
    s << "sd_rmse " << m.sd_rmse_mm << " mm";
    if (std::isfinite (m.sd_floor_mm))
      s << " (" << m.sd_floor_mm << " mm by chance)";
  }
  else
    s << "sd_rmse not measurable (one frame)";
  s << ", bias_rmse " << m.bias_rmse_mm << " mm (spatial SD " << m.bias_spatial_sd_mm << " mm, model "
    << m.bias_spatial_sd_pred_mm << " mm)";
  return s.str ();
}

/** Measures one recording, streaming: at most \a max_frames evenly spaced frames are kept, and
  * frames that cannot be read are skipped (counted in \a skipped) when \a skip.
  */
lab::RecordingMeasurement::Ptr
measure (const std::string &path, std::size_t max_frames, bool skip, std::size_t &skipped)
{
  pcl::texlet::RecordingReader::Ptr reader = pcl::texlet::openRecording (path);
  std::shared_ptr<pcl::texlet::FrameSkippingReader> skipping;
  if (skip)
    reader = skipping = std::make_shared<pcl::texlet::FrameSkippingReader> (reader, [] (const std::string &m) {
      std::cerr << kName << ": warning: skipped a frame that cannot be read: " << m << std::endl;
    });
  pcl_texlet_app::EvenlySpacedFrames kept (reader, max_frames);
  auto m = lab::measureRecording (kept, path, lab::readMetaYaml (path));
  if (skipping)
    skipped += skipping->skipped ();
  return m;
}

int
run (int argc, char **argv)
{
  std::string model_arg = "paper", report;
  std::vector<std::string> adds, recordings;
  int auto_count = 0, replicates = 5, threads = 0;
  unsigned seed = 1;
  bool quiet = false;
  std::size_t max_frames = 200;
  std::string bad_frames = "skip";
  CLI::App app ("pcl_texlet_lab: compare the noise model with recordings, rank the missing physical effects, add "
                "them and refit");
  app.add_option ("--model", model_arg, "starting model: 'paper' (Eq. 4) or a noise-model YAML file")
      ->capture_default_str ();
  std::string effects;
  for (const auto &e : pcl::texlet::noiseEffectNames ())
    effects += (effects.empty () ? "" : ", ") + e;
  app.add_option ("--add", adds, "add this effect and refit (repeatable, in order): " + effects)
      ->allow_extra_args (false);
  app.add_option ("--auto", auto_count, "then add the N best significant candidates in turn")->capture_default_str ();
  app.add_option ("--report", report, "output folder for report.html, report.json, model.yaml and the PNGs");
  app.add_option ("--null-replicates", replicates, "bootstrap data sets of the significance test")
      ->capture_default_str ();
  app.add_option ("--seed", seed, "seed of the bootstrap")->capture_default_str ();
  app.add_option ("-j,--threads", threads, "threads (0: all)")->capture_default_str ();
  app.add_flag ("-q,--quiet", quiet, "no progress on stderr");
  app.add_option ("--max-frames", max_frames,
                  "frames kept per recording, evenly spaced over it (the rest are read and dropped: memory stays "
                  "bounded however long the recording)")
      ->check (CLI::Range (std::size_t (2), std::size_t (65535)))
      ->capture_default_str ();
  app.add_option ("--bad-frames", bad_frames,
                  "a frame that cannot be read (corrupt, truncated, wrong size): skip (warn on stderr, count in "
                  "report.json) or fail (exit 2)")
      ->check (CLI::IsMember ({"skip", "fail"}))
      ->capture_default_str ();
  app.add_option ("RECORDING", recordings, "recordings: recording folders, PCD folders, grabber TIFF folders, .oni");
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv))
    return 0;
  if (report.empty ())
    throw InputError ("--report OUTDIR is required");
  if (recordings.empty ())
    throw InputError ("no RECORDING given");
  if (auto_count < 0 || auto_count > 20)
    throw InputError ("--auto must be between 0 and 20 (got " + std::to_string (auto_count) + ")");
  if (replicates < 2 || replicates > 100)
    throw InputError ("--null-replicates must be between 2 and 100 (got " + std::to_string (replicates) + ")");
  if (threads < 0 || threads > 1024)
    throw InputError ("--threads " + std::to_string (threads) + " is not a sensible thread count");
  for (const auto &a : adds)
  {
    const auto &names = pcl::texlet::noiseEffectNames ();
    if (std::find (names.begin (), names.end (), a) == names.end ())
      throw InputError ("--add: unknown effect '" + a + "' (known: " + effects + ")");
  }

  const auto t0 = std::chrono::steady_clock::now ();
  auto elapsed = [&] {
    return std::chrono::duration<double> (std::chrono::steady_clock::now () - t0).count ();
  };
  lab::LabSettings settings;
  settings.null_replicates = replicates;
  settings.seed = seed;
  settings.threads = threads;
  if (!quiet)
    settings.progress = [&] (const std::string &line) {
      std::cerr << "[" << std::fixed << std::setprecision (1) << elapsed () << " s] " << line << std::endl;
    };
  pcl::texlet::NoiseModel start =
      model_arg == "paper" ? pcl::texlet::NoiseModel::paper () : pcl::texlet::loadNoiseModelYaml (model_arg);
  for (const auto &a : adds)
    if (start.find (a))
      throw InputError ("--add " + a + ": the starting model already has this effect");
  lab::ModelLab lab (settings);
  std::size_t skipped = 0;
  for (const auto &path : recordings)
  {
    if (settings.progress)
      settings.progress ("lab: measuring " + path);
    lab.addRecording (measure (path, max_frames, bad_frames == "skip", skipped));
  }
  lab::LabSession session = lab::runLabSession (lab, start, model_arg, adds, auto_count);
  session.skipped_frames = skipped;
  if (skipped > 0)
    session.notes.push_back (std::to_string (skipped) + " frame(s) could not be read and were skipped "
                             "(--bad-frames skip; the warnings name them)");
  lab::writeLabReport (lab, session, report);
  if (!quiet)
  {
    std::cout << "start (" << model_arg << "): " << errorsText (session.start_metrics) << ", nll " << session.start_metrics.nll
              << texletText (session.start_metrics) << "\n";
    for (std::size_t k = 0; k < session.candidates.size (); ++k)
    {
      const auto &c = session.candidates[k];
      std::cout << "  candidate " << k + 1 << ": " << c.effect;
      if (c.applicable)
        std::cout << " gain " << c.gain << " (threshold " << c.threshold << "), " << c.effect_shows_in << " error "
                  << 100.0 * c.effect_size << " % of its squared error removed where it shows"
                  << (c.significant ? " significant"
                                    : c.statistically_significant ? " (" + lab::candidateVerdict (c) + ")" : std::string ());
      else
        std::cout << " not testable (" << c.note << ")";
      std::cout << "\n";
    }
    for (const auto &st : session.steps)
      std::cout << "+ " << st.added << ": " << errorsText (st.metrics) << ", nll " << st.metrics.nll
                << texletText (st.metrics) << "\n";
    std::cout << lab::latticeSummary (session.lattice) << "\n";
    std::cout << "skipped frames: " << skipped << "\n";
    std::cout << "report: " << report << "/report.html (" << std::fixed << std::setprecision (1) << elapsed ()
              << " s)" << std::endl;
  }
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
