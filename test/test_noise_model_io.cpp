/*
 * The effect terms of the noise model and its YAML files: closed-form values, round trips,
 * and clear errors for bad files.
 */
#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/noise/effect_adapter.h>
#include <pcl_texlet/noise/effects/axial_quadratic.h>
#include <pcl_texlet/noise/effects/depth_distortion.h>
#include <pcl_texlet/noise/effects/disparity_quantization.h>
#include <pcl_texlet/noise/effects/incidence_angle.h>
#include <pcl_texlet/noise/effects/interference.h>
#include <pcl_texlet/noise/effects/lateral_noise.h>
#include <pcl_texlet/noise/effects/radial.h>
#include <pcl_texlet/noise/effects/temporal_drift.h>
#include <pcl_texlet/noise/effects/vertical_stripes.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

using namespace pcl::texlet;
using Quantisation = pcl::texlet::effects::DisparityQuantization;

namespace
{
PixelContext
at (double u, double v, double depth_mm)
{
  PixelContext c;
  c.u = u;
  c.v = v;
  c.radius_px = std::hypot (u - 319.5, v - 239.5);
  c.depth_mm = depth_mm;
  return c;
}

NoiseModel
everyTerm ()
{
  NoiseModel m = NoiseModel::paper ();
  m.add (EffectTermOf<effects::AxialQuadratic> ({0.03}));
  m.add (EffectTermOf<effects::Radial> ({0.4}));
  m.add (EffectTermOf<effects::IncidenceAngle> ({0.5}));
  m.add (EffectTermOf<effects::VerticalStripes> ({0.1, 5.0}));
  EffectTermOf<effects::DepthDistortion> grid ({}, {640, 480, 5, 4});
  std::vector<double> offsets;
  for (int k = 0; k < 20; ++k)
    offsets.push_back (0.01 * k - 0.1);
  grid.setParameters (offsets);
  m.add (grid);
  m.add (EffectTermOf<effects::Interference> ({0.8}));
  m.add (EffectTermOf<effects::TemporalDrift> ({0.2, 8.0, 0.001}));
  m.add (EffectTermOf<effects::LateralNoise> ({2.0, 1.5}));
  m.add (EffectTermOf<effects::DisparityQuantization> ({0.125}));
  return m;
}
} // namespace

TEST (EffectTerms, QuantisedMomentsMatchClosedForms)
{
  double mean = 0, var = 0;
  // No noise: the nearest level; half-way between two levels with tiny noise: half each.
  Quantisation::moments (10.0 + 0.3 * 0.125, 0.0, 0.125, mean, var);
  EXPECT_NEAR (mean, -0.3 * 0.125, 1e-12);
  EXPECT_EQ (var, 0.0);
  Quantisation::moments (10.0625, 1e-4, 0.125, mean, var);
  EXPECT_NEAR (var, 0.0625 * 0.0625, 1e-6);
  // Much noise: Sheppard's correction, sigma^2 + step^2 / 12, no bias.
  Quantisation::moments (10.01, 0.5, 0.125, mean, var);
  EXPECT_NEAR (var, 0.25 + 0.125 * 0.125 / 12, 1e-6);
  EXPECT_NEAR (mean, 0.0, 1e-6);
}

// The two ways of computing the moments: the levels' probabilities summed (exact by definition,
// one erf per level) and the rounding error's Fourier series (three harmonics, used from half a
// step of noise on), over the whole sub-step phase and from a quarter of a step to 12 steps of noise.
// The frame-to-frame variance averaged over the phases (a measured depth's, a texlet's points'):
// against the rounded moments' variance averaged over 4000 phases, on both sides of the switch
// between the Poisson-summed form and the sum (a = 0.05: sigma = 0.0356 steps), and its limits:
// sqrt(1 / pi) step sigma far below a step, Sheppard's sigma^2 + step^2 / 12 above one.
TEST (EffectTerms, QuantisedVarianceOverPhasesIsThePhaseAverage)
{
  const double step = 0.125;
  for (const double sigma_steps : {0.002, 0.01, 0.035, 0.0356, 0.036, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0})
  {
    const double sigma = sigma_steps * step;
    double sum = 0;
    const int phases = 4000;
    for (int i = 0; i < phases; ++i)
    {
      double m = 0, v = 0;
      Quantisation::moments (37.0 + step * ((i + 0.5) / phases - 0.5), sigma, step, m, v);
      sum += v;
    }
    const double average = sum / phases, closed = Quantisation::varianceOverPhases (sigma, step);
    EXPECT_NEAR (closed, average, 2e-4 * average) << sigma_steps << " steps";
    if (sigma_steps <= 0.01)
      EXPECT_NEAR (closed, step * sigma / std::sqrt (M_PI), 0.02 * closed);
    if (sigma_steps >= 1.0)
      EXPECT_NEAR (closed, sigma * sigma + step * step / 12.0, 1e-12);
  }
  const double at_switch = std::sqrt (0.05) / (2 * M_PI) * step; // 4 pi^2 sigma^2 / step^2 = 0.05
  const double below = Quantisation::varianceOverPhases (at_switch * (1 - 1e-12), step);
  EXPECT_NEAR (below, Quantisation::varianceOverPhases (at_switch * (1 + 1e-12), step), 1e-10 * below);
}

TEST (EffectTerms, QuantisedMomentsByHarmonicsEqualTheLevelsSummed)
{
  const double step = 0.125;
  double worst_mean = 0, worst_var = 0;
  for (const double sigma_steps : {0.3, 0.45, 0.5, 0.55, 0.8, 1.0, 1.7, 3.0, 6.0, 12.0})
    for (int i = 0; i <= 40; ++i)
    {
      const double d0 = 37.0 + step * (i / 40.0 - 0.5), sigma = sigma_steps * step;
      double m_levels = 0, v_levels = 0, m_harmonics = 0, v_harmonics = 0;
      Quantisation::momentsByLevels (d0, sigma, step, m_levels, v_levels);
      Quantisation::momentsByHarmonics (d0, sigma, step, m_harmonics, v_harmonics);
      worst_mean = std::max (worst_mean, std::fabs (m_levels - m_harmonics) / step);
      worst_var = std::max (worst_var, std::fabs (v_levels - v_harmonics) / (sigma * sigma));
    }
  // The levels' sum stops at 7 SDs: the 2.6e-12 of the probability beyond, at up to 7 SDs, is
  // about 1e-10 of the variance (the harmonics are exact to 1e-19 from half a step on).
  EXPECT_LT (worst_mean, 1e-10);
  EXPECT_LT (worst_var, 3e-10);

  // At half a step the bias still swings with the phase (by about 0.7 % of a step) and the SD with
  // it; the dispatcher's switch between the two ways is continuous.
  double m_below = 0, v_below = 0, m_at = 0, v_at = 0;
  Quantisation::moments (37.03, 0.5 * step * (1 - 1e-12), step, m_below, v_below);
  Quantisation::moments (37.03, 0.5 * step, step, m_at, v_at);
  EXPECT_NEAR (m_below, m_at, 1e-12);
  EXPECT_NEAR (v_below, v_at, 1e-12);
  EXPECT_GT (std::fabs (m_at), 1e-4 * step);

  // A disparity that is not finite, or beyond what a double can tell levels apart at, has no
  // moments: NaN, and no endless sum.
  for (const double d0 : {double (INFINITY), -double (INFINITY), double (NAN), 1e300})
  {
    double m = 0, v = 0;
    Quantisation::moments (d0, 0.01, step, m, v);
    EXPECT_TRUE (std::isnan (m) && std::isnan (v)) << d0;
  }
  double m = 0, v = 0;
  Quantisation::moments (37.0, INFINITY, step, m, v);
  EXPECT_EQ (v, INFINITY);
}

TEST (EffectTerms, MomentsComposeAsTheSimulatorDraws)
{
  // (polynomial^2 + axial^2) x radial x incidence x interference, stripes outside the factors.
  NoiseModel m = NoiseModel::paper ();
  m.add (EffectTermOf<effects::AxialQuadratic> ({0.03}))
      .add (EffectTermOf<effects::Radial> ({0.4}))
      .add (EffectTermOf<effects::IncidenceAngle> ({0.5}));
  m.add (EffectTermOf<effects::Interference> ({0.8})).add (EffectTermOf<effects::VerticalStripes> ({0.1, 4.0}));
  PixelContext c = at (500, 400, 2000);
  c.cos_incidence = 0.5;
  c.active_projectors = 3;
  const double J = 2000.0 * 2000.0 / (1000.0 * c.fb_px_m);
  const double poly = NoiseModel::paper ().sigmaMm (c);
  const double factor = std::pow (1 + 0.4 * std::pow (c.radius_px / 400, 2), 2) * std::pow (1 + 0.5 * (2 - 1), 2) *
                        (1 + 0.8 * 2);
  const NoiseMoments mo = m.moments (c);
  EXPECT_NEAR (mo.variance_mm2, (poly * poly + 0.03 * 0.03 * J * J) * factor, 1e-9);
  EXPECT_NEAR (mo.column_variance_mm2, 0.01 * J * J, 1e-9);
  EXPECT_NEAR (mo.frame_variance_mm2, 0.01 * J * J / 4, 1e-9);
  EXPECT_NEAR (mo.sigma_mm, std::sqrt (mo.variance_mm2 + mo.column_variance_mm2), 1e-12);
  // Without the image's width the stripes' bands have no length in columns: all columns share.
  EXPECT_EQ (mo.column_correlation_px, INFINITY);
  // 4 bands: 3 cuts at random columns; columns du apart share a band with probability about
  // exp(-3 du / width).
  c.image_width_px = 640;
  EXPECT_NEAR (m.moments (c).column_correlation_px, 640.0 / 3, 1e-9);
  EXPECT_EQ (NoiseModel::paper ().moments (c).column_correlation_px, INFINITY);
}

TEST (EffectTerms, DriftAndDistortionAreBiases)
{
  PixelContext c = at (100, 100, 1500);
  const double J = 1500.0 * 1500.0 / (1000.0 * c.fb_px_m);
  NoiseModel m;
  m.add (EffectTermOf<effects::TemporalDrift> ({0.2, 10.0, 0.0}));
  EXPECT_EQ (m.biasMm (c), 0.0); // steady state when the frame is unknown
  c.frame = 10;
  EXPECT_NEAR (m.biasMm (c), -J * 0.2 * std::exp (-1.0), 1e-9);
  // The scale form (a focal change): depth grows by scale z exp(-frame / tau), with the offset's.
  NoiseModel scaled;
  scaled.add (EffectTermOf<effects::TemporalDrift> ({0.2, 10.0, 0.003}));
  EXPECT_NEAR (scaled.biasMm (c), -J * 0.2 * std::exp (-1.0) + 1500.0 * 0.003 * std::exp (-1.0), 1e-9);
  EffectTermOf<effects::DepthDistortion> grid ({}, {640, 480, 2, 2});
  grid.setParameters ({0.1, 0.1, 0.1, 0.1});
  EXPECT_NEAR (grid.bias (c), -J * 0.1, 1e-9);
}

TEST (EffectTerms, EveryVocabularyNameMakesANeutralTerm)
{
  const PixelContext c = at (300, 200, 1200);
  const double base = NoiseModel::paper ().sigmaMm (c);
  for (const auto &name : noiseEffectNames ())
  {
    NoiseModel m = NoiseModel::paper ();
    m.add (*makeNoiseTerm (name));
    EXPECT_NEAR (m.sigmaMm (c), base, 1e-12) << name;
    EXPECT_NEAR (m.biasMm (c), 0.0, 1e-12) << name;
  }
  EXPECT_THROW (makeNoiseTerm ("wobble"), pcl::BadArgumentException);
}

TEST (EffectTerms, TheLabReadsPropertiesNotNames)
{
  for (const auto &name : noiseEffectNames ())
  {
    const NoiseTerm::Ptr t = makeNoiseTerm (name);
    EXPECT_EQ (t->quantises (), name == "disparity_quantization") << name;
    EXPECT_EQ (t->linearBiasSupport () > 0, name == "depth_distortion") << name;
    EXPECT_EQ (t->frameDependent (), name == "temporal_drift") << name;
    EXPECT_EQ (effectInfo (name).quantises, t->quantises ()) << name;
  }
  EXPECT_EQ (effectInfo ("depth_distortion").lab_needs, unsigned (effects::kNeedsPlaneScene));
  EXPECT_EQ (effectInfo ("interference").lab_needs, unsigned (effects::kNeedsVariedProjectors | effects::kNeedsRepeatedFrames));
  EXPECT_EQ (effectInfo ("vertical_stripes").lab_needs, unsigned (effects::kNeedsFrameSplit | effects::kNeedsRepeatedFrames));
  EXPECT_EQ (effectInfo ("lateral_noise").lab_needs, unsigned (effects::kNeedsDepthEdges | effects::kNeedsRepeatedFrames));

  // The grid's bias basis reproduces its bias: bias = -J sum_k w_k offset_k.
  EffectTermOf<effects::DepthDistortion> grid ({}, {640, 480, 3, 3});
  std::vector<double> nodes;
  for (int k = 0; k < 9; ++k)
    nodes.push_back (0.01 * k - 0.03);
  grid.setParameters (nodes);
  const PixelContext c = at (200.5, 333.25, 1500);
  ASSERT_EQ (grid.linearBiasSupport (), 4);
  int index[4];
  double weight[4];
  grid.linearBiasBasis (c.u, c.v, index, weight);
  double offset = 0;
  for (int k = 0; k < 4; ++k)
    offset += weight[k] * nodes[index[k]];
  EXPECT_NEAR (grid.bias (c), -1500.0 * 1500.0 / (1000.0 * c.fb_px_m) * offset, 1e-12);

  // The lab's start values: the recording's step (the sensor's nominal one when unknown), a grid
  // spanning the recording's image, the typical scale of a parameter.
  effects::LabStart facts;
  facts.image_width = 320;
  facts.image_height = 240;
  facts.disparity_step_px = 0.25;
  const NoiseTerm::Ptr q = makeNoiseTerm ("disparity_quantization");
  q->setLabStart (facts);
  EXPECT_EQ (q->parameters (), std::vector<double> ({0.25}));
  facts.disparity_step_px = 0;
  q->setLabStart (facts);
  EXPECT_EQ (q->parameters (), std::vector<double> ({0.125}));
  EXPECT_EQ (q->settings ()[0], (std::pair<std::string, double> ("lattice_phase", 0.0)));
  // ... or the lattice the depths sit on, with its phase: its levels at (k + phase) step.
  facts.lattice_step_px = 0.11;
  facts.lattice_phase = 0.3;
  q->setLabStart (facts);
  EXPECT_EQ (q->parameters (), std::vector<double> ({0.11}));
  EXPECT_EQ (q->settings ()[0], (std::pair<std::string, double> ("lattice_phase", 0.3)));
  double offset_on_lattice = 0, offset_on_zero = 0, var = 0;
  q->roundingMoments ((40 + 0.3) * 0.11 + 0.01, 1e-9, offset_on_lattice, var);
  EXPECT_NEAR (offset_on_lattice, -0.01, 1e-12);
  const NoiseTerm::Ptr q0 = makeNoiseTerm ("disparity_quantization");
  q0->setParameters ({0.125});
  q0->roundingMoments (40 * 0.125 + 0.01, 1e-9, offset_on_zero, var);
  EXPECT_NEAR (offset_on_zero, -0.01, 1e-12);
  // Rounded on two lattices (rounds_before_noise 2): the true disparity on the first lattice
  // (camera.yaml's step, from the facts), the noisy one on the term's. Without noise, 5.03 px goes
  // to 5.0 on the 1/8 px lattice, then to 45 steps of 0.11 px (phase 0) = 4.95; with much noise the
  // second rounding's staircase is gone (Sheppard: variance sigma^2 + step^2 / 12) and the first
  // one's offset stays.
  const NoiseTerm::Ptr q2 = makeNoiseTerm ("disparity_quantization");
  facts.disparity_step_px = 0.125;
  facts.lattice_step_px = 0.11;
  facts.lattice_phase = 0;
  q2->setLabStart (facts);
  q2->setSetting ("rounds_before_noise", 2);
  q2->roundingMoments (5.03, 1e-9, offset_on_lattice, var);
  EXPECT_NEAR (offset_on_lattice, 4.95 - 5.03, 1e-12);
  EXPECT_NEAR (var, 0.0, 1e-12);
  q2->roundingMoments (5.03, 0.2, offset_on_lattice, var);
  EXPECT_NEAR (offset_on_lattice, 5.0 - 5.03, 1e-9);
  EXPECT_NEAR (var, 0.2 * 0.2 + 0.11 * 0.11 / 12.0, 1e-9);
  // Two lattices where the noise is a third of the second's step: each level's probability by
  // hand (5.0 + noise rounded to multiples of 0.11 px).
  q2->roundingMoments (5.03, 0.04, offset_on_lattice, var);
  double p_sum = 0, m1 = 0, m2 = 0;
  for (int k = 40; k <= 50; ++k)
  {
    const double lo = ((k - 0.5) * 0.11 - 5.0) / (0.04 * std::sqrt (2.0)), hi = ((k + 0.5) * 0.11 - 5.0) / (0.04 * std::sqrt (2.0));
    const double pk = 0.5 * (std::erf (hi) - std::erf (lo));
    p_sum += pk, m1 += pk * k * 0.11, m2 += pk * k * 0.11 * k * 0.11;
  }
  EXPECT_NEAR (offset_on_lattice, m1 / p_sum - 5.03, 1e-9);
  EXPECT_NEAR (var, m2 / p_sum - (m1 / p_sum) * (m1 / p_sum), 1e-9);
  facts.disparity_step_px = 0;
  facts.lattice_step_px = 0;
  facts.lattice_phase = 0;
  const NoiseTerm::Ptr g = makeNoiseTerm ("depth_distortion");
  g->setLabStart (facts);
  EXPECT_EQ (g->settings ()[0], (std::pair<std::string, double> ("image_width", 320)));
  EXPECT_EQ (g->settings ()[1], (std::pair<std::string, double> ("image_height", 240)));
  EXPECT_EQ (g->parameters (), std::vector<double> (17 * 13, 0.0));
  // The map's shape along depth: 1 at 1.5 m; a depth scale map grows as 1500 / z; Herrera's decay
  // exp(-alpha1 (d - d(1.5 m))), d in px at 640 px width.
  EXPECT_EQ (g->linearBiasShape (3000, 43.5), 1.0);
  g->setSetting ("depth_power", 1);
  EXPECT_NEAR (g->linearBiasShape (3000, 43.5), 0.5, 1e-12);
  g->setSetting ("depth_power", 0);
  g->setSetting ("decay_per_px", 0.02);
  EXPECT_NEAR (g->linearBiasShape (1500, 21.75), 1.0, 1e-12);
  EXPECT_NEAR (g->linearBiasShape (750, 21.75), std::exp (-0.02 * (29.0 - 14.5) * 2.0), 1e-12);
  EXPECT_THROW (g->setSetting ("depth_power", 2), pcl::BadArgumentException);
  g->setSetting ("decay_per_px", 0.0);
  EXPECT_FALSE (g->linearBiasShapeSearch ().empty ());
  EXPECT_TRUE (makeNoiseTerm ("radial")->linearBiasShapeSearch ().empty ());
  const NoiseTerm::Ptr a = makeNoiseTerm ("axial_quadratic");
  a->setLabStart (facts);
  EXPECT_EQ (a->parameters (), std::vector<double> ({0.02}));
  EXPECT_EQ (a->typicalScale (0), 0.02);
  EXPECT_EQ (NoiseModel::paper ().terms ().front ()->typicalScale (3), 1e-12);

  // Settings are checked one by one and as a whole; a refused one changes nothing.
  EXPECT_THROW (g->setSetting ("nodes_x", 1), pcl::BadArgumentException);
  EXPECT_THROW (g->setSetting ("nodes_x", 2.5), pcl::BadArgumentException);
  EXPECT_THROW (g->setSetting ("colour", 2), pcl::BadArgumentException);
  EXPECT_EQ (g->settings ()[2], (std::pair<std::string, double> ("nodes_x", 17)));
  EXPECT_THROW (makeNoiseTerm ("radial")->setSetting ("reference_radius_px", 0), pcl::BadArgumentException);
}

// A count of bands below 1 means one band: the terms read it so, a model may not hold it, and
// the lab's fit stops there (its likelihood is flat below).
TEST (EffectTerms, CountsOfBandsHaveALeastValue)
{
  for (const std::string name : {"vertical_stripes", "rows"})
  {
    const NoiseTerm::Ptr t = makeNoiseTerm (name);
    EXPECT_EQ (t->lowestValue (1), 1.0) << name;
    EXPECT_EQ (t->lowestValue (0), -std::numeric_limits<double>::infinity ()) << name;
    EXPECT_THROW (t->setParameters ({0.1, 0.5}), pcl::BadArgumentException) << name;
    EXPECT_NO_THROW (t->setParameters ({-0.1, 1.0})) << name;
  }
  EXPECT_EQ (makeNoiseTerm ("radial")->lowestValue (0), -std::numeric_limits<double>::infinity ());
}

TEST (NoiseModelYaml, RoundTripKeepsEveryTermAndValue)
{
  const NoiseModel m = everyTerm ();
  const NoiseModel back = parseNoiseModelYaml (noiseModelToYaml (m));
  ASSERT_EQ (back.terms ().size (), m.terms ().size ());
  for (std::size_t k = 0; k < m.terms ().size (); ++k)
  {
    EXPECT_EQ (back.terms ()[k]->name (), m.terms ()[k]->name ());
    EXPECT_EQ (back.terms ()[k]->parameters (), m.terms ()[k]->parameters ());
    EXPECT_EQ (back.terms ()[k]->settings (), m.terms ()[k]->settings ());
  }
  PixelContext c = at (123, 77, 1800);
  c.cos_incidence = 0.7;
  c.active_projectors = 2;
  c.frame = 3;
  c.edge_distance_px = 1.0;
  c.true_depth_mm = 1800.4;
  EXPECT_EQ (back.sigmaMm (c), m.sigmaMm (c));
  EXPECT_EQ (back.biasMm (c), m.biasMm (c));

  const pcl_texlet_test::TempDir temp;
  const std::string path = temp.file ("noise_model_roundtrip.yaml");
  saveNoiseModelYaml (path, m);
  EXPECT_EQ (loadNoiseModelYaml (path).sigmaMm (c), m.sigmaMm (c));
  EXPECT_EQ (temp.entries (), std::vector<std::string> ({"noise_model_roundtrip.yaml"})) << "no temporary is left";
}

TEST (NoiseModelYaml, BadFilesNameTheProblem)
{
  auto message = [] (const std::string &yaml) {
    try
    {
      parseNoiseModelYaml (yaml, "test.yaml");
    }
    catch (const pcl::IOException &e)
    {
      return std::string (e.what ());
    }
    return std::string ("no error");
  };
  EXPECT_NE (message ("terms: [").find ("test.yaml: not valid YAML"), std::string::npos);
  EXPECT_NE (message ("terms: []").find ("non-empty list"), std::string::npos);
  EXPECT_NE (message ("terms:\n  - name: wobble\n    parameters: {}").find ("unknown noise term 'wobble'"),
             std::string::npos);
  EXPECT_NE (message ("terms:\n  - name: radial\n    parameters: {}").find ("parameter 'gain' is missing"),
             std::string::npos);
  EXPECT_NE (message ("terms:\n  - name: radial\n    parameters: {gain: .nan}").find ("not finite"), std::string::npos);
  EXPECT_NE (message ("terms:\n  - name: vertical_stripes\n    parameters: {offset_px: 0.1, bands: 0.5}")
                 .find ("parameter bands is 0.5, below its least value 1"),
             std::string::npos);
  EXPECT_NE (message ("terms:\n  - name: radial\n    parameters: {gain: 1, power: 2}").find ("unknown parameter 'power'"),
             std::string::npos);
  EXPECT_NE (message ("terms:\n  - name: radial\n    settings: {colour: 2}\n    parameters: {gain: 1}")
                 .find ("unknown setting 'colour'"),
             std::string::npos);
  EXPECT_NE (message ("min_sigma_mm: -1\nterms:\n  - name: radial\n    parameters: {gain: 1}").find ("positive"),
             std::string::npos);
  EXPECT_THROW (loadNoiseModelYaml ("/no/such/model.yaml"), pcl::IOException);
}
