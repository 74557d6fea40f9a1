#include <pcl_texlet/report/lab_report.h>

#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/noise/model_description.h>
#include <pcl_texlet/report/base64.h>
#include <pcl_texlet/report/gnuplot.h>

#include <pcl/exceptions.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <system_error>
#include <sys/stat.h>
#include <unistd.h>

namespace pcl
{
namespace texlet
{
namespace lab
{

namespace
{

void
say (const ModelLab &lab, const std::string &line)
{
  if (lab.settings ().progress)
    lab.settings ().progress (line);
}

/** A number, or null where it is not measurable (NaN is not JSON). */
nlohmann::json
number (double x)
{
  return std::isfinite (x) ? nlohmann::json (x) : nlohmann::json (nullptr);
}

nlohmann::json
metricsJson (const LabMetrics &m)
{
  // sd_rmse_mm and sd_floor_mm are null on single-frame sets (no temporal SD).
  nlohmann::json j = {{"sd_rmse_mm", number (m.sd_rmse_mm)},   {"sd_floor_mm", number (m.sd_floor_mm)},
                      {"bias_rmse_mm", m.bias_rmse_mm},
                      {"bias_spatial_sd_mm", number (m.bias_spatial_sd_mm)},
                      {"bias_spatial_sd_pred_mm", number (m.bias_spatial_sd_pred_mm)},
                      {"nll", m.nll},                      {"within_1sigma", m.within_1sigma},
                      {"within_2sigma", m.within_2sigma},  {"pixels", m.pixels},
                      {"samples", m.samples}};
  const TexletConsistency &t = m.texlets;
  if (t.samples > 0) // computed for the starting model, the steps and the statistically significant candidates
  {
    j["texlet_nees_p"] = t.nees_p;
    j["texlet_nees_p_ideal"] = t.ideal_p;
    j["texlet_nees_p_ratio"] = t.ratioP ();
    j["texlet_nees_n"] = t.nees_n;
    j["texlet_nees_n_ideal"] = t.ideal_n;
    j["texlet_nees_n_ratio"] = t.ratioN ();
    j["texlet_nees_p_normal"] = t.nees_p_normal;
    j["texlet_nees_p_normal_ratio"] = t.ratioPNormal ();
    j["texlet_nees_p_median"] = t.median_p;
    j["texlet_nees_p_median_ratio"] = t.medianRatioP ();
    j["texlet_nees_n_median"] = t.median_n;
    j["texlet_nees_n_median_ratio"] = t.medianRatioN ();
    j["texlets"] = t.texlets;
    j["texlet_samples"] = t.samples;
  }
  return j;
}

nlohmann::json
termsJson (const NoiseModel &model)
{
  nlohmann::json terms = nlohmann::json::array ();
  for (const auto &t : describeModel (model).terms)
  {
    nlohmann::json term;
    term["name"] = t.name;
    nlohmann::json params = nlohmann::json::object ();
    for (const auto &p : t.parameters)
      params[p.first] = p.second;
    term["parameters"] = params;
    for (const auto &s : t.settings)
      term["settings"][s.first] = s.second;
    terms.push_back (term);
  }
  return terms;
}

/** The structures of \a d, strongest first: structure, strength, significant, z, words. */
nlohmann::json
unexplainedJson (const ResidualDiagnostics &d)
{
  nlohmann::json out = nlohmann::json::array ();
  for (const auto &u : d.structures)
    out.push_back ({{"structure", u.structure}, {"strength", number (u.strength)}, {"significant", u.significant},
                    {"z", number (u.z)}, {"words", u.words}});
  return out;
}

std::string
readFile (const std::string &path)
{
  std::ifstream in (path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf ();
  return s.str ();
}

std::string
escape (const std::string &s)
{
  std::string o;
  for (char c : s)
  {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else
      o += c;
  }
  return o;
}

std::string
fmt (double x, int precision = 4)
{
  std::ostringstream s;
  s << std::setprecision (precision) << x;
  return s.str ();
}

/** sd_rmse_mm for the page with the part of it that chance alone gives (sd_floor_mm); "not
  * measurable" on single frames (NaN).
  */
std::string
sdText (const LabMetrics &m)
{
  if (!std::isfinite (m.sd_rmse_mm))
    return "not measurable (one frame)";
  return std::isfinite (m.sd_floor_mm) ? fmt (m.sd_rmse_mm) + " (" + fmt (m.sd_floor_mm) + " by chance)"
                                       : fmt (m.sd_rmse_mm);
}

std::string
baseName (const std::string &path)
{
  std::string p = path;
  while (p.size () > 1 && p.back () == '/')
    p.pop_back ();
  const auto k = p.find_last_of ('/');
  return k == std::string::npos ? p : p.substr (k + 1);
}

/** Runs gnuplot on \a script, which writes its PNG to \a png's temporary path (set output), and
  * renames the PNG into place.
  */
void
drawPlot (const std::string &script, AtomicFile &png)
{
  runGnuplot (script, script + ".log");
  png.commit ();
}

/** Per-pixel measured and predicted SD and mean of recording r under a model. */
struct PixelComparison
{
  std::vector<float> sd_pred, mean_pred;
};

struct CovariateCurve
{
  std::string name, unit;
  std::vector<double> x, ratio_mean, ratio_se, bias_mean, bias_se;
};

/** Binned SD ratio and bias residual against one covariate, over every recording. */
CovariateCurve
covariateCurve (const ModelLab &lab, const std::vector<PixelComparison> &cmp, const std::string &name,
                const std::string &unit, double (*value) (const ModelLab &, std::size_t, std::size_t), bool discrete)
{
  CovariateCurve c;
  c.name = name;
  c.unit = unit;
  double lo = std::numeric_limits<double>::infinity (), hi = -lo;
  const auto &recs = lab.recordings ();
  for (std::size_t r = 0; r < recs.size (); ++r)
    for (std::size_t i = 0; i < recs[r]->used.size (); ++i)
      if (recs[r]->used[i] && std::isfinite (cmp[r].sd_pred[i]))
      {
        const double v = value (lab, r, i);
        if (!std::isfinite (v)) // a covariate the recording does not have (no colour frames)
          continue;
        lo = std::min (lo, v);
        hi = std::max (hi, v);
      }
  if (!(hi >= lo))
    return c;
  const int nb = discrete ? static_cast<int> (hi - lo + 1.5) : 16;
  std::vector<double> n (nb, 0), nr (nb, 0), s1 (nb, 0), s2 (nb, 0), b1 (nb, 0), b2 (nb, 0), xs (nb, 0);
  for (std::size_t r = 0; r < recs.size (); ++r)
    for (std::size_t i = 0; i < recs[r]->used.size (); ++i)
    {
      if (!recs[r]->used[i] || !std::isfinite (cmp[r].sd_pred[i]) || !(cmp[r].sd_pred[i] > 0))
        continue;
      const double v = value (lab, r, i);
      if (!std::isfinite (v))
        continue;
      int b = discrete ? static_cast<int> (v - lo + 0.5) : static_cast<int> (nb * (v - lo) / (hi - lo + 1e-12));
      b = std::max (0, std::min (nb - 1, b));
      const double ratio = recs[r]->sd_mm[i] / cmp[r].sd_pred[i];
      const double bias = recs[r]->mean_mm[i] - cmp[r].mean_pred[i];
      n[b] += 1;
      xs[b] += v;
      if (std::isfinite (ratio)) // single frames: no measured SD
      {
        nr[b] += 1;
        s1[b] += ratio;
        s2[b] += ratio * ratio;
      }
      b1[b] += bias;
      b2[b] += bias * bias;
    }
  for (int b = 0; b < nb; ++b)
  {
    if (n[b] < 5)
      continue;
    const double m = nr[b] > 0 ? s1[b] / nr[b] : std::numeric_limits<double>::quiet_NaN (), bm = b1[b] / n[b];
    c.x.push_back (xs[b] / n[b]);
    c.ratio_mean.push_back (m);
    c.ratio_se.push_back (nr[b] > 0 ? std::sqrt (std::max (0.0, s2[b] / nr[b] - m * m) / nr[b]) : m);
    c.bias_mean.push_back (bm);
    c.bias_se.push_back (std::sqrt (std::max (0.0, b2[b] / n[b] - bm * bm) / n[b]));
  }
  return c;
}

double covRadius (const ModelLab &l, std::size_t r, std::size_t i) { return l.context (r, i).radius_px; }
double covDepth (const ModelLab &l, std::size_t r, std::size_t i) { return l.recordings ()[r]->surface_mm[i]; }
double covIncidence (const ModelLab &l, std::size_t r, std::size_t i)
{
  return std::acos (std::min (1.0f, l.recordings ()[r]->cos_incidence[i])) * 57.29577951308232;
}
double covColumn (const ModelLab &l, std::size_t r, std::size_t i) { return double (i % l.recordings ()[r]->width); }
double covRow (const ModelLab &l, std::size_t r, std::size_t i) { return double (i / l.recordings ()[r]->width); }
double covPhase (const ModelLab &l, std::size_t r, std::size_t i) { return l.recordings ()[r]->phase[i]; }
double covEdge (const ModelLab &l, std::size_t r, std::size_t i)
{
  return std::min (40.0f, l.recordings ()[r]->edge_distance_px[i]);
}
double covProjectors (const ModelLab &l, std::size_t r, std::size_t) { return l.recordings ()[r]->active_projectors; }
double covIntensity (const ModelLab &l, std::size_t r, std::size_t i)
{
  const auto &grey = l.recordings ()[r]->intensity;
  return grey.empty () ? std::numeric_limits<double>::quiet_NaN () : double (grey[i]);
}

struct Region
{
  std::string text;
  double score;
};

} // namespace

LabSession
runLabSession (const ModelLab &lab, const NoiseModel &start, const std::string &start_name,
               const std::vector<std::string> &add, int auto_count)
{
  LabSession s;
  s.start_name = start_name;
  s.start = start;
  say (lab, "lab: the disparity lattice of the depth values");
  s.lattice = fitDisparityLattice (lab.recordings ());
  say (lab, "lab: comparing the model '" + start_name + "' with the recordings");
  s.start_metrics = lab.evaluate (start);
  say (lab, "lab: texlet NEES of P and N across frames under '" + start_name + "'");
  s.start_metrics.texlets = lab.texlets (start);
  say (lab, "lab: the structure '" + start_name + "' leaves in the residuals");
  s.start_unexplained = diagnoseResiduals (lab, start);
  say (lab, "lab: ranking the candidate effects (fit on even frames, score on odd frames)");
  s.candidates = lab.rankCandidates (start);
  if (!lab.splitsFrames ())
    s.notes.push_back ("a recording has fewer than 4 frames: the halves are a checkerboard of 32 px blocks, not even "
                       "and odd frames, and effects that change over time cannot be tested");
  NoiseModel current = start;
  for (const auto &effect : add)
  {
    say (lab, "lab: adding " + effect + " and refitting");
    current = lab.addEffect (current, effect);
    s.steps.push_back ({effect, lab.evaluate (current), current, false, {}});
    s.steps.back ().metrics.texlets = lab.texlets (current);
    s.steps.back ().unexplained = diagnoseResiduals (lab, current);
  }
  std::vector<Candidate> ranking = s.candidates;
  for (int k = 0; k < auto_count; ++k)
  {
    if (!s.steps.empty () && (k > 0 || !add.empty ()))
    {
      say (lab, "lab: re-ranking the candidates against the model with " + s.steps.back ().added);
      ranking = lab.rankCandidates (current);
    }
    const Candidate *best = nullptr;
    for (const auto &c : ranking)
      if (c.applicable && c.significant && !current.find (c.effect))
      {
        best = &c;
        break;
      }
    if (!best)
    {
      s.notes.push_back ("--auto: no significant candidate left after " + std::to_string (k) + " added effect(s)");
      break;
    }
    say (lab, "lab: adding " + best->effect + " (best significant candidate) and refitting");
    current = lab.addEffect (current, best->effect);
    s.steps.push_back ({best->effect, lab.evaluate (current), current, true, {}});
    s.steps.back ().metrics.texlets = lab.texlets (current);
    s.steps.back ().unexplained = diagnoseResiduals (lab, current);
  }
  if (s.steps.empty ())
  {
    s.final_model = lab.fit (start);
    say (lab, "lab: the structure the refitted model leaves in the residuals");
    s.unexplained = diagnoseResiduals (lab, s.final_model);
  }
  else
  {
    s.final_model = s.steps.back ().model;
    s.unexplained = s.steps.back ().unexplained;
  }
  return s;
}

std::string
labReportJson (const LabSession &s)
{
  nlohmann::json j;
  j["model"] = {{"name", s.start_name}, {"terms", termsJson (s.start)}};
  j["metrics"] = metricsJson (s.start_metrics);
  j["unexplained"] = unexplainedJson (s.unexplained);
  j["start_unexplained"] = unexplainedJson (s.start_unexplained);
  nlohmann::json cands = nlohmann::json::array ();
  for (const auto &c : s.candidates)
  {
    nlohmann::json cj;
    cj["effect"] = c.effect;
    cj["metrics"] = metricsJson (c.metrics);
    cj["gain"] = c.gain;
    cj["significant"] = c.significant;
    cj["threshold"] = c.threshold;
    cj["null_mean"] = c.null_mean;
    cj["null_sd"] = c.null_sd;
    cj["total_gain_nats"] = c.total_gain;
    cj["statistically_significant"] = c.statistically_significant;
    cj["texlets_less_honest"] = c.texlets_less_honest;
    cj["verdict"] = candidateVerdict (c);
    cj["effect_size"] = {{"fall", c.effect_size}, {"shows_in", c.effect_shows_in}, {"pixel_share", c.effect_share},
                         {"error_before", c.error_before}, {"error_after", c.error_after}, {"unit", c.error_unit}};
    if (c.metrics.texlets.samples > 0)
      cj["texlet_error"] = {{"before", number (c.texlet_error_before)}, {"after", number (c.texlet_error_after)}};
    cj["applicable"] = c.applicable;
    cj["physics"] = c.physics;
    cj["signature"] = c.signature;
    if (!c.note.empty ())
      cj["note"] = c.note;
    cands.push_back (cj);
  }
  j["candidates"] = cands;
  nlohmann::json steps = nlohmann::json::array ();
  for (const auto &st : s.steps)
    steps.push_back ({{"added", st.added}, {"metrics", metricsJson (st.metrics)}, {"auto", st.from_auto},
                      {"terms", termsJson (st.model)}, {"unexplained", unexplainedJson (st.unexplained)}});
  j["steps"] = steps;
  j["skipped_frames"] = s.skipped_frames;
  j["notes"] = s.notes;
  const DisparityLattice &l = s.lattice;
  j["disparity_lattice"] = {{"found", l.found}, {"constant_mm", l.constant_mm},
                            {"camera_constant_mm", l.camera_constant_mm},
                            {"ratio_to_camera", l.constant_mm / l.camera_constant_mm}, {"phase", l.phase},
                            {"coherence", l.coherence}, {"residual_ratio", l.residual_ratio}, {"values", l.values}};
  return j.dump (2) + "\n";
}

void
writeLabReport (const ModelLab &lab, const LabSession &s, const std::string &folder)
{
  ::mkdir (folder.c_str (), 0755);
  struct stat st;
  if (::stat (folder.c_str (), &st) != 0 || !S_ISDIR (st.st_mode) || ::access (folder.c_str (), W_OK) != 0)
    throw pcl::IOException ("lab report: '" + folder + "' is not a writable folder");
  const std::string work = folder + "/.plots-tmp";
  ::mkdir (work.c_str (), 0755);
  const auto &recs = lab.recordings ();
  say (lab, "lab: drawing the plots");

  // --- per-pixel comparisons of the start and the final model
  std::vector<PixelComparison> first (recs.size ()), last (recs.size ());
  {
    std::vector<std::vector<float>> sd, mean;
    for (const bool start : {true, false})
    {
      lab.predict (start ? s.start : s.final_model, sd, mean);
      auto &to = start ? first : last;
      for (std::size_t r = 0; r < recs.size (); ++r)
      {
        to[r].sd_pred = std::move (sd[r]);
        to[r].mean_pred = std::move (mean[r]);
      }
    }
  }

  // --- staircase: the error after each added effect
  {
    std::ofstream d (work + "/staircase.dat");
    // The texlets' median NEES ratios; NaN (gnuplot skips it) where they were not measured.
    auto row = [&] (std::size_t k, const LabMetrics &m, const std::string &label) {
      d << k << " " << m.sd_rmse_mm << " " << m.bias_rmse_mm << " " << m.nll << " " << label << " "
        << m.texlets.medianRatioP () << " " << m.texlets.medianRatioN () << "\n";
    };
    row (0, s.start_metrics, "start");
    for (std::size_t k = 0; k < s.steps.size (); ++k)
      row (k + 1, s.steps[k].metrics, "+" + s.steps[k].added);
    d.close ();
    // The texlet panel's range: its ratios, and 1 (honest) well inside.
    double ratio_lo = 0.5, ratio_hi = 2.0;
    auto widen = [&] (const LabMetrics &m) {
      for (double r : {m.texlets.medianRatioP (), m.texlets.medianRatioN ()})
        if (std::isfinite (r) && r > 0)
        {
          ratio_lo = std::min (ratio_lo, r / 1.5);
          ratio_hi = std::max (ratio_hi, r * 1.5);
        }
    };
    widen (s.start_metrics);
    for (const auto &st : s.steps)
      widen (st.metrics);
    std::ofstream g (work + "/staircase.gp");
    AtomicFile png (folder + "/staircase.png");
    const std::string &out = png.temporaryPath ();
    g << "set terminal pngcairo size 820,760 font 'Sans,10'\nset output '" << out << "'\n"
      << "set multiplot layout 2,1\nset lmargin 10\nset rmargin 10\nset xtics noenhanced\n"
      << "set title 'Watch the error fall: the model after each added effect (all data, refitted)'\n"
      << "set ylabel 'RMS error (mm)'\nset y2label 'NLL per depth sample (nats)'\nset ytics nomirror\nset y2tics\n"
      << "set xrange [-0.5:" << s.steps.size () + 0.5 << "]\nset yrange [0:*]\nset grid\nset key top right\n"
      << "set xtics rotate by -20\n"
      << "plot '" << work << "/staircase.dat' using 1:2:xtic(5) with histeps lw 3 title 'sd\\_rmse\\_mm', "
      << "'' using 1:2 with points pt 7 notitle, "
      << "'' using 1:3 with histeps lw 3 title 'bias\\_rmse\\_mm', '' using 1:3 with points pt 7 notitle, "
      << "'' using 1:4 axes x1y2 with histeps lw 2 dt 2 title 'nll (right axis)'\n"
      << "set title 'At texlet level: median NEES over its ideal (1: honest covariances, above: over-confident)'\n"
      << "unset y2tics\nunset y2label\nset ylabel 'median NEES / ideal'\nset logscale y\nset yrange [" << ratio_lo << ":" << ratio_hi << "]\n"
      << "set ytics (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 1e3, 1e4, 1e5, 1e6)\n"
      << "set key top right\n"
      << "plot '" << work << "/staircase.dat' using 1:6:xtic(5) with linespoints lw 3 pt 7 title 'P (Sigma\\_P)', "
      << "'' using 1:7 with linespoints lw 3 pt 5 title 'N (Sigma\\_N)', 1 with lines lw 1 lc 'black' dt 2 title 'honest'\n"
      << "unset multiplot\n";
    g.close ();
    drawPlot (work + "/staircase.gp", png);
  }

  // --- what the final model leaves: the structures' strengths and the residual correlations
  {
    const ResidualDiagnostics &u = s.unexplained;
    const double floor = 1e-4;
    std::ofstream d (work + "/unexplained.dat");
    const std::size_t shown = std::min<std::size_t> (u.structures.size (), 12);
    for (std::size_t k = 0; k < shown; ++k)
    {
      const auto &x = u.structures[k];
      d << k << " " << std::max (x.strength, floor) << " " << (x.significant ? 2 : 1) << " \"" << x.structure
        << "\"\n";
    }
    d.close ();
    std::ofstream c (work + "/correlation.dat");
    const std::size_t lags = u.correlations.empty () ? 0 : u.correlations[0].measured.size ();
    for (std::size_t k = 0; k < lags; ++k)
    {
      c << k + 1;
      for (const auto &cor : u.correlations)
        c << " " << cor.measured[k] << " " << cor.model[k];
      c << "\n";
    }
    c.close ();
    ResidualDiagnosticsSettings defaults;
    std::ofstream g (work + "/unexplained.gp");
    AtomicFile png (folder + "/unexplained.png");
    g << "set terminal pngcairo size 1100,480 font 'Sans,10'\nset output '" << png.temporaryPath () << "'\n"
      << "set multiplot layout 1,2\nset grid\nset xtics noenhanced rotate by -35\nset bmargin 7\n"
      << "set title 'What the final model leaves: strength beyond its own replicas'\n"
      << "set ylabel 'strength (share of the residual variance)'\nset logscale y\nset yrange [" << floor << ":2]\n"
      << "set style fill solid 0.6\nset boxwidth 0.7\nset key top right\nset xrange [-0.6:" << shown - 0.4 << "]\n"
      << "plot '" << work << "/unexplained.dat' using 1:($3==2?$2:1/0):xtic(4) with boxes lc rgb '#c03020' "
      << "title 'significant', '' using 1:($3==1?$2:1/0):xtic(4) with boxes lc rgb '#8090a0' title 'not significant', "
      << defaults.min_strength << " with lines dt 2 lc 'black' title 'practical threshold'\n"
      << "unset logscale y\nset xtics norotate\nset bmargin 9\nset xrange [0.5:" << lags + 0.5 << "]\nset yrange [*:*]\n"
      << "set key below maxrows 3\nset title 'Residual autocorrelation after the frame, row and column offsets'\n"
      << "set xlabel 'lag (pixels along rows and columns, frames in time)'\nset ylabel 'autocorrelation'\n"
      << "plot '" << work << "/correlation.dat' using 1:2 with linespoints lw 2 pt 7 lc 1 title 'along rows, data', "
      << "'' using 1:3 with lines lw 1 dt 2 lc 1 title 'along rows, model', "
      << "'' using 1:4 with linespoints lw 2 pt 5 lc 2 title 'along columns, data', "
      << "'' using 1:5 with lines lw 1 dt 2 lc 2 title 'along columns, model', "
      << "'' using 1:6 with linespoints lw 2 pt 9 lc 3 title 'over time, data', "
      << "'' using 1:7 with lines lw 1 dt 2 lc 3 title 'over time, model'\n"
      << "unset multiplot\n";
    g.close ();
    drawPlot (work + "/unexplained.gp", png);
  }

  // --- maps of the SD ratio and the bias residual, one panel per recording (up to 6)
  std::vector<Region> regions;
  auto maps = [&] (const std::vector<PixelComparison> &cmp, const std::string &tag, const std::string &label) {
    const std::size_t R = std::min<std::size_t> (recs.size (), 6);
    double bias_scale = 0;
    std::vector<double> all_bias;
    for (std::size_t r = 0; r < R; ++r)
    {
      const auto &m = *recs[r];
      const int f = std::max (1, (m.width + 159) / 160);
      std::ofstream ra (work + "/ratio_" + tag + std::to_string (r) + ".dat"),
          bi (work + "/bias_" + tag + std::to_string (r) + ".dat");
      for (int by = 0; by < m.height / f; ++by)
      {
        for (int bx = 0; bx < m.width / f; ++bx)
        {
          double sr = 0, nr = 0, sb = 0, n = 0;
          for (int y = by * f; y < (by + 1) * f; ++y)
            for (int x = bx * f; x < (bx + 1) * f; ++x)
            {
              const std::size_t i = static_cast<std::size_t> (y) * m.width + x;
              if (!m.used[i] || !(cmp[r].sd_pred[i] > 0))
                continue;
              if (std::isfinite (m.sd_mm[i])) // single frames: no measured SD
              {
                sr += m.sd_mm[i] / cmp[r].sd_pred[i];
                nr += 1;
              }
              sb += m.mean_mm[i] - cmp[r].mean_pred[i];
              n += 1;
            }
          ra << (nr > 0 ? fmt (std::max (0.05, sr / nr)) : "NaN") << " ";
          bi << (n > 0 ? fmt (sb / n) : "NaN") << " ";
          if (n > 0)
            all_bias.push_back (std::fabs (sb / n));
        }
        ra << "\n";
        bi << "\n";
      }
      // Worst 32 px blocks of the starting model, for the text.
      if (tag == "start")
        for (int v0 = 0; v0 + 16 <= m.height; v0 += 32)
          for (int u0 = 0; u0 + 16 <= m.width; u0 += 32)
          {
            double sr = 0, sb = 0, n = 0;
            for (int y = v0; y < std::min (m.height, v0 + 32); ++y)
              for (int x = u0; x < std::min (m.width, u0 + 32); ++x)
              {
                const std::size_t i = static_cast<std::size_t> (y) * m.width + x;
                if (!m.used[i] || !(cmp[r].sd_pred[i] > 0) || !std::isfinite (m.sd_mm[i]))
                  continue;
                sr += std::log (m.sd_mm[i] / cmp[r].sd_pred[i]);
                sb += m.mean_mm[i] - cmp[r].mean_pred[i];
                n += 1;
              }
            if (n < 100)
              continue;
            const double ratio = std::exp (sr / n), bias = sb / n;
            std::ostringstream t;
            t << baseName (m.name) << ", columns " << u0 << "-" << std::min (m.width, u0 + 32) - 1 << ", rows " << v0
              << "-" << std::min (m.height, v0 + 32) - 1 << ": measured SD " << fmt (ratio, 3)
              << " x the predicted, mean bias residual " << fmt (bias, 3) << " mm";
            regions.push_back ({t.str (), std::fabs (std::log (ratio)) + std::fabs (bias) / 10.0});
          }
    }
    std::sort (all_bias.begin (), all_bias.end ());
    bias_scale = all_bias.empty () ? 1.0 : std::max (0.5, all_bias[all_bias.size () * 98 / 100]);
    for (int which = 0; which < 2; ++which)
    {
      const std::string kind = which ? "bias" : "sd_ratio";
      const std::string name = kind + "_map_" + tag + ".png";
      AtomicFile png (folder + "/" + name);
      const std::string &out = png.temporaryPath ();
      std::ofstream g (work + "/" + kind + tag + ".gp");
      const int cols = static_cast<int> (std::min<std::size_t> (R, 3)), rows = static_cast<int> ((R + 2) / 3);
      g << "set terminal pngcairo size " << 300 * cols + 60 << "," << 250 * rows + 40 << " font 'Sans,9'\n"
        << "set output '" << out << "'\n"
        << "set multiplot layout " << rows << "," << cols << " title '" << label << ": "
        << (which ? "mean minus predicted mean (mm)" : "measured SD / predicted SD (log colour scale)") << "'\n"
        << "set yrange [*:*] reverse\nset size ratio -1\nunset xtics\nunset ytics\n"
        << (which ? "set palette defined (-1 'blue', 0 'white', 1 'red')\nset cbrange [" + fmt (-bias_scale) + ":" +
                        fmt (bias_scale) + "]\n"
                  : "set palette defined (-1 'blue', 0 'white', 1 'red')\nset logscale cb\nset cbrange [0.25:4]\nset cbtics ('0.25' 0.25, '0.5' 0.5, '1' 1, '2' 2, '4' 4)\n");
      for (std::size_t r = 0; r < R; ++r)
        g << "set title '" << baseName (recs[r]->name) << "' noenhanced\nplot '" << work << "/"
          << (which ? "bias_" : "ratio_") << tag << r << ".dat' matrix with image notitle\n";
      g << "unset multiplot\n";
      g.close ();
      drawPlot (work + "/" + kind + tag + ".gp", png);
    }
  };
  maps (first, "start", "Starting model");
  if (!s.steps.empty ())
    maps (last, "final", "Final model");
  std::sort (regions.begin (), regions.end (), [] (const Region &a, const Region &b) { return a.score > b.score; });

  // --- residuals against each covariate (start and final model), with standard errors
  struct Cov
  {
    const char *name, *unit;
    double (*f) (const ModelLab &, std::size_t, std::size_t);
    bool discrete;
  };
  std::vector<Cov> covs = {{"radius", "px", covRadius, false},       {"depth", "mm", covDepth, false},
                           {"incidence angle", "deg", covIncidence, false}, {"column", "px", covColumn, false},
                           {"row", "px", covRow, false},             {"sub-step phase", "1", covPhase, false},
                           {"edge distance", "px (40 = none)", covEdge, false}, {"active projectors", "1", covProjectors, true}};
  // Recordings with colour frames: the grey level too, a tenth panel.
  if (std::any_of (recs.begin (), recs.end (), [] (const auto &r) { return !r->intensity.empty (); }))
    covs.push_back ({"grey level", "0-1", covIntensity, false});
  const int cov_rows = covs.size () > 8 ? 4 : 3;
  std::vector<Region> worst_covariates;
  for (int which = 0; which < 2; ++which)
  {
    const std::string name = which ? "bias_vs_covariates.png" : "sd_ratio_vs_covariates.png";
    AtomicFile png (folder + "/" + name);
    const std::string &out = png.temporaryPath ();
    std::ofstream g (work + "/cov" + std::to_string (which) + ".gp");
    g << "set terminal pngcairo size 1200," << 820 * cov_rows / 3 << " font 'Sans,9'\nset output '" << out << "'\n"
      << "set multiplot layout " << cov_rows << ",3 title '"
      << (which ? "Mean bias residual (mean - predicted, mm) against each covariate, +- 1 standard error"
                : "Measured SD / predicted SD against each covariate, +- 1 standard error")
      << "'\nset grid\nset key top left font ',8'\n";
    int panel = 0;
    for (const Cov &cv : covs)
    {
      const CovariateCurve a = covariateCurve (lab, first, cv.name, cv.unit, cv.f, cv.discrete);
      const CovariateCurve b = covariateCurve (lab, last, cv.name, cv.unit, cv.f, cv.discrete);
      const std::string file = work + "/cov" + std::to_string (which) + "_" + std::to_string (panel++) + ".dat";
      std::ofstream d (file);
      for (std::size_t k = 0; k < a.x.size (); ++k)
        d << a.x[k] << " " << (which ? a.bias_mean[k] : a.ratio_mean[k]) << " " << (which ? a.bias_se[k] : a.ratio_se[k])
          << "\n";
      d << "\n\n";
      for (std::size_t k = 0; k < b.x.size (); ++k)
        d << b.x[k] << " " << (which ? b.bias_mean[k] : b.ratio_mean[k]) << " " << (which ? b.bias_se[k] : b.ratio_se[k])
          << "\n";
      d.close ();
      if (!which)
      {
        // The covariate's worst bin, if it is off by more than 25 %.
        std::size_t worst = a.x.size ();
        for (std::size_t k = 0; k < a.x.size (); ++k)
          if (std::fabs (std::log (a.ratio_mean[k])) > std::log (1.25) &&
              (worst == a.x.size () || std::fabs (std::log (a.ratio_mean[k])) > std::fabs (std::log (a.ratio_mean[worst]))))
            worst = k;
        if (worst < a.x.size ())
          worst_covariates.push_back ({std::string (cv.name) + " near " + fmt (a.x[worst], 4) + " " + cv.unit +
                                           ": measured SD " + fmt (a.ratio_mean[worst], 3) + " x the predicted",
                                       std::fabs (std::log (a.ratio_mean[worst]))});
      }
      // Single frames: no measured SD, nothing to plot against the covariate.
      bool measured = which == 1;
      for (double v : a.ratio_mean)
        measured = measured || std::isfinite (v);
      if (!measured)
      {
        g << "set xlabel '" << cv.name << " (" << cv.unit << ")'\nset ylabel 'ratio'\nset yrange [0:2]\n"
          << "plot 1 with lines lc 'black' dt 2 title 'no temporal SD (one frame a pixel)'\nunset yrange\n";
        continue;
      }
      g << "set xlabel '" << cv.name << " (" << cv.unit << ")'\n"
        << (which ? "set ylabel 'mm'\n" : "set ylabel 'ratio'\n")
        << "plot '" << file << "' index 0 using 1:2:3 with yerrorlines pt 7 ps 0.5 title 'start', "
        << (s.steps.empty () ? "" : "'" + file + "' index 1 using 1:2:3 with yerrorlines pt 5 ps 0.5 title 'final', ")
        << (which ? "0" : "1") << " with lines lc 'black' dt 2 notitle\n";
    }
    // The last panel: the per-frame offset (drift), measured and predicted, averaged over recordings.
    {
      const std::string file = work + "/frames" + std::to_string (which) + ".dat";
      std::ofstream d (file);
      std::map<int, std::vector<double>> meas, pa, pb;
      for (std::size_t r = 0; r < recs.size (); ++r)
      {
        std::vector<double> p0, m0, p1, m1;
        lab.frameCurve (s.start, r, p0, m0);
        lab.frameCurve (s.final_model, r, p1, m1);
        for (std::size_t t = 0; t < m0.size (); ++t)
          if (std::isfinite (m0[t]))
          {
            meas[static_cast<int> (t)].push_back (m0[t]);
            pa[static_cast<int> (t)].push_back (p0[t]);
            pb[static_cast<int> (t)].push_back (p1[t]);
          }
      }
      auto mean = [] (const std::vector<double> &v) {
        double s = 0;
        for (double x : v)
          s += x;
        return v.empty () ? 0.0 : s / v.size ();
      };
      for (const auto &kv : meas)
        d << kv.first << " " << mean (kv.second) << " " << mean (pa[kv.first]) << " " << mean (pb[kv.first]) << "\n";
      d.close ();
      g << "set xlabel 'frame index'\nset ylabel 'mm at the centre'\n";
      if (meas.empty ()) // single frames: no frame offsets
        g << "plot 0 with lines lc 'black' dt 2 title 'no frame offsets (one frame a pixel)'\n";
      else
        g << "plot '" << file << "' using 1:2 with linespoints pt 7 ps 0.5 title 'measured frame offset', '' using 1:3 "
        << "with lines lw 2 title 'start', '' using 1:4 with lines lw 2 dt 2 title 'final'\n";
    }
    g << "unset multiplot\n";
    g.close ();
    drawPlot (work + "/cov" + std::to_string (which) + ".gp", png);
  }

  // --- model.yaml, report.json
  saveNoiseModelYaml (folder + "/model.yaml", s.final_model);
  writeFileAtomically (folder + "/report.json", labReportJson (s));

  // --- report.html
  std::ostringstream h;
  auto metricsRow = [&] (const std::string &what, const LabMetrics &m) {
    h << "<tr><td>" << escape (what) << "</td><td>" << sdText (m) << "</td><td>" << fmt (m.bias_rmse_mm)
      << "</td><td>" << fmt (m.nll) << "</td><td>" << fmt (100 * m.within_1sigma, 3) << " %</td><td>"
      << fmt (100 * m.within_2sigma, 3) << " %</td><td>" << fmt (m.texlets.nees_p, 3) << " ("
      << fmt (m.texlets.ratioP (), 3) << " x; median " << fmt (m.texlets.medianRatioP (), 3) << " x)</td><td>"
      << fmt (m.texlets.nees_n, 3) << " (" << fmt (m.texlets.ratioN (), 3) << " x; median "
      << fmt (m.texlets.medianRatioN (), 3) << " x)</td><td>" << m.texlets.texlets << "</td></tr>\n";
  };
  auto image = [&] (const std::string &name, const std::string &caption) {
    h << "<figure><img src=\"data:image/png;base64," << base64 (readFile (folder + "/" + name)) << "\" alt=\"" << name
      << "\"><figcaption>" << escape (caption) << "</figcaption></figure>\n";
  };
  h << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>pcl_texlet model lab</title><style>"
    << "body{font-family:sans-serif;max-width:1250px;margin:auto;padding:1em}table{border-collapse:collapse;margin:"
    << "0.5em 0}td,th{border:1px solid #bbb;padding:3px 7px;font-size:90%}th{background:#eee}img{max-width:100%}"
    << ".sig{color:#060;font-weight:bold}pre{background:#f6f6f6;padding:0.5em;overflow-x:auto;font-size:80%}"
    << "</style></head><body>\n<h1>pcl_texlet model lab</h1>\n";
  {
    // The structure no effect of the model explains, said first.
    auto said = [&] (const ResidualDiagnostics &u, const std::string &model) {
      std::vector<const UnexplainedStructure *> sig;
      for (const auto &x : u.structures)
        if (x.significant)
          sig.push_back (&x);
      if (sig.empty ())
      {
        h << "<p>" << escape (model) << ": nothing significant is left in the residuals (every structure below "
          << "the practical threshold or within the model's own replicas).</p>\n";
        return;
      }
      h << "<p>" << escape (model) << ": <b>" << escape (sig[0]->structure) << "</b> is the strongest structure the "
        << "model does not explain.</p>\n<ul>\n";
      for (const auto *x : sig)
        h << "<li><b>" << escape (x->structure) << "</b>: " << escape (x->words) << " (z " << fmt (x->z, 3)
          << ").</li>\n";
      h << "</ul>\n";
    };
    h << "<h2>What the model leaves unexplained</h2>\n<p>Each structure is measured on the residuals and on "
      << "replicas of the model's own noise on the same pixels (its column and frame offsets included); its "
      << "strength is the difference, and it is significant when that is at least "
      << fmt (ResidualDiagnosticsSettings ().min_z, 2) << " replica SDs and at least "
      << fmt (ResidualDiagnosticsSettings ().min_strength, 2) << " (docs/model_lab.md, \"What no effect "
      << "explains\"). A vocabulary effect in the model takes its structure off the list.</p>\n";
    said (s.unexplained, s.steps.empty () ? "The model refitted" : "The final model");
    said (s.start_unexplained, "The model as given (" + s.start_name + ")");
    image ("unexplained.png", "Left: the strongest structures the final model leaves (significant in red; log "
                              "scale; dashed: the practical threshold). Right: the residuals' autocorrelation "
                              "along rows, along columns and over time, data (solid) against the model's replicas "
                              "(dashed).");
  }
  h << "<h2>Recordings</h2><table><tr><th>recording</th><th>frames</th><th>size</th><th>scene</th><th>projectors</th>"
    << "<th>pixels compared</th><th>left out (too few valid frames)</th><th>never valid</th></tr>\n";
  for (const auto &r : recs)
    h << "<tr><td>" << escape (r->name) << "</td><td>" << r->frames << "</td><td>" << r->width << "x" << r->height
      << "</td><td>" << escape (r->scene) << "</td><td>" << r->active_projectors << "</td><td>" << r->usedCount ()
      << "</td><td>" << r->left_out << "</td><td>" << r->no_surface << "</td></tr>\n";
  h << "</table>\n<p>" << escape (latticeSummary (s.lattice)) << "</p>\n";
  h << "<h2>1-2. The model against the measurements</h2>\n<p>Starting model: <b>" << escape (s.start_name)
    << "</b>. Metrics over all frames (NLL: Gaussian negative log-likelihood per depth sample, in nats, with the "
       "frame and column offsets as separate parts; calibration: share of samples within 1 and 2 predicted SDs of "
       "the predicted mean, 68.3 % and 95.4 % when calibrated).</p>\n<p>Texlet NEES: texlets extracted with the "
       "model as their noise model at the extractor's default settings (automatic RANSAC threshold widened by "
       "the patch's own residual scale, P on the centre pixel's ray; Analytic uncertainty) at the same "
       "hexagonal-grid centres in up to 15 evenly spaced frames of each recording; per centre, the mean NEES "
       "over frames of P against its own Sigma_P and of N (its deviation from the mean normal in the texlet's "
       "tangent frame) against Sigma_N. Ideal: rank (Sigma_P) (n - 1) / n for P (1 dof on the centre ray) and "
       "2 (n - 1) / n for N with n frames (the mean is estimated); in brackets the ratio to the ideal (1 when calibrated, above 1 when the texlets are "
       "over-confident) and that of the median NEES to its ideal (robust to a few texlets that jump).</p>\n<table><tr><th>model</th><th>sd_rmse_mm (its part by chance)</th>"
       "<th>bias_rmse_mm</th><th>nll</th><th>within 1 sigma</th><th>within 2 sigma</th><th>texlet NEES P</th>"
       "<th>texlet NEES N</th><th>texlets</th></tr>\n";
  metricsRow ("start: " + s.start_name, s.start_metrics);
  for (const auto &st : s.steps)
    metricsRow ("+ " + st.added, st.metrics);
  h << "</table>\n<h2>3. Where it fails</h2>\n";
  image ("sd_ratio_map_start.png", "Measured over predicted temporal SD per pixel, starting model (red: noisier than "
                                   "predicted).");
  image ("bias_map_start.png", "Mean depth minus the predicted mean (the surface fit plus the model's bias), "
                               "starting model.");
  image ("sd_ratio_vs_covariates.png", "SD ratio against each covariate (start and final model); the last panel "
                                       "shows the mean offset of each frame.");
  image ("bias_vs_covariates.png", "Bias residual against each covariate.");
  h << "<p>Worst regions (32 px blocks) under the starting model:</p><ul>\n";
  for (std::size_t k = 0; k < std::min<std::size_t> (regions.size (), 5); ++k)
    h << "<li>" << escape (regions[k].text) << "</li>\n";
  h << "</ul>\n<p>The worst bin of each covariate where the measured SD differs from the predicted by more "
       "than 25 %, worst first:</p><ul>\n";
  std::sort (worst_covariates.begin (), worst_covariates.end (),
             [] (const Region &a, const Region &b) { return a.score > b.score; });
  for (const auto &w : worst_covariates)
    h << "<li>" << escape (w.text) << "</li>\n";
  if (worst_covariates.empty ())
    h << "<li>none</li>\n";
  h << "</ul>\n<h2>4. What is missing: the candidates</h2>\n<p>Each effect not in the model was fitted together with "
       "the model's terms on one half of the data and scored on the other. Gain: the fall of the held-out NLL per "
       "sample against the current model refitted on the same half. Significant: the gain exceeds the mean of the "
       "gains the same fit brings on "
    << lab.settings ().null_replicates << " data sets drawn from the current model (no effect missing) by more than "
    << lab.settings ().null_sigmas << " of their SDs, and the gain summed over the held-out samples is at least "
    << lab.settings ().min_total_gain_nats << " nats (a likelihood ratio of at least e^"
    << lab.settings ().min_total_gain_nats << " on data the fit did not see), and, so that it matters as well as "
       "being detectable, it removes at least "
    << 100.0 * lab.settings ().min_effect_size
    << " % of the mean squared error of the SD, the bias or the lines' offsets where it shows (the pixels, or the "
       "columns and rows, where adding it moves that prediction most). For the statistically significant candidates the texlets are scored too, on the "
       "score half's frames (every frame where the halves are pixel blocks): the median texlet NEES of P and N over "
       "its ideal with the candidate's model (fitted on the fit half), and their distance from honest (the larger "
       "|ln| of the two ratios) under the current model refitted and with the candidate; nearer 1 (nearer 0) means "
       "honester covariances. A term that takes them further from 1 "
       "than the current model refitted by more than a factor of "
    << fmt (std::exp (lab.settings ().max_texlet_worsening), 3)
    << " (in the worse of P and N) is not significant: it would make the covariances users consume less honest "
       "(a rounding is exempt: the texlets take the model's bias off their depths, but a rounding's phase at a "
       "reading is unknown). "
       "Otherwise the choice stays with the held-out likelihood: the texlet NEES sums every effect into two numbers "
       "and cannot tell which is missing.</p>\n<table><tr><th>#</th><th>effect</th><th>gain (nats/sample)"
    << "</th><th>threshold</th><th>effect size (error where it shows)</th><th>significant</th><th>sd_rmse_mm (its part by chance)</th>"
    << "<th>bias_rmse_mm</th><th>nll</th><th>texlet NEES, median / ideal: P, N</th><th>shows in</th>"
    << "<th>physics</th></tr>\n";
  for (std::size_t k = 0; k < s.candidates.size (); ++k)
  {
    const auto &c = s.candidates[k];
    h << "<tr><td>" << k + 1 << "</td><td>" << c.effect << "</td>";
    if (c.applicable)
    {
      h << "<td>" << fmt (c.gain) << "</td><td>" << fmt (c.threshold, 3) << "</td><td>" << fmt (100.0 * c.effect_size, 3)
        << " % of the " << c.effect_shows_in << " error's mean square (RMS " << fmt (c.error_before, 3) << " to "
        << fmt (c.error_after, 3);
      if (c.error_unit == "mm")
        h << " mm over " << fmt (100.0 * c.effect_share, 2) << (c.effect_shows_in == "offsets" ? " % of lines)" : " % of pixels)");
      else // the neighbours' residual correlation, dimensionless, over every lag
        h << " over lags 1 to " << ResidualDiagnosticsSettings ().max_lag << " along rows and columns)";
      h << "</td><td"
        << (c.significant                   ? std::string (" class=\"sig\">yes")
            : c.statistically_significant ? ">no (" + candidateVerdict (c) + ")"
                                          : std::string (">no"))
        << "</td><td>" << sdText (c.metrics) << "</td><td>"
        << fmt (c.metrics.bias_rmse_mm) << "</td><td>" << fmt (c.metrics.nll) << "</td><td>"
        << (c.metrics.texlets.samples > 0
                ? fmt (c.metrics.texlets.medianRatioP (), 3) + ", " + fmt (c.metrics.texlets.medianRatioN (), 3) +
                      " (distance from honest " + fmt (c.texlet_error_before, 3) + " to " + fmt (c.texlet_error_after, 3) + ")"
                : std::string ("-"))
        << "</td>";
    }
    else
      h << "<td colspan=\"8\">not testable: " << escape (c.note) << "</td>";
    h << "<td>" << escape (c.signature) << "</td><td>" << escape (c.physics) << "</td></tr>\n";
  }
  h << "</table>\n<h2>5. Add and refit: watch the error fall</h2>\n";
  if (s.steps.empty ())
    h << "<p>No effect was added (use --add EFFECT or --auto N). model.yaml holds the starting model refitted.</p>\n";
  image ("staircase.png", "The error after each added effect (all data, every parameter refitted).");
  if (!s.steps.empty ())
  {
    image ("sd_ratio_map_final.png", "SD ratio per pixel, final model.");
    image ("bias_map_final.png", "Bias residual per pixel, final model.");
  }
  for (const auto &n : s.notes)
    h << "<p><b>Note:</b> " << escape (n) << "</p>\n";
  h << "<h2>6. The fitted model (model.yaml)</h2>\n<p>Load it with <code>pcl_texlet_extract --noise-model "
       "model.yaml</code> or <code>pcl::texlet::loadNoiseModelYaml</code>.</p><pre>"
    << escape (noiseModelToYaml (s.final_model)) << "</pre>\n</body></html>\n";
  writeFileAtomically (folder + "/report.html", h.str ());
  // The plot scripts and data are not part of the report.
  std::error_code ec;
  std::filesystem::remove_all (work, ec);
  if (ec)
    say (lab, "lab: could not remove " + work);
}

} // namespace lab
} // namespace texlet
} // namespace pcl
