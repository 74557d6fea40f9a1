/*
 * The effect terms of the noise model and its YAML files: closed-form values, round trips,
 * and clear errors for bad files.
 */
#include <pcl_texlet/kernels/effect_terms.h>
#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

using namespace pcl::texlet;

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
  m.add (AxialQuadraticTerm (0.03));
  m.add (RadialTerm (0.4));
  m.add (IncidenceAngleTerm (0.5));
  m.add (VerticalStripesTerm (0.1, 5.0));
  DepthDistortionTerm grid (640, 480, 5, 4);
  std::vector<double> offsets;
  for (int k = 0; k < 20; ++k)
    offsets.push_back (0.01 * k - 0.1);
  grid.setParameters (offsets);
  m.add (grid);
  m.add (InterferenceTerm (0.8));
  m.add (TemporalDriftTerm (0.2, 8.0));
  m.add (LateralNoiseTerm (2.0, 1.5));
  m.add (DisparityQuantizationTerm (0.125));
  return m;
}
} // namespace

TEST (EffectTerms, QuantisedMomentsMatchClosedForms)
{
  double mean = 0, var = 0;
  // No noise: the nearest level; half-way between two levels with tiny noise: half each.
  pcl::texlet::kernels::quantizedMoments (10.0 + 0.3 * 0.125, 0.0, 0.125, mean, var);
  EXPECT_NEAR (mean, -0.3 * 0.125, 1e-12);
  EXPECT_EQ (var, 0.0);
  pcl::texlet::kernels::quantizedMoments (10.0625, 1e-4, 0.125, mean, var);
  EXPECT_NEAR (var, 0.0625 * 0.0625, 1e-6);
  // Much noise: Sheppard's correction, sigma^2 + step^2 / 12, no bias.
  pcl::texlet::kernels::quantizedMoments (10.01, 0.5, 0.125, mean, var);
  EXPECT_NEAR (var, 0.25 + 0.125 * 0.125 / 12, 1e-6);
  EXPECT_NEAR (mean, 0.0, 1e-6);
}

// The two ways of computing the moments: the levels' probabilities summed (exact by definition,
// one erf per level) and the rounding error's Fourier series (three harmonics, used from half a
// step of noise on), over the whole sub-step phase and from a quarter of a step to 12 steps of noise.
TEST (EffectTerms, QuantisedMomentsByHarmonicsEqualTheLevelsSummed)
{
  const double step = 0.125;
  double worst_mean = 0, worst_var = 0;
  for (const double sigma_steps : {0.3, 0.45, 0.5, 0.55, 0.8, 1.0, 1.7, 3.0, 6.0, 12.0})
    for (int i = 0; i <= 40; ++i)
    {
      const double d0 = 37.0 + step * (i / 40.0 - 0.5), sigma = sigma_steps * step;
      double m_levels = 0, v_levels = 0, m_harmonics = 0, v_harmonics = 0;
      pcl::texlet::kernels::quantizedMomentsByLevels (d0, sigma, step, m_levels, v_levels);
      pcl::texlet::kernels::quantizedMomentsByHarmonics (d0, sigma, step, m_harmonics, v_harmonics);
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
  pcl::texlet::kernels::quantizedMoments (37.03, 0.5 * step * (1 - 1e-12), step, m_below, v_below);
  pcl::texlet::kernels::quantizedMoments (37.03, 0.5 * step, step, m_at, v_at);
  EXPECT_NEAR (m_below, m_at, 1e-12);
  EXPECT_NEAR (v_below, v_at, 1e-12);
  EXPECT_GT (std::fabs (m_at), 1e-4 * step);

  // A disparity that is not finite, or beyond what a double can tell levels apart at, has no
  // moments: NaN, and no endless sum.
  for (const double d0 : {double (INFINITY), -double (INFINITY), double (NAN), 1e300})
  {
    double m = 0, v = 0;
    pcl::texlet::kernels::quantizedMoments (d0, 0.01, step, m, v);
    EXPECT_TRUE (std::isnan (m) && std::isnan (v)) << d0;
  }
  double m = 0, v = 0;
  pcl::texlet::kernels::quantizedMoments (37.0, INFINITY, step, m, v);
  EXPECT_EQ (v, INFINITY);
}

TEST (EffectTerms, MomentsComposeAsTheSimulatorDraws)
{
  // (polynomial^2 + axial^2) x radial x incidence x interference, stripes outside the factors.
  NoiseModel m = NoiseModel::paper ();
  m.add (AxialQuadraticTerm (0.03)).add (RadialTerm (0.4)).add (IncidenceAngleTerm (0.5));
  m.add (InterferenceTerm (0.8)).add (VerticalStripesTerm (0.1, 4.0));
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
}

TEST (EffectTerms, DriftAndDistortionAreBiases)
{
  PixelContext c = at (100, 100, 1500);
  const double J = 1500.0 * 1500.0 / (1000.0 * c.fb_px_m);
  NoiseModel m;
  m.add (TemporalDriftTerm (0.2, 10.0));
  EXPECT_EQ (m.biasMm (c), 0.0); // steady state when the frame is unknown
  c.frame = 10;
  EXPECT_NEAR (m.biasMm (c), -J * 0.2 * std::exp (-1.0), 1e-9);
  DepthDistortionTerm grid (640, 480, 2, 2);
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

TEST (NoiseModelYaml, RoundTripKeepsEveryTermAndValue)
{
  const NoiseModel m = everyTerm ();
  const NoiseModel back = parseNoiseModelYaml (noiseModelToYaml (m));
  ASSERT_EQ (back.terms ().size (), m.terms ().size ());
  for (std::size_t k = 0; k < m.terms ().size (); ++k)
  {
    EXPECT_EQ (back.terms ()[k]->name (), m.terms ()[k]->name ());
    EXPECT_EQ (back.terms ()[k]->parameters (), m.terms ()[k]->parameters ());
  }
  PixelContext c = at (123, 77, 1800);
  c.cos_incidence = 0.7;
  c.active_projectors = 2;
  c.frame = 3;
  c.edge_distance_px = 1.0;
  c.true_depth_mm = 1800.4;
  EXPECT_EQ (back.sigmaMm (c), m.sigmaMm (c));
  EXPECT_EQ (back.biasMm (c), m.biasMm (c));

  const std::string path = testing::TempDir () + "/noise_model_roundtrip.yaml";
  saveNoiseModelYaml (path, m);
  EXPECT_EQ (loadNoiseModelYaml (path).sigmaMm (c), m.sigmaMm (c));
  std::remove (path.c_str ());
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
  EXPECT_NE (message ("terms:\n  - name: radial\n    parameters: {gain: 1, power: 2}").find ("unknown parameter 'power'"),
             std::string::npos);
  EXPECT_NE (message ("terms:\n  - name: radial\n    settings: {colour: 2}\n    parameters: {gain: 1}")
                 .find ("unknown setting 'colour'"),
             std::string::npos);
  EXPECT_NE (message ("min_sigma_mm: -1\nterms:\n  - name: radial\n    parameters: {gain: 1}").find ("positive"),
             std::string::npos);
  EXPECT_THROW (loadNoiseModelYaml ("/no/such/model.yaml"), pcl::IOException);
}
