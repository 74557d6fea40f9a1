/*
 * pcl_texlet_bench: texlets against PCL's normal estimators, in one run, at the same centres
 * with the same pixel neighbourhood; accuracy on simulated scenes with ground truth; the
 * paper's Table 1 and Fig. 8; time against the number of texlets and the neighbourhood size.
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 */
#include "../common/app_main.h"
#include "harness.h"
#include "methods.h"
#include "scenes.h"

#include <pcl_texlet/camera/camera_estimation.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <omp.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using nlohmann::json;
using pcl_texlet_app::InputError;
using pcl_texlet_app::pclMessage;
using namespace pcl_texlet_bench;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::UncertaintyMethod;

namespace
{

const char *const kName = "pcl_texlet_bench";

#ifndef PCL_TEXLET_DEFAULT_FRAME
#define PCL_TEXLET_DEFAULT_FRAME ""
#endif

struct Options
{
  std::string input = PCL_TEXLET_DEFAULT_FRAME;
  std::string scene; // simulated input instead of a PCD
  int sim_width = 640, sim_height = 480;
  Setup setup;
  std::vector<std::string> fits = {"pca", "svd", "averaging"};
  int repetitions = 15, warmup = 2;
  bool organized_knn = true;
  bool timing = true, accuracy = true, table1 = false, fig8 = false, scaling = false;
  int table1_reps = 5, scaling_reps = 5, fig8_runs = 100;
  std::string json_path, data_dir;
  bool quiet = false;
};

void
progress (const Options &o, const std::string &line)
{
  if (!o.quiet)
    std::cerr << kName << ": " << line << std::endl;
}

/** Writes to a temporary name in the same folder and renames it when complete. */
void
writeAtomically (const std::string &path, const std::string &text)
{
  const fs::path target (path);
  if (!target.parent_path ().empty () && !fs::is_directory (target.parent_path ()))
    throw InputError ("the folder of '" + path + "' does not exist");
  const fs::path tmp = target.parent_path () / ("." + target.filename ().string () + ".tmp");
  {
    std::ofstream f (tmp);
    f << text;
    if (!f)
    {
      std::error_code ec;
      fs::remove (tmp, ec);
      throw InputError ("cannot write '" + path + "'");
    }
  }
  std::error_code ec;
  fs::rename (tmp, target, ec);
  if (ec)
  {
    fs::remove (tmp, ec);
    throw InputError ("cannot write '" + path + "': " + ec.message ());
  }
}

std::string
cpuModel ()
{
  std::ifstream f ("/proc/cpuinfo");
  std::string line;
  while (std::getline (f, line))
    if (line.rfind ("model name", 0) == 0)
      return line.substr (line.find (':') + 2);
  return "unknown";
}

double
loadAverage ()
{
  std::ifstream f ("/proc/loadavg");
  double l = NAN;
  f >> l;
  return l;
}

json
spreadJson (const Spread &s)
{
  return {{"median", s.median}, {"q1", s.q1}, {"q3", s.q3}, {"min", s.min}, {"max", s.max}};
}

/** NaN is not JSON: it becomes null. */
json
num (double x)
{
  return std::isfinite (x) ? json (x) : json (nullptr);
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

/** The input: an organised PCD (as XYZ) with a pinhole estimated from it once, or a scene. */
struct Input
{
  std::string description;
  Cloud::Ptr cloud;
  pcl::texlet::CameraModel::ConstPtr camera;
};

Input
loadInput (const Options &o)
{
  Input in;
  if (!o.scene.empty ())
  {
    const SimulatedScene s = simulateScene (o.scene, o.sim_width, o.sim_height, 1);
    in.cloud = s.cloud;
    in.camera = s.camera;
    in.description = "simulated " + o.scene + " " + std::to_string (o.sim_width) + "x" + std::to_string (o.sim_height);
    return in;
  }
  if (o.input.empty ())
    throw InputError ("no INPUT given and no bundled frame known: give an organised PCD file or --scene");
  if (!fs::is_regular_file (o.input))
    throw InputError ("input '" + o.input + "' does not exist or is not a file");
  pcl::PCLPointCloud2 header;
  int version, type;
  unsigned int offset;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  if (pcl::PCDReader ().readHeader (o.input, header, origin, orientation, version, type, offset) != 0)
    throw InputError ("cannot read '" + o.input + "': not a PCD file or a corrupt header");
  if (header.height <= 1)
    throw InputError ("'" + o.input + "' is not an organised cloud (height " + std::to_string (header.height) + ")");
  in.cloud = std::make_shared<Cloud> ();
  if (pcl::io::loadPCDFile (o.input, *in.cloud) != 0 ||
      in.cloud->size () != static_cast<std::size_t> (header.width) * header.height)
    throw InputError ("cannot read '" + o.input + "': corrupt or truncated PCD data");
  try
  {
    in.camera = std::make_shared<pcl::texlet::PinholeModel> (pcl::texlet::estimatePinholeModel (*in.cloud));
  }
  catch (const pcl::PCLException &e)
  {
    throw InputError ("'" + o.input + "': " + pclMessage (e.what ()));
  }
  in.description = fs::path (o.input).filename ().string () + " " + std::to_string (in.cloud->width) + "x" +
                   std::to_string (in.cloud->height);
  return in;
}

std::string
fmt (double x, int precision = 1)
{
  if (!std::isfinite (x))
    return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision (precision) << x;
  return s.str ();
}

std::size_t
countFinite (const MethodOutput &out)
{
  std::size_t n = 0;
  for (const auto &v : out.normal)
    n += v.allFinite () ? 1 : 0;
  return n;
}

double
meanFinite (const std::vector<float> &v)
{
  double s = 0;
  std::size_t n = 0;
  for (const float x : v)
    if (std::isfinite (x))
    {
      s += x;
      ++n;
    }
  return n ? s / n : NAN;
}

// --- timing at the same centres -----------------------------------------------------------

json
runTiming (const Options &o, const Input &in, const std::vector<MethodSpec> &methods)
{
  const auto centres = hexCentres (static_cast<int> (in.cloud->width), static_cast<int> (in.cloud->height),
                                   o.setup.spacing);
  const std::vector<int> valid_disc = validDiscCounts (in.cloud, *centres, o.setup.radius);

  progress (o, "checking that NormalEstimationOMP sees exactly the texlets' neighbourhoods");
  const NeighbourhoodCheck check = checkSameNeighbourhood (o.setup, in.cloud, centres, valid_disc, in.camera);

  std::vector<std::unique_ptr<MethodRunner>> owned;
  std::vector<MethodRunner *> runners;
  int reference = -1;
  for (std::size_t i = 0; i < methods.size (); ++i)
  {
    owned.push_back (makeRunner (methods[i], o.setup, in.cloud, centres, valid_disc, in.camera));
    runners.push_back (owned.back ().get ());
    if (methods[i].kind == MethodKind::NormalOmpDisc)
      reference = static_cast<int> (i);
  }
  const double load_before = loadAverage ();
  progress (o, "timing " + std::to_string (methods.size ()) + " methods on " + in.description + ": " +
                   std::to_string (o.warmup) + " warm-up + " + std::to_string (o.repetitions) +
                   " repetitions, interleaved, " + std::to_string (o.setup.threads) + " threads");
  const auto t = timeInterleaved (runners, reference, o.warmup, o.repetitions, [&] (int done, int total) {
    progress (o, "  timing repetition " + std::to_string (done) + "/" + std::to_string (total) +
                     (done <= o.warmup ? " (warm-up)" : ""));
  });
  const double load_after = loadAverage ();

  json j;
  j["input"] = in.description;
  j["centres"] = centres->size ();
  j["repetitions"] = o.repetitions;
  j["warmup"] = o.warmup;
  j["reference"] = reference >= 0 ? methods[reference].name : "";
  j["load_average_before"] = num (load_before);
  j["load_average_after"] = num (load_after);
  j["neighbourhood_check"] = {{"centres", check.centres},         {"compared", check.compared},
                              {"support_equal", check.support_equal}, {"centre_equal", check.centre_equal},
                              {"median_angle_deg", num (check.median_angle_deg)},
                              {"p99_angle_deg", num (check.p99_angle_deg)},
                              {"max_angle_deg", num (check.max_angle_deg)}};
  const double ref_median = reference >= 0 ? spread (t[reference].ms).median : NAN;

  std::cout << "\n== Time on " << in.description << ", spacing " << o.setup.spacing << ", radius " << o.setup.radius
            << " (" << pcl::texlet::kernels::pixelDiscSize (o.setup.radius) << " px), " << o.setup.iterations
            << " RANSAC iterations, " << o.setup.threads << " threads, " << centres->size () << " centres ==\n"
            << "median of " << o.repetitions << " interleaved repetitions after " << o.warmup
            << " warm-up; ratios = median of per-repetition ratios to " << (reference >= 0 ? methods[reference].name : "-")
            << "; CPU = process CPU time, all threads; load average " << fmt (load_before, 2) << " before, "
            << fmt (load_after, 2) << " after\n";
  std::cout << std::left << std::setw (34) << "method" << std::right << std::setw (9) << "wall ms" << std::setw (16)
            << "IQR" << std::setw (16) << "min-max" << std::setw (7) << "ratio" << std::setw (9) << "CPU ms"
            << std::setw (7) << "ratio" << std::setw (9) << "normals" << std::setw (9) << "inliers" << "\n";
  for (std::size_t i = 0; i < methods.size (); ++i)
  {
    const Spread s = spread (t[i].ms), c = spread (t[i].cpu_ms);
    const MethodOutput out = owned[i]->output ();
    const std::size_t made = countFinite (out);
    const double share = meanFinite (out.inlier_share);
    const double ratio = reference >= 0 ? spread (t[i].ratio).median : NAN;
    const double cpu_ratio = reference >= 0 ? spread (t[i].cpu_ratio).median : NAN;
    std::cout << std::left << std::setw (34) << methods[i].name << std::right << std::setw (9) << fmt (s.median)
              << std::setw (16) << (fmt (s.q1) + "-" + fmt (s.q3)) << std::setw (16) << (fmt (s.min) + "-" + fmt (s.max))
              << std::setw (7) << fmt (ratio, 2) << std::setw (9) << fmt (c.median) << std::setw (7) << fmt (cpu_ratio, 2)
              << std::setw (9) << made << std::setw (8) << fmt (100.0 * share) << "%\n";
    json m;
    m["name"] = methods[i].name;
    m["description"] = methods[i].description (o.setup.radius, o.setup.samples);
    m["centres"] = out.normal.size ();
    m["normals"] = made;
    m["inlier_share"] = num (share);
    m["time_ms"] = spreadJson (s);
    m["times_ms"] = t[i].ms;
    m["ratio_to_reference"] = num (ratio);
    m["ratio_of_medians"] = num (s.median / ref_median);
    m["cpu_time_ms"] = spreadJson (c);
    m["cpu_ratio_to_reference"] = num (cpu_ratio);
    j["methods"].push_back (m);
  }
  // The speed targets, as ratios to NormalEstimationOMP in this run (PCA fit): to the
  // same-neighbourhood reference, and to OrganizedNeighbor kNN of the same size (k = disc size),
  // which is how PCL users usually run it on organised clouds.
  int knn = -1;
  for (std::size_t i = 0; i < methods.size (); ++i)
    if (methods[i].kind == MethodKind::NormalOmpOrganized)
      knn = static_cast<int> (i);
  const auto medianRatio = [&] (int i, int ref, bool cpu) {
    if (ref < 0)
      return static_cast<double> (NAN);
    std::vector<double> r;
    for (std::size_t k = 0; k < t[i].ms.size (); ++k)
      r.push_back (cpu ? t[i].cpu_ms[k] / t[ref].cpu_ms[k] : t[i].ms[k] / t[ref].ms[k]);
    return quantile (r, 0.5);
  };
  const std::pair<const char *, double> targets[] = {
      {"texlet/none/pca", 0.35}, {"texlet/analytic/pca", 0.6}, {"texlet/montecarlo/pca", 1.5}};
  std::cout << "targets, ratio wall / CPU to " << (reference >= 0 ? methods[reference].name : "-")
            << (knn >= 0 ? " [and to " + methods[knn].name + "]" : std::string ()) << ":\n";
  for (const auto &[name, target] : targets)
    for (std::size_t i = 0; i < methods.size (); ++i)
      if (methods[i].name == name)
      {
        const int ii = static_cast<int> (i);
        const double r = medianRatio (ii, reference, false), rc = medianRatio (ii, reference, true);
        const double rk = medianRatio (ii, knn, false), rkc = medianRatio (ii, knn, true);
        j["targets"].push_back ({{"name", name},
                                 {"target_ratio", target},
                                 {"ratio", num (r)},
                                 {"cpu_ratio", num (rc)},
                                 {"met", r <= target},
                                 {"met_cpu", rc <= target},
                                 {"ratio_to_organized_knn", num (rk)},
                                 {"cpu_ratio_to_organized_knn", num (rkc)}});
        std::cout << "  " << std::left << std::setw (24) << name << std::right << fmt (r, 2) << " / " << fmt (rc, 2)
                  << " [" << fmt (rk, 2) << " / " << fmt (rkc, 2) << "]  (target <= " << fmt (target, 2) << ")\n";
      }
  std::cout << "neighbourhood check: texlet support == PixelDiscSearch neighbours at " << check.support_equal << "/"
            << check.centres << " centres, same centre pixel at " << check.centre_equal << "/" << check.centres
            << "; normals of TexletEstimation (PCA, all inliers) vs NormalEstimationOMP: median "
            << fmt (check.median_angle_deg, 5) << " deg, p99 " << fmt (check.p99_angle_deg, 5) << " deg over "
            << check.compared << " centres\n";
  return j;
}

// --- accuracy on simulated scenes ---------------------------------------------------------

struct Errors
{
  std::vector<double> all, edge, away;
};

json
errorJson (const std::vector<double> &e)
{
  double mean = 0;
  for (const double x : e)
    mean += x / e.size ();
  return {{"n", e.size ()}, {"mean_deg", num (e.empty () ? NAN : mean)}, {"p95_deg", num (quantile (e, 0.95))}};
}

double
meanOf (const std::vector<double> &e)
{
  double m = 0;
  for (const double x : e)
    m += x / e.size ();
  return e.empty () ? NAN : m;
}

json
runAccuracy (const Options &o, const std::vector<MethodSpec> &methods)
{
  json j;
  j["noise"] = "the paper's Eq. 4 (in disparity), depth in whole mm, projector shadows; no other effect";
  j["error"] = "angle between the estimated and the true normal, degrees, sign ignored; texlets are scored "
               "at the pixel their P projects to, PCL's normals at their centre pixel";
  j["edges"] = "near edges: the centre's pixel disc holds a pixel at a depth step (> 2 cm), a crease "
               "(> 30 deg), or a border of no surface or no reading";
  std::vector<Errors> pooled (methods.size ());
  for (const std::string &name : sceneNames ())
  {
    progress (o, "accuracy: simulating the " + name + " scene (" + std::to_string (o.sim_width) + "x" +
                     std::to_string (o.sim_height) + ")");
    const SimulatedScene s = simulateScene (name, o.sim_width, o.sim_height, 7);
    const int w = static_cast<int> (s.cloud->width), h = static_cast<int> (s.cloud->height);
    const auto centres = hexCentres (w, h, o.setup.spacing);
    const auto valid_disc = validDiscCounts (s.cloud, *centres, o.setup.radius);
    const auto near = nearEdge (edgePixels (s), w, h, *centres, o.setup.radius);
    const auto *pin = dynamic_cast<const pcl::texlet::PinholeModel *> (s.camera.get ());
    json js;
    js["name"] = name;
    js["centres"] = centres->size ();
    std::size_t near_count = 0;
    for (const auto b : near)
      near_count += b;
    js["near_edge_centres"] = near_count;
    std::cout << "\n== Accuracy on the simulated " << name << " scene (" << w << "x" << h << ", " << centres->size ()
              << " centres, " << near_count << " near edges): angle to the true normal, degrees ==\n"
              << std::left << std::setw (34) << "method" << std::right << std::setw (8) << "n" << std::setw (8)
              << "mean" << std::setw (8) << "p95" << std::setw (10) << "n edge" << std::setw (8) << "mean"
              << std::setw (8) << "p95" << "\n";
    for (std::size_t m = 0; m < methods.size (); ++m)
    {
      auto runner = makeRunner (methods[m], o.setup, s.cloud, centres, valid_disc, s.camera);
      runner->run ();
      const MethodOutput out = runner->output ();
      Errors e;
      for (std::size_t c = 0; c < out.normal.size (); ++c)
      {
        if (!out.normal[c].allFinite ())
          continue;
        int pixel = (*centres)[c];
        if (methods[m].kind == MethodKind::Texlet && out.position[c].allFinite () && pin)
        {
          const Eigen::Vector3f &p = out.position[c];
          const int u = static_cast<int> (std::lround (pin->fx () * p.x () / p.z () + pin->cx ()));
          const int v = static_cast<int> (std::lround (pin->fy () * p.y () / p.z () + pin->cy ()));
          if (u < 0 || v < 0 || u >= w || v >= h)
            continue;
          pixel = v * w + u;
        }
        const Eigen::Vector3d t = s.truth_normal[pixel].cast<double> ();
        if (!t.allFinite ())
          continue;
        const Eigen::Vector3d n = out.normal[c].cast<double> ();
        const double deg = std::atan2 (n.cross (t).norm (), std::fabs (n.dot (t))) * 180.0 / M_PI;
        e.all.push_back (deg);
        (near[c] ? e.edge : e.away).push_back (deg);
      }
      pooled[m].all.insert (pooled[m].all.end (), e.all.begin (), e.all.end ());
      pooled[m].edge.insert (pooled[m].edge.end (), e.edge.begin (), e.edge.end ());
      pooled[m].away.insert (pooled[m].away.end (), e.away.begin (), e.away.end ());
      js["methods"].push_back ({{"name", methods[m].name},
                                {"all", errorJson (e.all)},
                                {"near_edges", errorJson (e.edge)},
                                {"away_from_edges", errorJson (e.away)}});
      std::cout << std::left << std::setw (34) << methods[m].name << std::right << std::setw (8) << e.all.size ()
                << std::setw (8) << fmt (meanOf (e.all), 2) << std::setw (8) << fmt (quantile (e.all, 0.95), 2)
                << std::setw (10) << e.edge.size () << std::setw (8) << fmt (meanOf (e.edge), 2) << std::setw (8)
                << fmt (quantile (e.edge, 0.95), 2) << "\n";
    }
    j["scenes"].push_back (js);
  }
  std::cout << "\n== Accuracy over all three scenes, degrees ==\n"
            << std::left << std::setw (34) << "method" << std::right << std::setw (8) << "mean" << std::setw (8)
            << "p95" << std::setw (12) << "mean edge" << std::setw (10) << "p95 edge" << std::setw (12) << "mean away"
            << std::setw (10) << "p95 away" << "\n";
  for (std::size_t m = 0; m < methods.size (); ++m)
  {
    const Errors &e = pooled[m];
    j["overall"].push_back ({{"name", methods[m].name},
                             {"all", errorJson (e.all)},
                             {"near_edges", errorJson (e.edge)},
                             {"away_from_edges", errorJson (e.away)}});
    std::cout << std::left << std::setw (34) << methods[m].name << std::right << std::setw (8) << fmt (meanOf (e.all), 2)
              << std::setw (8) << fmt (quantile (e.all, 0.95), 2) << std::setw (12) << fmt (meanOf (e.edge), 2)
              << std::setw (10) << fmt (quantile (e.edge, 0.95), 2) << std::setw (12) << fmt (meanOf (e.away), 2)
              << std::setw (10) << fmt (quantile (e.away, 0.95), 2) << "\n";
  }
  return j;
}

// --- the paper's Table 1 ------------------------------------------------------------------

struct PaperRow
{
  const char *variable;
  int spacing, radius;
  double ms;
  int texlets;
  double inliers_pct;
};

// Olesen et al., Table 1: 640x480, 20 RANSAC iterations, 50 Monte Carlo samples, a 2012 GPU.
const PaperRow kPaperTable1[] = {
    {"spacing", 2, 6, 288.7, 38321, 61.8}, {"spacing", 6, 6, 89.8, 9814, 61.7},
    {"spacing", 8, 6, 33.1, 2430, 61.4},   {"radius", 6, 4, 68.1, 10715, 48.3},
    {"radius", 6, 6, 89.8, 9814, 61.7},    {"radius", 6, 8, 127.7, 9060, 75.1},
};

json
runTable1 (const Options &o, const Input &in)
{
  json j = json::array ();
  std::cout << "\n== The paper's Table 1, measured here on " << in.description << " (" << o.setup.threads
            << " CPU threads) beside the paper's (GPU, 2012); ours: PCA, " << o.setup.iterations
            << " RANSAC iterations ==\n"
            << std::left << std::setw (9) << "variable" << std::right << std::setw (5) << "px" << std::setw (12)
            << "paper ms" << std::setw (10) << "MC50 ms" << std::setw (10) << "none ms" << std::setw (10)
            << "NE-OMP ms" << std::setw (12) << "paper texl" << std::setw (9) << "texlets" << std::setw (10)
            << "centres" << std::setw (12) << "paper inl%" << std::setw (10) << "inliers%" << "\n";
  int row = 0;
  for (const PaperRow &p : kPaperTable1)
  {
    ++row;
    Setup s = o.setup;
    s.spacing = p.spacing;
    s.radius = p.radius;
    s.samples = 50;
    const auto centres = hexCentres (static_cast<int> (in.cloud->width), static_cast<int> (in.cloud->height), s.spacing);
    const auto valid_disc = validDiscCounts (in.cloud, *centres, s.radius);
    const std::vector<MethodSpec> specs = {texletMethod (UncertaintyMethod::MonteCarlo, PlaneFitMethod::PCA),
                                           texletMethod (UncertaintyMethod::None, PlaneFitMethod::PCA),
                                           referenceMethod ()};
    std::vector<std::unique_ptr<MethodRunner>> owned;
    std::vector<MethodRunner *> runners;
    for (const auto &m : specs)
    {
      owned.push_back (makeRunner (m, s, in.cloud, centres, valid_disc, in.camera));
      runners.push_back (owned.back ().get ());
    }
    const auto t = timeInterleaved (runners, 2, 1, o.table1_reps, [&] (int done, int total) {
      progress (o, "table 1 row " + std::to_string (row) + "/6 (spacing " + std::to_string (p.spacing) + ", radius " +
                       std::to_string (p.radius) + "): repetition " + std::to_string (done) + "/" +
                       std::to_string (total));
    });
    const MethodOutput out = owned[0]->output ();
    const std::size_t made = countFinite (out);
    const double share = 100.0 * meanFinite (out.inlier_share);
    const double mc = spread (t[0].ms).median, none = spread (t[1].ms).median, ne = spread (t[2].ms).median;
    std::cout << std::left << std::setw (9) << p.variable << std::right << std::setw (5)
              << (std::string (p.variable) == "spacing" ? p.spacing : p.radius) << std::setw (12) << fmt (p.ms)
              << std::setw (10) << fmt (mc) << std::setw (10) << fmt (none) << std::setw (10) << fmt (ne) << std::setw (12)
              << p.texlets << std::setw (9) << made << std::setw (10) << centres->size () << std::setw (12)
              << fmt (p.inliers_pct) << std::setw (10) << fmt (share) << "\n";
    j.push_back (json{{"variable", p.variable},
                  {"spacing", p.spacing},
                  {"radius", p.radius},
                  {"paper", {{"time_ms", p.ms}, {"texlets", p.texlets}, {"inliers_pct", p.inliers_pct}}},
                  {"measured",
                   {{"time_ms_montecarlo50", spreadJson (spread (t[0].ms))},
                    {"time_ms_none", spreadJson (spread (t[1].ms))},
                    {"time_ms_ne_omp_disc", spreadJson (spread (t[2].ms))},
                    {"cpu_ms_montecarlo50", spreadJson (spread (t[0].cpu_ms))},
                    {"cpu_ms_none", spreadJson (spread (t[1].cpu_ms))},
                    {"cpu_ms_ne_omp_disc", spreadJson (spread (t[2].cpu_ms))},
                    {"texlets", made},
                    {"centres", centres->size ()},
                    {"inliers_pct", num (share)}}}});
  }
  return j;
}

// --- the paper's Fig. 8 -------------------------------------------------------------------

json
runFig8 (const Options &o, std::string &dat)
{
  const std::vector<double> sigmas_mm = {0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0};
  const std::vector<PlaneFitMethod> fits = {PlaneFitMethod::Averaging, PlaneFitMethod::PCA, PlaneFitMethod::SVD};
  const int w = 128, h = 128, spacing = 4 * o.setup.radius; // patches that do not share points
  json j;
  j["setup"] = "a plane 1 m away tilted 30 degrees, f = 525 px, Gaussian depth noise along each ray; " +
               std::to_string (o.fig8_runs) + " runs per noise level, the patches of a hexagonal grid of spacing " +
               std::to_string (spacing) + " px in a " + std::to_string (w) + "x" + std::to_string (h) +
               " image; radius " + std::to_string (o.setup.radius) +
               " px; no outlier rejection (RANSAC threshold 1 km), so the fits alone are compared";
  std::ostringstream d;
  d << "# sigma_mm  mean_deg_averaging var_deg2_averaging  mean_deg_pca var_deg2_pca  mean_deg_svd var_deg2_svd\n";
  std::cout << "\n== The paper's Fig. 8: normal angle error against added depth noise (degrees, degrees^2) ==\n"
            << std::setw (9) << "sigma mm" << std::setw (14) << "avg mean" << std::setw (12) << "avg var" << std::setw (12)
            << "pca mean" << std::setw (12) << "pca var" << std::setw (12) << "svd mean" << std::setw (12) << "svd var"
            << "\n";
  for (std::size_t l = 0; l < sigmas_mm.size (); ++l)
  {
    progress (o, "fig. 8: noise " + fmt (sigmas_mm[l]) + " mm (" + std::to_string (l + 1) + "/" +
                     std::to_string (sigmas_mm.size ()) + ")");
    std::vector<std::vector<double>> err (fits.size ());
    for (int run = 0; run < o.fig8_runs; ++run)
    {
      Eigen::Vector3f truth;
      const Cloud::Ptr cloud = noisyPlane (w, h, 1.0, 30.0, sigmas_mm[l] * 1e-3, 1000u * l + run, truth);
      for (std::size_t f = 0; f < fits.size (); ++f)
      {
        pcl::TexletEstimation<pcl::PointXYZ> est;
        pcl::texlet::TexletParameters p;
        p.spacing = spacing;
        p.radius = o.setup.radius;
        p.ransac_iterations = 1;
        p.ransac_threshold = 1e3;
        p.uncertainty = UncertaintyMethod::None;
        p.fit = fits[f];
        p.seed = run;
        est.setParameters (p);
        est.setNumberOfThreads (o.setup.threads);
        est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (525.0, 525.0, 0.5 * (w - 1), 0.5 * (h - 1)));
        est.setInputCloud (cloud);
        pcl::PointCloud<pcl::Texlet> out;
        est.compute (out);
        for (const auto &t : out)
          if (t.support > 0)
          {
            const Eigen::Vector3d n (t.normal_x, t.normal_y, t.normal_z), g = truth.cast<double> ();
            err[f].push_back (std::atan2 (n.cross (g).norm (), std::fabs (n.dot (g))) * 180.0 / M_PI);
          }
      }
    }
    json row;
    row["sigma_mm"] = sigmas_mm[l];
    d << sigmas_mm[l];
    std::cout << std::setw (9) << fmt (sigmas_mm[l]);
    for (std::size_t f = 0; f < fits.size (); ++f)
    {
      const double mean = meanOf (err[f]);
      double var = 0;
      for (const double e : err[f])
        var += (e - mean) * (e - mean) / std::max<std::size_t> (1, err[f].size () - 1);
      row[pcl::texlet::toString (fits[f])] = {{"mean_deg", num (mean)}, {"var_deg2", num (var)}, {"n", err[f].size ()}};
      d << " " << mean << " " << var;
      std::cout << std::setw (f == 0 ? 14 : 12) << fmt (mean, 3) << std::setw (12) << fmt (var, 3);
    }
    d << "\n";
    std::cout << "\n";
    j["levels"].push_back (row);
  }
  dat = d.str ();
  return j;
}

// --- scaling ------------------------------------------------------------------------------

json
runScaling (const Options &o, const Input &in, std::string &dat_spacing, std::string &dat_radius)
{
  const std::vector<MethodSpec> specs = {texletMethod (UncertaintyMethod::None, PlaneFitMethod::PCA),
                                         texletMethod (UncertaintyMethod::Analytic, PlaneFitMethod::PCA),
                                         texletMethod (UncertaintyMethod::MonteCarlo, PlaneFitMethod::PCA),
                                         referenceMethod ()};
  json j;
  const int w = static_cast<int> (in.cloud->width), h = static_cast<int> (in.cloud->height);
  for (const bool by_spacing : {true, false})
  {
    const std::vector<int> values = by_spacing ? std::vector<int>{2, 3, 4, 5, 6, 8, 10, 12}
                                               : std::vector<int>{2, 3, 4, 5, 6, 7, 8, 10};
    std::ostringstream d;
    d << "# " << (by_spacing ? "spacing_px centres" : "radius_px disc_px")
      << "  then per method (none, analytic, montecarlo50, ne_omp_disc): wall median_ms q1_ms q3_ms, "
         "CPU median_ms q1_ms q3_ms\n";
    std::vector<std::vector<double>> x_of (specs.size ()), y_of (specs.size ()), c_of (specs.size ());
    std::cout << "\n== Time against " << (by_spacing ? "the number of texlets (spacing)" : "the neighbourhood size (radius)")
              << ", median wall / CPU ms of " << o.scaling_reps << " ==\n"
              << std::setw (8) << (by_spacing ? "spacing" : "radius") << std::setw (10)
              << (by_spacing ? "centres" : "disc px");
    for (const auto &m : specs)
      std::cout << std::setw (26) << m.name;
    std::cout << "\n";
    for (const int value : values)
    {
      Setup s = o.setup;
      (by_spacing ? s.spacing : s.radius) = value;
      const auto centres = hexCentres (w, h, s.spacing);
      const auto valid_disc = validDiscCounts (in.cloud, *centres, s.radius);
      std::vector<std::unique_ptr<MethodRunner>> owned;
      std::vector<MethodRunner *> runners;
      for (const auto &m : specs)
      {
        owned.push_back (makeRunner (m, s, in.cloud, centres, valid_disc, in.camera));
        runners.push_back (owned.back ().get ());
      }
      const auto t = timeInterleaved (runners, 3, 1, o.scaling_reps, [&] (int done, int total) {
        progress (o, std::string ("scaling by ") + (by_spacing ? "spacing " : "radius ") + std::to_string (value) +
                         ": repetition " + std::to_string (done) + "/" + std::to_string (total));
      });
      const double x = by_spacing ? static_cast<double> (centres->size ())
                                  : static_cast<double> (pcl::texlet::kernels::pixelDiscSize (value));
      d << value << " " << x;
      std::cout << std::setw (8) << value << std::setw (10) << x;
      json row = {{by_spacing ? "spacing" : "radius", value}, {by_spacing ? "centres" : "disc_px", x}};
      for (std::size_t m = 0; m < specs.size (); ++m)
      {
        const Spread sp = spread (t[m].ms), cp = spread (t[m].cpu_ms);
        d << " " << sp.median << " " << sp.q1 << " " << sp.q3 << " " << cp.median << " " << cp.q1 << " " << cp.q3;
        std::cout << std::setw (26) << (fmt (sp.median) + " / " + fmt (cp.median));
        row[specs[m].name] = {{"wall_ms", spreadJson (sp)}, {"cpu_ms", spreadJson (cp)}};
        x_of[m].push_back (x);
        y_of[m].push_back (sp.median);
        c_of[m].push_back (cp.median);
      }
      d << "\n";
      std::cout << "\n";
      j[by_spacing ? "by_spacing" : "by_radius"]["rows"].push_back (row);
    }
    std::cout << "least-squares lines of CPU time (ms = a + b x):";
    for (std::size_t m = 0; m < specs.size (); ++m)
    {
      const LineFit f = fitLine (x_of[m], c_of[m]), fw = fitLine (x_of[m], y_of[m]);
      j[by_spacing ? "by_spacing" : "by_radius"]["lines"][specs[m].name] = {
          {"cpu", {{"intercept_ms", num (f.intercept)}, {"slope_ms_per_unit", num (f.slope)}, {"r2", num (f.r2)}}},
          {"wall", {{"intercept_ms", num (fw.intercept)}, {"slope_ms_per_unit", num (fw.slope)}, {"r2", num (fw.r2)}}}};
      std::cout << "  " << specs[m].name << ": a " << fmt (f.intercept, 2) << ", b " << fmt (f.slope, 5) << ", R^2 "
                << fmt (f.r2, 4) << ";";
      d << "# cpu line " << specs[m].name << " " << f.intercept << " " << f.slope << " " << f.r2 << "\n";
    }
    std::cout << "\n";
    (by_spacing ? dat_spacing : dat_radius) = d.str ();
  }
  return j;
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
                   {"threads", o.setup.threads}};
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
        writeAtomically ((fs::path (o.data_dir) / "timing.dat").string (), d.str ());
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
        writeAtomically ((fs::path (o.data_dir) / "scaling_spacing.dat").string (), ds);
        writeAtomically ((fs::path (o.data_dir) / "scaling_radius.dat").string (), dr);
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
      writeAtomically ((fs::path (o.data_dir) / "fig8.dat").string (), d);
  }
  j["machine"]["load_average_at_end"] = num (loadAverage ());
  if (!o.json_path.empty ())
    writeAtomically (o.json_path, j.dump (2) + "\n");
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
