/*
 * pcl_texlet model lab: ranking the candidate effects. Each is fitted on the fit half and scored
 * on the score half; its gain is judged against the gains of the same fit on data drawn from the
 * current model (the parametric bootstrap).
 */
#include <pcl_texlet/lab/model_lab.h>

#include "bootstrap.h"
#include "effect_size.h"
#include "lab_data.h"
#include "nll_fit.h"
#include "spatial_correlation_fit.h"
#include "static_fit.h"

#include <pcl_texlet/common/parallel_for.h>
#include <pcl_texlet/lab/residual_diagnostics.h>
#include <pcl_texlet/noise/effect_registry.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <random>

namespace pcl
{
namespace texlet
{
namespace lab
{

using namespace detail;

std::vector<Candidate>
ModelLab::rankCandidates (const NoiseModel &current) const
{
  const std::shared_ptr<const Data> data_fit = data (Half::fit, current), data_score = data (Half::score, current);
  const Data &A = *data_fit, &B = *data_score;
  auto say = [&] (const std::string &line) {
    if (settings_.progress)
      settings_.progress (line);
  };
  const int threads = settings_.threads > 0 ? settings_.threads : omp_get_max_threads ();

  // Which effects the data can show at all.
  std::vector<Candidate> out;
  for (const auto &name : noiseEffectNames ())
  {
    if (current.find (name))
      continue;
    Candidate c;
    c.effect = name;
    const EffectInfo &info = effectInfo (name);
    c.physics = info.physics;
    c.signature = info.signature;
    c.note = whyNotApplicable (name);
    c.applicable = c.note.empty ();
    out.push_back (c);
  }

  // Data sets: 0 is the real data; 1 .. null_replicates are drawn from the current model (the
  // null: the same fits where no effect is missing). On each, the current model refitted on the
  // fit half is what every candidate has to beat.
  struct DataSet
  {
    const Data *fit = nullptr, *score = nullptr;
    std::unique_ptr<Data> own_fit, own_score;
    NoiseModel given, fitted; // the model the candidates start from as given, and refitted
    double fitted_score = 0, fitted_objective = 0;
  };
  const int S = 1 + std::max (0, settings_.null_replicates);
  std::vector<DataSet> sets (S);
  auto refit = [&] (DataSet &set) {
    set.fitted = fitOn (set.given, *set.fit, recordings_, settings_);
    set.fitted_score = scoreOn (set.fitted, *set.score, recordings_);
    StaticState state;
    set.fitted_objective = fitObjective (set.fitted, *set.fit, recordings_, state);
  };
  say ("lab: refitting the current model on the fit half");
  sets[0].fit = &A;
  sets[0].score = &B;
  sets[0].given = current;
  refit (sets[0]);
  const NoiseModel &base = sets[0].fitted;
  std::mt19937_64 rng (settings_.seed);
  for (int rep = 1; rep < S; ++rep)
  {
    say ("lab: significance, drawing bootstrap data set " + std::to_string (rep) + " of " + std::to_string (S - 1));
    DataSet &set = sets[rep];
    set.own_fit = synthesise (A, base, recordings_, rng);
    set.own_score = synthesise (B, base, recordings_, rng);
    set.fit = set.own_fit.get ();
    set.score = set.own_score.get ();
    // As for the real data: the model as given (here the one the data were drawn from) and its
    // refit.
    set.given = base;
  }
  say ("lab: refitting the current model on the bootstrap data sets");
  parallelFor (S - 1, threads, true, [&] (int i) { refit (sets[i + 1]); });

  // Every fit of a candidate on every data set is one task, so that the two threads stay busy
  // to the end (disparity_quantization, fitted twice, costs more than the others together).
  struct Fit
  {
    int set, candidate;
    bool from_given; // disparity_quantization's second fit, on top of the model as given
    NoiseModel model;
    double objective = 0;
  };
  std::vector<Fit> fits;
  for (int set = 0; set < S; ++set)
    for (int k = 0; k < static_cast<int> (out.size ()); ++k)
      if (out[k].applicable && !fittedToNeighbourPairs (out[k].effect))
      {
        fits.push_back ({set, k, false, NoiseModel (), 0.0});
        if (effectInfo (out[k].effect).quantises &&
            sets[set].given.terms ().size () == sets[set].fitted.terms ().size ())
          fits.push_back ({set, k, true, NoiseModel (), 0.0});
      }
  say ("lab: fitting " + std::to_string (out.size ()) + " candidates on " + std::to_string (S) + " data sets (" +
       std::to_string (fits.size ()) + " fits)");
  // The longest first: disparity_quantization's fits, then the rest in order.
  std::vector<int> order (fits.size ());
  std::iota (order.begin (), order.end (), 0);
  std::stable_partition (order.begin (), order.end (),
                         [&] (int i) { return effectInfo (out[fits[i].candidate].effect).quantises; });
  parallelFor (static_cast<int> (fits.size ()), threads, true, [&] (int i) {
    Fit &f = fits[order[i]];
    const DataSet &set = sets[f.set];
    f.model = fitWithEffect (set.fitted, set.given, out[f.candidate].effect, *set.fit, recordings_, settings_,
                             set.fitted_objective, f.from_given ? 1 : 0);
    NoiseModel copy (f.model);
    StaticState state;
    f.objective = fitObjective (copy, *set.fit, recordings_, state);
  });

  // Per data set and candidate the better of its fits on the fit half, scored on the other half.
  std::vector<std::vector<double>> null_gains (out.size (), std::vector<double> (S - 1, 0.0));
  std::vector<int> chosen;
  for (int i = 0; i < static_cast<int> (fits.size ()); ++i)
  {
    const bool same = !chosen.empty () && fits[chosen.back ()].set == fits[i].set &&
                      fits[chosen.back ()].candidate == fits[i].candidate;
    if (!same)
      chosen.push_back (i);
    else if (fits[i].objective < fits[chosen.back ()].objective)
      chosen.back () = i;
  }
  // Each candidate's practical effect is measured against the refitted current model's
  // per-pixel predictions on the score half.
  PixelErrors base_pixels;
  evaluate (base, B, &base_pixels);
  parallelFor (static_cast<int> (chosen.size ()), threads, true, [&] (int i) {
    const Fit &f = fits[chosen[i]];
    const DataSet &set = sets[f.set];
    const double gain = set.fitted_score - scoreOn (f.model, *set.score, recordings_);
    if (f.set > 0)
    {
      null_gains[f.candidate][f.set - 1] = gain;
      return;
    }
    Candidate &c = out[f.candidate];
    c.model = f.model;
    c.gain = gain;
    PixelErrors pixels;
    c.metrics = evaluate (c.model, B, &pixels);
    const EffectSize size = effectSize (base_pixels, pixels);
    // Judged on what the term can move: a term of variance only changes the bias through the
    // surface fit's weights, which is not its signature.
    const bool moves_mean = effectInfo (c.effect).moves_mean;
    const double falls[] = {size.sd_fall, moves_mean ? size.bias_fall : -std::numeric_limits<double>::infinity (), size.line_fall};
    const int best = static_cast<int> (std::max_element (falls, falls + 3) - falls);
    c.effect_size = falls[best];
    c.effect_shows_in = best == 0 ? "sd" : best == 1 ? "bias" : "offsets";
    c.effect_share = best == 0 ? size.sd_share : best == 1 ? size.bias_share : size.line_share;
    c.error_before = best == 0 ? size.sd_before_mm : best == 1 ? size.bias_before_mm : size.line_before_mm;
    c.error_after = best == 0 ? size.sd_after_mm : best == 1 ? size.bias_after_mm : size.line_after_mm;
#pragma omp critical(lab_progress)
    say ("lab: candidate " + c.effect + ": held-out gain " + std::to_string (c.gain) + " nats/sample, " +
         c.effect_shows_in + " error " + std::to_string (100.0 * c.effect_size) + " % of its squared error removed where it shows");
  });
  // Terms of the neighbours' correlation: fitted on the even frames' neighbour pairs and scored
  // on the odd frames' (the per-pixel halves cannot see them); the null: the same on the
  // diagnostics' replicas of the current model.
  std::unique_ptr<ResidualDiagnostics> pairs;
  for (std::size_t k = 0; k < out.size (); ++k)
  {
    Candidate &c = out[k];
    if (!c.applicable || !fittedToNeighbourPairs (c.effect))
      continue;
    if (!pairs)
    {
      say ("lab: neighbour pairs of the residuals under the current model, and of its replicas");
      pairs = std::make_unique<ResidualDiagnostics> (diagnoseResiduals (*this, base));
    }
    const ModelCorrelation mc = modelCorrelation (*pairs);
    const NeighbourPairs &data_pairs = pairs->neighbour_pairs[0];
    // Scored with the share fitted to the windows' overlap, as the data's excess is measured; the
    // candidate's model carries the share calibrated through its replicas, as --add fits it.
    const WindowFit fit = fitWindow (data_pairs, mc, 0);
    c.gain = windowGain (data_pairs, mc, fit, 1);
    null_gains[k].clear (); // the per-pixel bootstrap's slots, never filled for this term
    for (std::size_t j = 1; j < pairs->neighbour_pairs.size (); ++j)
    {
      const NeighbourPairs &null_pairs = pairs->neighbour_pairs[j];
      const ModelCorrelation others = modelCorrelation (*pairs, j);
      null_gains[k].push_back (windowGain (null_pairs, others, fitWindow (null_pairs, others, 0), 1));
    }
    c.model = withFittedWindow (*this, base, c.effect, *pairs, 0);
    c.metrics = evaluate (c.model, B, nullptr);
    c.effect_size = windowEffect (data_pairs, mc, fit, 1, c.error_before, c.error_after);
    c.effect_shows_in = "correlation";
    c.error_unit = "correlation";
    c.effect_share = 1.0;
    const NoiseTerm::Ptr term = c.model.find (c.effect);
    const std::vector<double> p = term ? term->parameters () : std::vector<double> ();
    c.note = "fitted to the correlation of neighbouring pixels' residuals (even frames), scored on the odd frames' "
             "pairs: share " + std::to_string (p.size () > 0 ? p[0] : fit.share) + " over a " +
             std::to_string (fit.window_px) + " px window";
    say ("lab: candidate " + c.effect + ": held-out gain " + std::to_string (c.gain) + " nats/sample, share " +
         std::to_string (fit.share) + " of the overlap (calibrated " + std::to_string (p.size () > 0 ? p[0] : fit.share) +
         ") over " + std::to_string (fit.window_px) + " px");
  }
  for (std::size_t k = 0; k < out.size (); ++k)
  {
    Candidate &c = out[k];
    const auto &g = null_gains[k];
    if (!c.applicable || g.empty ())
      continue;
    const double mean = std::accumulate (g.begin (), g.end (), 0.0) / g.size ();
    double var = 0;
    for (double x : g)
      var += (x - mean) * (x - mean);
    c.null_mean = mean;
    c.null_sd = g.size () > 1 ? std::sqrt (var / (g.size () - 1)) : 0.0;
    c.threshold = mean + settings_.null_sigmas * c.null_sd;
    c.total_gain = c.gain * (fittedToNeighbourPairs (c.effect) && pairs ? pairs->neighbour_pairs[0].samples[1] : B.samples);
    c.statistically_significant = c.gain > c.threshold && c.gain > 0 && c.total_gain >= settings_.min_total_gain_nats;
    c.significant = c.statistically_significant && c.effect_size >= settings_.min_effect_size;
  }
  // The texlets of the statistically significant candidates, on the frames they were not fitted on
  // (all frames where the halves are pixel blocks), against the refitted current model's there.
  if (std::any_of (out.begin (), out.end (), [] (const Candidate &c) { return c.applicable && c.statistically_significant; }))
  {
    const std::string where = splitsFrames () ? "on the score half's frames" : "on every frame (the halves are pixel blocks)";
    say ("lab: texlet NEES " + where + " under the current model refitted");
    const double before = texlets (base, Half::score).logRatioError ();
    for (Candidate &c : out)
      if (c.applicable && c.statistically_significant)
      {
        say ("lab: texlet NEES " + where + " with " + c.effect);
        c.metrics.texlets = texlets (c.model, Half::score);
        c.texlet_error_before = before;
        c.texlet_error_after = c.metrics.texlets.logRatioError ();
        // A term that makes the covariances users consume less honest is not one to add, whatever
        // the pixels gain (NaN, nothing compared, vetoes nothing). The texlets take the model's
        // bias off their readings, but not a rounding's: at a reading its phase is unknown, so its
        // staircase stays in P and a rounding is exempt (docs/model_lab.md section 4).
        if (c.significant && !effectInfo (c.effect).quantises &&
            c.texlet_error_after > c.texlet_error_before + settings_.max_texlet_worsening)
        {
          c.significant = false;
          c.texlets_less_honest = true;
          c.note += std::string (c.note.empty () ? "" : "; ") + "makes the texlets' covariances less honest on the " +
                    "score half (|ln median NEES ratio| " + std::to_string (c.texlet_error_before) + " -> " +
                    std::to_string (c.texlet_error_after) + ")";
        }
      }
  }
  std::stable_sort (out.begin (), out.end (), [] (const Candidate &a, const Candidate &b) {
    if (a.applicable != b.applicable)
      return a.applicable;
    return a.gain > b.gain;
  });
  return out;
}

std::string
candidateVerdict (const Candidate &c)
{
  if (!c.applicable)
    return "not testable";
  if (c.significant)
    return "significant";
  if (!c.statistically_significant)
    return "not significant";
  return c.texlets_less_honest ? "detectable, makes the texlets less honest" : "detectable, too small";
}

std::string
ModelLab::whyNotApplicable (const std::string &effect) const
{
  const unsigned needs = effectInfo (effect).lab_needs;
  // Single frames first: it is the most basic of the limits.
  if ((needs & effects::kNeedsRepeatedFrames) && !facts_.any_repeated)
    return "needs at least 2 frames per pixel to measure temporal noise: it adds variance only, which single frames "
           "cannot tell from an unmodelled bias";
  if ((needs & effects::kNeedsPlaneScene) && !facts_.any_plane)
    return "needs a plane scene (meta.yaml scene: plane) to tell a static bias from the surface";
  if ((needs & effects::kNeedsVariedProjectors) && !(facts_.max_projectors > facts_.min_projectors))
    return "every recording has the same number of active projectors";
  if ((needs & effects::kNeedsFrameSplit) && !splitsFrames ())
    return "needs recordings of at least 4 frames";
  if ((needs & effects::kNeedsDepthEdges) && !facts_.any_edges)
    return "no depth edges in the recordings";
  if ((needs & effects::kNeedsIntensity) && !facts_.any_intensity)
    return "needs colour frames (rgb/*.png) to know each pixel's grey level";
  return std::string ();
}

} // namespace lab
} // namespace texlet
} // namespace pcl
