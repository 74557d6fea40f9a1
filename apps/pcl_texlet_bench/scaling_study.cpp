#include "studies.h"

#include "harness.h"
#include "output_format.h"
#include "runner_set.h"

#include <pcl_texlet/kernels/pixel_disc.h>

#include <iomanip>
#include <iostream>
#include <sstream>

using nlohmann::json;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::UncertaintyMethod;

namespace pcl_texlet_bench
{

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
      const RunnerSet set = makeRunners (specs, s, in.cloud, centres, valid_disc, in.camera);
      const auto t = timeInterleaved (set.runners, 3, 1, o.scaling_reps, [&] (int done, int total) {
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

} // namespace pcl_texlet_bench
