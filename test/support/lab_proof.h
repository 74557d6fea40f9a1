/*
 * pcl_texlet tests: the model lab's proof on a set of recordings, whoever made them (the
 * simulator in test_lab.cpp, the independent generator in test_lab_independent.cpp). The lab,
 * started from the paper's model and not told what is hidden, ranks the candidates; adding the
 * first must bring the error where it shows down.
 */
#pragma once

#include <pcl_texlet/lab/model_lab.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

namespace pcl_texlet_test
{

/** \brief What the lab did with one set of recordings. */
struct LabRun
{
  pcl::texlet::lab::LabMetrics before, after;
  std::vector<pcl::texlet::lab::Candidate> candidates;
};

/** \brief Ranks the candidates on top of the paper's model and, when \a add_first, adds the
  * first and evaluates the result; prints what it found under \a title.
  */
inline LabRun
runLabOn (const std::vector<pcl::texlet::lab::RecordingMeasurement::ConstPtr> &recordings, const std::string &title,
          bool add_first)
{
  using namespace pcl::texlet;
  lab::ModelLab lab{lab::LabSettings ()};
  for (const auto &r : recordings)
    lab.addRecording (r);
  LabRun run;
  const NoiseModel paper = NoiseModel::paper ();
  run.before = lab.evaluate (paper);
  run.candidates = lab.rankCandidates (paper);
  std::cout << title << "\n  start: sd_rmse " << run.before.sd_rmse_mm << " bias_rmse " << run.before.bias_rmse_mm
            << " nll " << run.before.nll << "\n";
  for (const auto &c : run.candidates)
  {
    std::cout << "  " << c.effect << ": gain " << c.gain << " (" << c.total_gain << " nats in all) threshold "
              << c.threshold << " (null " << c.null_mean << " +- " << c.null_sd << "), " << c.effect_shows_in
              << " error: " << 100.0 * c.effect_size << " % of its mean square removed where it shows ("
              << 100.0 * c.effect_share << " % of pixels)" << " (" << lab::candidateVerdict (c) << ")"
              << (c.metrics.texlets.samples > 0 ? ", texlets' distance from honest " + std::to_string (c.texlet_error_before) +
                                                      " -> " + std::to_string (c.texlet_error_after) + " (P " +
                                                      std::to_string (c.metrics.texlets.medianRatioP ()) + ", N " +
                                                      std::to_string (c.metrics.texlets.medianRatioN ()) + ")"
                                                : std::string ())
              << " sd_rmse "
              << c.metrics.sd_rmse_mm << " bias_rmse " << c.metrics.bias_rmse_mm;
    if (const NoiseTerm::Ptr term = c.model.find (c.effect))
    {
      std::cout << ", fitted";
      for (const double v : term->parameters ())
        std::cout << " " << v;
    }
    std::cout << "\n";
  }
  if (add_first && !run.candidates.empty ())
  {
    const NoiseModel added = lab.addEffect (paper, run.candidates.front ().effect);
    run.after = lab.evaluate (added);
    std::cout << "  after adding " << run.candidates.front ().effect << ": sd_rmse " << run.after.sd_rmse_mm
              << " bias_rmse " << run.after.bias_rmse_mm << " nll " << run.after.nll << "\n";
  }
  return run;
}

/** \brief The hidden \a effect must be ranked first and significant, and adding it must bring the
  * error where it shows (the bias when \a shows_in_bias, else the SD) to at most \a max_ratio of
  * the paper's; none of the candidates in \a not_significant may be called significant.
  * \return what the lab did, for checks of the fitted term
  */
inline LabRun
expectFoundIn (const std::vector<pcl::texlet::lab::RecordingMeasurement::ConstPtr> &recordings,
               const std::string &effect, bool shows_in_bias, double max_ratio = 0.5,
               const std::vector<std::string> &not_significant = {})
{
  const LabRun run = runLabOn (recordings, "hidden effect: " + effect, true);
  EXPECT_FALSE (run.candidates.empty ());
  if (run.candidates.empty ())
    return run;
  for (const auto &c : run.candidates)
    for (const auto &name : not_significant)
      if (c.effect == name)
        EXPECT_FALSE (c.significant) << name << ": " << c.effect_shows_in << " error " << 100.0 * c.effect_size
                                     << " % of its mean square removed where it shows";
  EXPECT_EQ (run.candidates.front ().effect, effect);
  EXPECT_TRUE (run.candidates.front ().significant);
  const double before = shows_in_bias ? run.before.bias_rmse_mm : run.before.sd_rmse_mm;
  const double after = shows_in_bias ? run.after.bias_rmse_mm : run.after.sd_rmse_mm;
  EXPECT_LE (after, max_ratio * before) << (shows_in_bias ? "bias_rmse_mm" : "sd_rmse_mm");
  return run;
}

/** \brief Both hidden \a effects must be added, in either order, by what the app's --auto 2 does
  * (rank the candidates, add the best significant one, re-rank against the result, add the best
  * again), and the SD and the bias error must each fall to at most \a max_ratio of the paper's,
  * the SD error also with what chance alone gives any model (sd_floor_mm) taken out of both.
  */
inline void
expectBothFoundIn (const std::vector<pcl::texlet::lab::RecordingMeasurement::ConstPtr> &recordings,
                   std::vector<std::string> effects, double max_ratio = 0.5)
{
  using namespace pcl::texlet;
  lab::ModelLab lab{lab::LabSettings ()};
  for (const auto &r : recordings)
    lab.addRecording (r);
  NoiseModel model = NoiseModel::paper ();
  const lab::LabMetrics before = lab.evaluate (model);
  std::cout << "hidden effects: " << effects[0] << " and " << effects[1] << "\n  start: sd_rmse " << before.sd_rmse_mm
            << " (" << before.sd_floor_mm << " by chance) bias_rmse " << before.bias_rmse_mm << "\n";
  std::vector<std::string> added;
  for (int round = 0; round < 2; ++round)
  {
    const std::vector<lab::Candidate> candidates = lab.rankCandidates (model);
    const lab::Candidate *best = nullptr;
    for (const auto &c : candidates)
    {
      std::cout << "  round " << round + 1 << " " << c.effect << ": gain " << c.gain << " threshold " << c.threshold
                << ", " << c.effect_shows_in << " error: " << 100.0 * c.effect_size
                << " % of its mean square removed where it shows" << (c.significant ? " significant" : "") << "\n";
      if (!best && c.applicable && c.significant)
        best = &c;
    }
    ASSERT_NE (best, nullptr) << "round " << round + 1 << ": no significant candidate";
    added.push_back (best->effect);
    model = lab.addEffect (model, best->effect);
  }
  const lab::LabMetrics after = lab.evaluate (model);
  std::cout << "  after adding " << added[0] << " and " << added[1] << ": sd_rmse " << after.sd_rmse_mm << " ("
            << after.sd_floor_mm << " by chance) bias_rmse " << after.bias_rmse_mm << "\n";
  for (const auto &term : model.terms ())
  {
    std::cout << "  " << term->name () << ":";
    for (const double v : term->parameters ())
      std::cout << " " << v;
    for (const auto &setting : term->settings ())
      std::cout << " " << setting.first << "=" << setting.second;
    std::cout << "\n";
  }
  std::sort (added.begin (), added.end ());
  std::sort (effects.begin (), effects.end ());
  EXPECT_EQ (added, effects);
  EXPECT_LE (after.sd_rmse_mm, max_ratio * before.sd_rmse_mm);
  EXPECT_LE (after.bias_rmse_mm, max_ratio * before.bias_rmse_mm);
  // The model's own SD error, less what chance gives any model (sd_floor_mm), falls as far.
  auto own = [] (const pcl::texlet::lab::LabMetrics &m) {
    return std::sqrt (std::max (0.0, m.sd_rmse_mm * m.sd_rmse_mm - m.sd_floor_mm * m.sd_floor_mm));
  };
  std::cout << "  the model's own SD error: " << own (before) << " -> " << own (after) << "\n";
  EXPECT_LE (own (after), max_ratio * own (before));
}

/** \brief No candidate may be significant (nothing is hidden). */
inline void
expectNothingSignificantIn (const std::vector<pcl::texlet::lab::RecordingMeasurement::ConstPtr> &recordings)
{
  const LabRun run = runLabOn (recordings, "hidden effect: none", false);
  for (const auto &c : run.candidates)
    EXPECT_FALSE (c.significant) << c.effect << " gain " << c.gain << " threshold " << c.threshold << " effect size "
                                 << c.effect_size;
}

} // namespace pcl_texlet_test
