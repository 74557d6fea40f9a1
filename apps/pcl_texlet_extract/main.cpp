/*
 * pcl_texlet_extract: texlets from an organised PCD file, a folder of them, or any recording
 * openRecording () reads (docs/inputs.md: recording folder, PCL grabber TIFF folder, .oni
 * file), written as texlet PCD files, with a summary on stdout.
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 */
#include "../common/app_main.h"
#include "../common/folder_guard.h"
#include <pcl_texlet/io/frame_skipping_reader.h>
#include <pcl_texlet/camera/depth_image.h>
#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/lab/recording_measurement.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/io/open_recording.h>
#include <pcl_texlet/io/pcd_folder_reader.h>
#include <pcl_texlet/io/openni2_device_reader.h>
#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

namespace fs = std::filesystem;
using pcl::texlet::CameraModel;

using pcl_texlet_app::InputError;
using pcl_texlet_app::pclMessage;

namespace
{

const char *const kName = "pcl_texlet_extract";

struct Options
{
  std::string input, output;
  pcl::texlet::TexletParameters params;
  std::string fit = "pca", uncertainty = "montecarlo", centre = "ray";
  double threshold_mm = 0.0;
  std::vector<double> intrinsics; // fx fy cx cy
  std::string noise_model;        // noise-model YAML (pcl_texlet_lab's model.yaml), or empty: the paper's
  pcl::texlet::NoiseModel noise = pcl::texlet::NoiseModel::paper ();
  unsigned threads = 0;
  bool ascii = false, quiet = false;
  std::string bad_frames = "skip"; // a frame that cannot be read: skip (warn, count) or fail
  std::size_t frames = 0; // frames to read: all of a recording (0), or that many of a live sensor
};

/** A uniform sample of at most kCapacity of the values added (reservoir sampling, fixed seed),
  * so that a summary's medians cost bounded memory however long the recording: exact up to
  * kCapacity values, a sample median beyond.
  */
class ValueSample
{
public:
  static constexpr std::size_t kCapacity = 100000;

  void
  add (double x)
  {
    ++seen_;
    if (values_.size () < kCapacity)
      values_.push_back (x);
    else
    {
      const std::size_t k = std::uniform_int_distribution<std::size_t> (0, seen_ - 1) (rng_);
      if (k < kCapacity)
        values_[k] = x;
    }
  }

  bool
  empty () const { return values_.empty (); }

  const std::vector<double> &
  values () const { return values_; }

private:
  std::vector<double> values_;
  std::size_t seen_ = 0;
  std::mt19937_64 rng_{1};
};

/** Running statistics for the summary. */
struct Summary
{
  std::size_t frames = 0, texlets = 0, valid = 0;
  std::size_t skipped = 0; ///< frames that could not be read, passed over (--bad-frames skip)
  double seconds = 0.0;
  ValueSample position_sd_mm, normal_sd_deg, inlier_share;
};

double
median (std::vector<double> v)
{
  if (v.empty ())
    return std::nan ("");
  std::nth_element (v.begin (), v.begin () + v.size () / 2, v.end ());
  return v[v.size () / 2];
}

/** Writes through a temporary file, renamed once complete. */
void
writeTexlets (const std::string &path, const pcl::PointCloud<pcl::Texlet> &texlets, bool ascii)
{
  pcl::texlet::AtomicFile file (path);
  const std::string &tmp = file.temporaryPath ();
  const int rc = ascii ? pcl::PCDWriter ().writeASCII (tmp, texlets, 9) : pcl::PCDWriter ().writeBinary (tmp, texlets);
  if (rc != 0)
    throw InputError ("cannot write '" + path + "'");
  file.commit ();
}

class Extractor
{
public:
  explicit Extractor (const Options &o) : o_ (o)
  {
    if (o.intrinsics.size () == 4)
      try
      {
        camera_ = std::make_shared<pcl::texlet::PinholeModel> (o.intrinsics[0], o.intrinsics[1], o.intrinsics[2],
                                                                o.intrinsics[3]);
      }
      catch (const pcl::PCLException &e)
      {
        throw InputError ("--camera: " + pclMessage (e.what ()));
      }
  }

  /** Texlets of one organised cloud, written to `out`. */
  template <typename PointT> void
  run (const typename pcl::PointCloud<PointT>::ConstPtr &cloud, const CameraModel::ConstPtr &camera,
       const std::string &source, const std::string &out)
  {
    pcl::TexletEstimation<PointT> est;
    est.setParameters (o_.params);
    est.setNoiseModel (o_.noise);
    est.setNoiseContext (context_);
    est.setNumberOfThreads (o_.threads);
    est.setInputCloud (cloud);
    est.setCameraModel (camera_ ? camera_ : camera);
    pcl::PointCloud<pcl::Texlet> texlets;
    const auto t0 = std::chrono::steady_clock::now ();
    try
    {
      est.compute (texlets);
    }
    catch (const pcl::PCLException &e)
    {
      throw InputError (source + ": " + pclMessage (e.what ()));
    }
    const double s = std::chrono::duration<double> (std::chrono::steady_clock::now () - t0).count ();
    writeTexlets (out, texlets, o_.ascii);

    const double disc = static_cast<double> (pcl::texlet::kernels::pixelDiscSize (o_.params.radius));
    std::size_t valid = 0;
    for (const auto &t : texlets)
    {
      if (!std::isfinite (t.x))
        continue;
      ++valid;
      sum_.inlier_share.add (t.support / disc);
      if (std::isfinite (t.cov_p_xx))
      {
        sum_.position_sd_mm.add (1e3 * std::sqrt (t.cov_p_xx + t.cov_p_yy + t.cov_p_zz));
        sum_.normal_sd_deg.add (180.0 / M_PI * std::sqrt (t.cov_n_11 + t.cov_n_22));
      }
    }
    ++sum_.frames;
    sum_.texlets += texlets.size ();
    sum_.valid += valid;
    sum_.seconds += s;
    if (!o_.quiet && frames_total_ > 1)
      std::cerr << kName << ": frame " << sum_.frames << "/" << frames_total_ << " " << fs::path (source).filename ().string ()
                << ": " << valid << "/" << texlets.size () << " texlets in " << std::fixed << std::setprecision (1)
                << 1e3 * s << " ms" << std::defaultfloat << std::endl;
  }

  void
  setFrameCount (std::size_t n) { frames_total_ = n; }

  /** What the noise model needs that a cloud does not carry (f b, frame, projectors), as the lab
    * sets it when it fits the model; the default (a VGA Kinect v1, steady state, one projector)
    * for clouds from PCD files.
    */
  void
  setNoiseContext (const pcl::texlet::PixelContext &context) { context_ = context; }

  void
  noteSkipped (std::size_t n) { sum_.skipped += n; }

  const Summary &
  summary () const { return sum_; }

private:
  const Options &o_;
  CameraModel::ConstPtr camera_;
  pcl::texlet::PixelContext context_;
  Summary sum_;
  std::size_t frames_total_ = 1;
};

/** An organised PCD file, read: XYZRGBA when it has colour, XYZ otherwise. */
struct PcdCloud
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr xyz;
  pcl::PointCloud<pcl::PointXYZRGBA>::Ptr rgba;
};

/** \throws InputError naming the file: missing, not a PCD file, no x/y/z, unorganised, truncated. */
PcdCloud
loadPcd (const std::string &file)
{
  if (!fs::is_regular_file (file))
    throw InputError ("input '" + file + "' does not exist or is not a file");
  pcl::PCLPointCloud2 header;
  int version, type;
  unsigned int offset;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  if (pcl::PCDReader ().readHeader (file, header, origin, orientation, version, type, offset) != 0)
    throw InputError ("cannot read '" + file + "': not a PCD file or a corrupt header");
  bool colour = false;
  int xyz = 0;
  for (const auto &f : header.fields)
  {
    colour |= f.name == "rgb" || f.name == "rgba";
    xyz += (f.name == "x" || f.name == "y" || f.name == "z") ? 1 : 0;
  }
  if (xyz != 3)
    throw InputError ("'" + file + "' has no x, y, z fields");
  if (header.height <= 1)
    throw InputError ("'" + file + "' is not an organised cloud (height " + std::to_string (header.height) +
                      "): texlets need the pixel grid of a depth image");
  const auto load = [&] (auto cloud) {
    if (pcl::io::loadPCDFile (file, *cloud) != 0 || cloud->size () != static_cast<std::size_t> (header.width) * header.height)
      throw InputError ("cannot read '" + file + "': corrupt or truncated PCD data");
    return cloud;
  };
  PcdCloud c;
  if (colour)
    c.rgba = load (std::make_shared<pcl::PointCloud<pcl::PointXYZRGBA>> ());
  else
    c.xyz = load (std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ());
  return c;
}

void
extractPcd (Extractor &ex, const PcdCloud &c, const std::string &file, const std::string &out)
{
  if (c.rgba)
    ex.run<pcl::PointXYZRGBA> (c.rgba, nullptr, file, out);
  else
    ex.run<pcl::PointXYZ> (c.xyz, nullptr, file, out);
}

/** Warns on stderr of a frame passed over; shown even with --quiet, since output is missing. */
void
warnSkipped (const std::string &message)
{
  std::cerr << kName << ": warning: skipped a frame that cannot be read: " << message << std::endl;
}

/** Every frame of a recording, back-projected with the recording's own camera. The noise model
  * gets what the recording knows, as in the lab that fits it: f b from its camera (the terms
  * defined in disparity, at its resolution), the active projectors from \a meta_yaml (its
  * meta.yaml text, "" for none) and each frame's index (in the order read, as the lab counts).
  */
void
extractRecording (Extractor &ex, pcl::texlet::RecordingReader &reader, pcl::texlet::RecordingKind kind,
                  const std::string &input, const std::string &out_dir, const std::string &meta_yaml,
                  std::size_t max_frames = 0)
{
  const auto &info = reader.cameraInfo ();
  const auto camera = std::make_shared<pcl::texlet::PinholeModel> (pcl::texlet::PinholeModel::fromCameraInfo (info));
  pcl::texlet::PixelContext context = pcl::texlet::lab::recordingNoiseContext (info, meta_yaml, input);
  const std::size_t frames = max_frames > 0 ? std::min (max_frames, reader.size ()) : reader.size ();
  ex.setFrameCount (frames);
  pcl::texlet::DepthFrame frame;
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZRGBA>> ();
  for (std::size_t read = 0; read < frames && reader.next (frame); ++read)
  {
    context.frame = static_cast<double> (read);
    ex.setNoiseContext (context);
    pcl::texlet::depthToCloud (frame, *camera, *cloud);
    // Names the frame's file where there is one, else the frame within the input.
    const std::string source = kind == pcl::texlet::RecordingKind::recording_folder
                                   ? input + "/depth/" + frame.name + ".png"
                                   : (fs::path (input) / frame.name).string ();
    ex.run<pcl::PointXYZRGBA> (cloud, camera, source, (fs::path (out_dir) / (frame.name + ".pcd")).string ());
  }
}

/** \return the files that could not be read and were skipped (0 unless \a skip). */
std::size_t
extractPcdFolder (Extractor &ex, const std::vector<std::string> &files, const std::string &out_dir, bool skip)
{
  ex.setFrameCount (files.size ());
  std::size_t skipped = 0;
  for (const auto &f : files)
  {
    PcdCloud cloud;
    try
    {
      cloud = loadPcd (f);
    }
    catch (const InputError &e)
    {
      if (!skip)
        throw;
      warnSkipped (e.what ());
      ++skipped;
      continue;
    }
    extractPcd (ex, cloud, f, (fs::path (out_dir) / fs::path (f).filename ()).string ());
  }
  return skipped;
}

void
printSummary (const Summary &s, const Options &o)
{
  std::cout << std::fixed << std::setprecision (3);
  std::cout << "frames:                " << s.frames << "\n"
            << "texlets:               " << s.valid << " valid of " << s.texlets << " centres ("
            << (s.texlets ? 100.0 * s.valid / s.texlets : 0.0) << " %)\n"
            << "time:                  " << 1e3 * s.seconds / std::max<std::size_t> (s.frames, 1) << " ms per frame ("
            << pcl::texlet::toString (o.params.fit) << ", " << pcl::texlet::toString (o.params.uncertainty) << ")\n"
            << "median inlier share:   " << 100.0 * median (s.inlier_share.values ()) << " % of the disc\n";
  if (!s.position_sd_mm.empty ())
    std::cout << "median position SD:    " << median (s.position_sd_mm.values ()) << " mm  (sqrt trace Sigma_P)\n"
              << "median normal SD:      " << median (s.normal_sd_deg.values ()) << " deg (sqrt trace Sigma_N)\n";
  std::cout << "skipped frames:        " << s.skipped << " (could not be read; --bad-frames " << o.bad_frames
            << ")\n";
  std::cout << "output:                " << o.output << std::endl;
}

int
run (int argc, char **argv)
{
  Options o;
  CLI::App app ("Extract texlets (surface patches with uncertainties) from organised depth data.\n"
                "INPUT: an organised PCD file, a folder of them, a recording folder (camera.yaml + depth/*.png),\n"
                "a folder of PCL image grabber frames (tiff/*_depth.tiff + intrinsics.xml) or an .oni file.\n"
                "OUTPUT: a texlet PCD file for a PCD file input, else a folder with one texlet PCD per frame.",
                kName);
  app.add_option ("INPUT", o.input, "organised PCD file, folder of PCD files, recording folder, grabber TIFF folder, "
                                    ".oni file, or a live OpenNI2 device: 'sensor' (the first one) or 'sensor:URI' "
                                    "(e.g. sensor:pcltexlet:sim=plane;seed=1, docs/openni2_device.md)")
      ->required ();
  app.add_option ("OUTPUT", o.output, "texlet PCD file, or output folder for several frames")->required ();
  app.add_option ("-s,--spacing", o.params.spacing, "hexagonal grid spacing, pixels")->capture_default_str ();
  app.add_option ("-r,--radius", o.params.radius, "neighbourhood radius, pixels")->capture_default_str ();
  app.add_option ("-i,--iterations", o.params.ransac_iterations, "RANSAC iterations")->capture_default_str ();
  app.add_option ("-t,--threshold", o.threshold_mm, "RANSAC inlier distance, mm (0: from the noise model)")
      ->capture_default_str ();
  app.add_option ("--sigmas", o.params.threshold_sigmas, "automatic threshold in depth SDs")->capture_default_str ();
  app.add_option ("--robust-sigmas", o.params.robust_sigmas,
                  "the automatic threshold widens to this many of the patch's own depth SDs where they exceed the "
                  "model's (0: the model's threshold alone, the paper's)")
      ->capture_default_str ();
  app.add_option ("-f,--fit", o.fit, "plane fit: pca, svd, averaging")->capture_default_str ();
  app.add_option ("--centre", o.centre,
                  "texlet centre P: ray (where the centre pixel's ray meets the plane) or mean (the inliers' mean, "
                  "the paper's)")
      ->capture_default_str ();
  app.add_option ("-u,--uncertainty", o.uncertainty, "uncertainty: montecarlo, analytic, none")->capture_default_str ();
  app.add_option ("-n,--samples", o.params.samples, "Monte Carlo samples")->capture_default_str ();
  app.add_option ("--seed", o.params.seed, "random seed")->capture_default_str ();
  app.add_option ("--min-support", o.params.min_support, "fewest inliers for a texlet")->capture_default_str ();
  app.add_flag ("--keep-model-bias{false}", o.params.remove_model_bias,
                "fit the readings as they are (default: each depth loses the noise model's bias first, where a "
                "term of the model moves the mean)");
  app.add_flag ("--exact-window-form", o.params.exact_window_form,
                "form every texlet's noise shared over a window (spatial_correlation) by the windows' sums (default: "
                "discs missing few readings or inliers from tables; docs/benchmarks.md)");
  app.add_option ("--camera", o.intrinsics, "pinhole intrinsics fx fy cx cy, pixels (default: the recording's, "
                                            "or estimated from each PCD cloud)")
      ->expected (4);
  app.add_option ("--noise-model", o.noise_model,
                  "depth noise model YAML (e.g. the model.yaml pcl_texlet_lab writes; default: the paper's Eq. 4)");
  app.add_option ("-j,--threads", o.threads, "threads (0: all)")->capture_default_str ();
  app.add_flag ("--ascii", o.ascii, "write ASCII PCD (9 significant digits: exact) instead of binary");
  app.add_option ("--frames", o.frames, "frames to read: needed for a live sensor; the first N of a recording "
                                        "(0: all)")
      ->capture_default_str ();
  app.add_flag ("-q,--quiet", o.quiet, "no progress lines");
  app.add_option ("--bad-frames", o.bad_frames,
                  "a frame of a recording or PCD folder that cannot be read (corrupt, truncated, wrong size): "
                  "skip (warn on stderr, count in the summary) or fail (exit 2)")
      ->check (CLI::IsMember ({"skip", "fail"}))
      ->capture_default_str ();
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv))
    return 0;

  o.params.fit = pcl::texlet::planeFitMethodFromString (o.fit);
  o.params.uncertainty = pcl::texlet::uncertaintyMethodFromString (o.uncertainty);
  o.params.centre = pcl::texlet::texletCentreFromString (o.centre);
  o.params.ransac_threshold = o.threshold_mm * 1e-3;
  pcl::texlet::validate (o.params);
  if (!o.noise_model.empty ())
    o.noise = pcl::texlet::loadNoiseModelYaml (o.noise_model);
  if (o.threads > 1024)
    throw InputError ("--threads " + std::to_string (o.threads) + " is not a sensible thread count");
  Extractor ex (o);
  const bool skip = o.bad_frames == "skip";

  if (o.input == "sensor" || o.input.rfind ("sensor:", 0) == 0)
  {
    if (o.frames == 0)
      throw InputError ("a live sensor needs --frames N (how many frames to read)");
    if (fs::exists (o.output) && !fs::is_directory (o.output))
      throw InputError ("OUTPUT '" + o.output + "' must be a folder when INPUT is a sensor");
    pcl::texlet::OpenNI2DeviceReader reader (o.input == "sensor" ? "" : o.input.substr (7), o.frames);
    pcl_texlet_app::FolderGuard made (fs::exists (o.output) ? fs::path () : fs::path (o.output));
    fs::create_directories (o.output);
    extractRecording (ex, reader, pcl::texlet::RecordingKind::oni_file, o.input, o.output, "");
    made.release ();
    printSummary (ex.summary (), o);
    return 0;
  }

  std::string extension = fs::path (o.input).extension ().string ();
  std::transform (extension.begin (), extension.end (), extension.begin (), [] (unsigned char c) { return std::tolower (c); });
  if (fs::is_directory (o.input) || extension == ".oni")
  {
    if (fs::exists (o.output) && !fs::is_directory (o.output))
      throw InputError ("OUTPUT '" + o.output + "' must be a folder when INPUT is a folder or an .oni file");
    // Inputs are checked before the output folder is made; a folder this run made goes again
    // if the run fails.
    const pcl::texlet::RecordingKind kind = pcl::texlet::recordingKind (o.input);
    pcl_texlet_app::FolderGuard made (fs::exists (o.output) ? fs::path () : fs::path (o.output));
    std::size_t frames = 0;
    if (kind == pcl::texlet::RecordingKind::pcd_folder)
    {
      // The clouds themselves, not depth re-projected: their points and any camera stay exact.
      const auto files = pcl::texlet::PcdFolderReader::listPcdFiles (o.input);
      frames = files.size ();
      fs::create_directories (o.output);
      ex.noteSkipped (extractPcdFolder (ex, files, o.output, skip));
    }
    else
    {
      pcl::texlet::RecordingReader::Ptr reader = pcl::texlet::openRecording (o.input);
      const std::string meta = pcl::texlet::lab::readMetaYaml (o.input);
      frames = reader->size ();
      std::shared_ptr<pcl::texlet::FrameSkippingReader> skipping;
      if (skip)
        reader = skipping = std::make_shared<pcl::texlet::FrameSkippingReader> (reader, warnSkipped);
      fs::create_directories (o.output);
      extractRecording (ex, *reader, kind, o.input, o.output, meta, o.frames);
      if (skipping)
        ex.noteSkipped (skipping->skipped ());
    }
    if (ex.summary ().frames == 0)
      throw InputError ("no frame of '" + o.input + "' could be read (" + std::to_string (frames) +
                        " skipped; see the warnings)");
    made.release ();
  }
  else
  {
    if (!fs::exists (fs::absolute (o.output).parent_path ()))
      throw InputError ("the folder that should hold OUTPUT '" + o.output + "' does not exist");
    extractPcd (ex, loadPcd (o.input), o.input, o.output);
  }
  printSummary (ex.summary (), o);
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
