#include "studies.h"

#include "harness.h"
#include "machine.h"
#include "output_format.h"
#include "runner_set.h"

#include <pcl_texlet/kernels/pixel_disc.h>

#include <iomanip>
#include <iostream>
#include <utility>

using nlohmann::json;

namespace pcl_texlet_bench
{

json
runTiming (const Options &o, const Input &in, const std::vector<MethodSpec> &methods)
{
  const auto centres = hexCentres (static_cast<int> (in.cloud->width), static_cast<int> (in.cloud->height),
                                   o.setup.spacing);
  const std::vector<int> valid_disc = validDiscCounts (in.cloud, *centres, o.setup.radius);

  progress (o, "checking that NormalEstimationOMP sees exactly the texlets' neighbourhoods");
  const NeighbourhoodCheck check = checkSameNeighbourhood (o.setup, in.cloud, centres, valid_disc, in.camera);

  const RunnerSet set = makeRunners (methods, o.setup, in.cloud, centres, valid_disc, in.camera);
  int reference = -1;
  for (std::size_t i = 0; i < methods.size (); ++i)
    if (methods[i].kind == MethodKind::NormalOmpDisc)
      reference = static_cast<int> (i);
  const double load_before = loadAverage ();
  progress (o, "timing " + std::to_string (methods.size ()) + " methods on " + in.description + ": " +
                   std::to_string (o.warmup) + " warm-up + " + std::to_string (o.repetitions) +
                   " repetitions, interleaved, " + std::to_string (o.setup.threads) + " threads");
  const auto t = timeInterleaved (set.runners, reference, o.warmup, o.repetitions, [&] (int done, int total) {
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
    const MethodOutput out = set.owned[i]->output ();
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

} // namespace pcl_texlet_bench
