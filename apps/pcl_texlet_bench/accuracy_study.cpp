#include "studies.h"

#include "harness.h"
#include "output_format.h"
#include "scenes.h"

#include <pcl_texlet/camera/pinhole_model.h>

#include <cmath>
#include <iomanip>
#include <iostream>

using nlohmann::json;

namespace pcl_texlet_bench
{

namespace
{

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

} // namespace

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

} // namespace pcl_texlet_bench
