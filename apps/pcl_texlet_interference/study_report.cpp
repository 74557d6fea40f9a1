#include "study_report.h"

#include <pcl_texlet/report/base64.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using nlohmann::json;

namespace pcl_texlet_interference
{

namespace
{

/** NaN is not JSON: null instead. */
json
number (double v)
{
  return std::isfinite (v) ? json (v) : json (nullptr);
}

double
round3 (double v)
{
  return std::round (v * 1000.0) / 1000.0;
}

std::string
imageTag (const std::string &folder, const std::string &name, const std::string &alt)
{
  std::ifstream in (fs::path (folder) / name, std::ios::binary);
  if (!in)
    throw pcl::IOException ("report: cannot read the image '" + name + "' to embed");
  const std::string bytes ((std::istreambuf_iterator<char> (in)), std::istreambuf_iterator<char> ());
  return "<img alt=\"" + alt + "\" src=\"data:image/png;base64," + pcl::texlet::base64 (bytes) + "\">";
}

std::string
escape (const std::string &s)
{
  std::string out;
  for (char c : s)
    out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string (1, c);
  return out;
}

std::string
fixed (const json &v, int digits = 1)
{
  if (!v.is_number ())
    return "&ndash;";
  std::ostringstream s;
  s << std::fixed << std::setprecision (digits) << v.get<double> ();
  return s.str ();
}

} // namespace

/* Half the smallest gap between Table 2's distances (112 and 128 mm) less a bin, so that one
 * relation's window never reaches the other's peak. */
constexpr double kPeakWindowM = 0.007;
constexpr double kPeakWindowDeg = 20.0;

json
peaksJson (const pcl::texlet::RelationStatistics &stats)
{
  json peaks = json::array ();
  for (const auto &r : stats.relations)
  {
    if (r.distance_max_m != r.distance_min_m)
      continue; // a range (orthogonal planes) has no single peak
    const auto p = stats.peakNear (r.distance_min_m, r.angle_deg, kPeakWindowM, kPeakWindowDeg);
    peaks.push_back ({{"relation", r.name},
                      {"expected_distance_mm", round3 (1000.0 * r.distance_min_m)},
                      {"expected_angle_deg", r.angle_deg},
                      {"peak_distance_mm", round3 (1000.0 * p.distance_m)},
                      {"peak_angle_deg", round3 (p.angle_deg)},
                      {"peak_count", p.count}});
  }
  return peaks;
}

json
studyJson (const json &setup, const pcl::texlet::KnownObject &object, const std::vector<CellResult> &cells)
{
  json j;
  j["generator"] = "pcl_texlet_interference";
  j["setup"] = setup;
  json obj;
  obj["name"] = object.name;
  obj["tolerance"] = {{"angle_deg", object.angle_tol_deg}, {"distance_mm", 1000.0 * object.distance_tol_m}};
  for (const auto &r : object.relations)
    obj["relations"].push_back ({{"name", r.name},
                                 {"angle_deg", r.angle_deg},
                                 {"distance_mm", {round3 (1000.0 * r.distance_min_m), round3 (1000.0 * r.distance_max_m)}}});
  for (const auto &f : object.faces)
    obj["faces"].push_back (f.name);
  j["object"] = obj;

  json list = json::array ();
  for (const auto &c : cells)
  {
    const auto &s = c.cell.statistics;
    json cell;
    cell["projectors"] = c.cell.projectors;
    cell["radius_px"] = c.cell.radius;
    cell["texlets"] = s.texlets;
    cell["texlets_per_sensor"] = c.cell.texlets_per_sensor;
    cell["relations"] = s.relation_count;
    cell["inliers"] = s.inliers;
    cell["inlier_percent"] = number (s.inlierPercent ());
    cell["outside_histogram"] = s.outside_histogram;
    json per = json::array ();
    for (std::size_t r = 0; r < s.relations.size (); ++r)
      per.push_back ({{"relation", s.relations[r].name},
                      {"inliers", s.relation_hits[r]},
                      {"percent_of_relations",
                       number (s.relation_count ? 100.0 * s.relation_hits[r] / s.relation_count : NAN)}});
    cell["relation_inliers"] = per;
    cell["peaks"] = peaksJson (s);
    json faces = json::array ();
    for (std::size_t f = 0; f < c.cell.faces.size (); ++f)
    {
      const auto &q = c.cell.faces[f];
      faces.push_back ({{"face", q.name},
                        {"texlets", q.texlets},
                        {"rms_plane_distance_mm", number (q.rms_distance_mm)},
                        {"rms_normal_angle_deg", number (q.rms_angle_deg)},
                        {"median_normal_angle_deg", number (q.median_angle_deg)},
                        {"inlier_percent", number (s.labelInlierPercent (static_cast<int> (f)))}});
    }
    cell["faces"] = faces;
    // The relations the paper singles out (Fig. 11i): top vs ground against the sides.
    json pairs = json::array ();
    for (std::size_t a = 0; a < s.labels.size (); ++a)
      for (std::size_t b = a; b < s.labels.size (); ++b)
      {
        const double p = s.labelPairInlierPercent (static_cast<int> (a), static_cast<int> (b));
        if (std::isfinite (p))
          pairs.push_back ({{"faces", {s.labels[a], s.labels[b]}}, {"inlier_percent", p}});
      }
    cell["face_pairs"] = pairs;
    if (!c.histogram_png.empty ())
      cell["histogram_png"] = c.histogram_png;
    cell["seconds"] = round3 (c.seconds);
    list.push_back (cell);
  }
  j["cells"] = list;
  return j;
}

std::string
studyHtml (const json &j, const std::string &folder, const std::string &curves_png)
{
  std::set<int> radii, projectors;
  std::map<std::pair<int, int>, const json *> cell;
  for (const auto &c : j["cells"])
  {
    const int p = c["projectors"], r = c["radius_px"];
    radii.insert (r);
    projectors.insert (p);
    cell[{p, r}] = &c;
  }
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>pcl_texlet interference study</title>\n"
    << "<style>body{font-family:sans-serif;margin:2em;max-width:1400px}table{border-collapse:collapse;margin:1em 0}"
       "td,th{border:1px solid #bbb;padding:4px 8px;text-align:right}th{background:#eee}"
       "img{max-width:100%}.grid{display:grid;gap:8px}</style></head><body>\n";
  h << "<h1>Interference study: texlet relations against a known object</h1>\n";
  h << "<p>Object: " << escape (j["object"]["name"].get<std::string> ()) << ". Source: "
    << escape (j["setup"].value ("source", std::string ("?"))) << ". Inlier boxes: &plusmn;"
    << j["object"]["tolerance"]["angle_deg"].get<double> () << "&deg;, &plusmn;"
    << j["object"]["tolerance"]["distance_mm"].get<double> () << " mm around each expected relation "
    << "(the paper's Fig. 10b). Every texlet is related to every other one (both directions).</p>\n";
  h << "<h2>Expected relations (the paper's Table 2)</h2>\n<table><tr><th>relation</th><th>angle (&deg;)</th>"
       "<th>distance (mm)</th></tr>\n";
  for (const auto &r : j["object"]["relations"])
  {
    const double d0 = r["distance_mm"][0], d1 = r["distance_mm"][1];
    h << "<tr><td style=\"text-align:left\">" << escape (r["name"].get<std::string> ()) << "</td><td>"
      << r["angle_deg"].get<double> () << "</td><td>" << d0 << (d1 != d0 ? "&ndash;" + fixed (d1, 0) : "")
      << "</td></tr>\n";
  }
  h << "</table>\n<h2>Inlier percentage</h2>\n<table><tr><th>active projectors</th>";
  for (int r : radii)
    h << "<th>radius " << r << " px</th>";
  h << "</tr>\n";
  for (int p : projectors)
  {
    h << "<tr><th>" << p << "</th>";
    for (int r : radii)
      h << "<td>" << (cell.count ({p, r}) ? fixed ((*cell[{p, r}])["inlier_percent"]) + " %" : "") << "</td>";
    h << "</tr>\n";
  }
  h << "</table>\n";
  if (!curves_png.empty ())
    h << imageTag (folder, curves_png, "inlier percentage against radius") << "\n";

  h << "<h2>Quality histograms (the paper's Fig. 11)</h2>\n<p>Rows: active projectors; columns: radius. "
       "Colour: log<sub>10</sub> of the relations per bin; green: the inlier boxes.</p>\n";
  h << "<div class=\"grid\" style=\"grid-template-columns:repeat(" << radii.size () << ",1fr)\">\n";
  for (int p : projectors)
    for (int r : radii)
    {
      h << "<div>";
      if (cell.count ({p, r}) && cell[{p, r}]->contains ("histogram_png"))
        h << imageTag (folder, (*cell[{p, r}])["histogram_png"].get<std::string> (),
                       "active projectors: " + std::to_string (p) + ", radius " + std::to_string (r) + " px");
      h << "</div>\n";
    }
  h << "</div>\n";

  // One table row per item of a cell's list (its faces, its peaks), cells in table order.
  const auto eachItem = [&] (const char *list, const auto &row) {
    for (int p : projectors)
      for (int r : radii)
        if (cell.count ({p, r}))
          for (const auto &item : (*cell[{p, r}])[list])
            row (p, r, item);
  };
  h << "<h2>Per face (texlets labelled by position on the known object)</h2>\n";
  h << "<table><tr><th>projectors</th><th>radius</th><th>face</th><th>texlets</th><th>RMS plane distance (mm)</th>"
       "<th>RMS normal angle (&deg;)</th><th>median normal angle (&deg;)</th><th>inliers of its relations (%)</th></tr>\n";
  eachItem ("faces", [&] (int p, int r, const json &f) {
    h << "<tr><td>" << p << "</td><td>" << r << "</td><td style=\"text-align:left\">"
      << escape (f["face"].get<std::string> ()) << "</td><td>" << f["texlets"].get<std::size_t> () << "</td><td>"
      << fixed (f["rms_plane_distance_mm"], 2) << "</td><td>" << fixed (f["rms_normal_angle_deg"], 2) << "</td><td>"
      << fixed (f["median_normal_angle_deg"], 2) << "</td><td>" << fixed (f["inlier_percent"]) << "</td></tr>\n";
  });
  h << "</table>\n";

  h << "<h2>Peaks of the point relations</h2>\n<table><tr><th>projectors</th><th>radius</th><th>relation</th>"
       "<th>expected (mm, &deg;)</th><th>peak (mm, &deg;)</th><th>count</th></tr>\n";
  eachItem ("peaks", [&] (int p, int r, const json &k) {
    h << "<tr><td>" << p << "</td><td>" << r << "</td><td style=\"text-align:left\">"
      << escape (k["relation"].get<std::string> ()) << "</td><td>" << fixed (k["expected_distance_mm"], 0) << ", "
      << fixed (k["expected_angle_deg"], 0) << "</td><td>" << fixed (k["peak_distance_mm"]) << ", "
      << fixed (k["peak_angle_deg"]) << "</td><td>" << k["peak_count"].get<std::uint64_t> () << "</td></tr>\n";
  });
  h << "</table>\n<h2>Setup</h2>\n<pre>" << escape (j["setup"].dump (2)) << "</pre>\n</body></html>\n";
  return h.str ();
}

} // namespace pcl_texlet_interference
