#include "studies.h"

#include "harness.h"
#include "output_format.h"
#include "runner_set.h"

#include <iomanip>
#include <iostream>
#include <string>

using nlohmann::json;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::UncertaintyMethod;

namespace pcl_texlet_bench
{

namespace
{

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

} // namespace

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
    const RunnerSet set = makeRunners (specs, s, in.cloud, centres, valid_disc, in.camera);
    const auto t = timeInterleaved (set.runners, 2, 1, o.table1_reps, [&] (int done, int total) {
      progress (o, "table 1 row " + std::to_string (row) + "/6 (spacing " + std::to_string (p.spacing) + ", radius " +
                       std::to_string (p.radius) + "): repetition " + std::to_string (done) + "/" +
                       std::to_string (total));
    });
    const MethodOutput out = set.owned[0]->output ();
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

} // namespace pcl_texlet_bench
