/*
 * The noise model: the paper's polynomial, composition of terms, copies, bad parameters.
 */
#include <pcl_texlet/noise/effect_adapter.h>
#include <pcl_texlet/noise/effects/axial_quadratic.h>
#include <pcl_texlet/noise/effects/spatial_correlation.h>
#include <pcl_texlet/noise/effects/temporal_drift.h>
#include <pcl_texlet/noise/noise_model.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>

using namespace pcl::texlet;

namespace
{
PixelContext
at (double r, double d)
{
  PixelContext c;
  c.radius_px = r;
  c.depth_mm = d;
  return c;
}

/** A constant extra SD with a constant bias: the shape of a later physical effect. */
class ConstantTerm : public NoiseTerm
{
public:
  explicit ConstantTerm (double sigma, double bias = 0) : s_ (sigma), b_ (bias) {}
  std::string name () const override { return "constant"; }
  double variance (const PixelContext &) const override { return s_ * s_; }
  double bias (const PixelContext &) const override { return b_; }
  std::vector<std::string> parameterNames () const override { return {"sigma", "bias"}; }
  std::vector<double> parameters () const override { return {s_, b_}; }
  void setParameters (const std::vector<double> &v) override { s_ = v.at (0); b_ = v.at (1); }
  NoiseTerm::Ptr clone () const override { return std::make_shared<ConstantTerm> (*this); }

private:
  double s_, b_;
};
} // namespace

TEST (NoiseModel, PaperPolynomialValues)
{
  const NoiseModel m = NoiseModel::paper ();
  EXPECT_NEAR (m.sigmaMm (at (0, 1000)), 0.843, 1e-12);
  EXPECT_NEAR (m.sigmaMm (at (100, 1500)), 0.97445, 1e-12);
  // 1750 mm, 300 px: 2.344 - 3.606 - 4.7845 + 1.6362 + 3.4209 + 3.7760625
  EXPECT_NEAR (m.sigmaMm (at (300, 1750)), 2.7866625, 1e-9);
  EXPECT_EQ (m.biasMm (at (0, 1000)), 0.0);
  ASSERT_EQ (m.terms ().size (), 1u);
  EXPECT_EQ (m.terms ()[0]->name (), "polynomial");
  EXPECT_EQ (m.terms ()[0]->parameters ()[0], 2.344);
}

TEST (NoiseModel, TermsAddInQuadratureAndBiasesAdd)
{
  NoiseModel m = NoiseModel::paper ();
  m.add (ConstantTerm (0.5, 0.25)).add (ConstantTerm (0.2, -0.05));
  const double base = 0.843;
  EXPECT_NEAR (m.sigmaMm (at (0, 1000)), std::sqrt (base * base + 0.25 + 0.04), 1e-12);
  EXPECT_NEAR (m.biasMm (at (0, 1000)), 0.2, 1e-15);
  ASSERT_NE (m.find ("constant"), nullptr);
  EXPECT_EQ (m.find ("incidence_angle"), nullptr);
}

TEST (NoiseModel, CopiesAreIndependent)
{
  NoiseModel a = NoiseModel::paper ();
  NoiseModel b = a;
  b.terms ()[0]->setParameters ({1, 0, 0, 0, 0, 0});
  EXPECT_NEAR (a.sigmaMm (at (0, 1000)), 0.843, 1e-12);
  EXPECT_NEAR (b.sigmaMm (at (0, 1000)), 1.0, 1e-12);
}

TEST (NoiseModel, FloorAndInvalidDepth)
{
  NoiseModel m;
  m.add (PolynomialSigmaTerm ({-1, 0, 0, 0, 0, 0})); // negative: contributes nothing
  EXPECT_EQ (m.sigmaMm (at (0, 1000)), 0.1);
  m.setMinSigmaMm (0.3);
  EXPECT_EQ (m.sigmaMm (at (0, 1000)), 0.3);
  EXPECT_TRUE (std::isnan (m.sigmaMm (at (0, 0))));
  EXPECT_TRUE (std::isnan (m.sigmaMm (at (0, -5))));
  EXPECT_THROW (m.setMinSigmaMm (0), pcl::BadArgumentException);
  EXPECT_THROW (m.setMinSigmaMm (-1), pcl::BadArgumentException);
  PolynomialSigmaTerm t;
  EXPECT_THROW (t.setParameters ({1, 2, 3}), pcl::BadArgumentException);
  EXPECT_THROW (t.setParameters ({1, 2, 3, 4, 5, std::nan ("")}), pcl::BadArgumentException);
}

TEST (NoiseModel, PolynomialOnlyFastPathGivesTheBitsOfSigmaMm)
{
  using pcl::texlet::kernels::PolynomialCoefficients;
  NoiseModel m = NoiseModel::paper ();
  m.setMinSigmaMm (0.5);
  PolynomialCoefficients c;
  ASSERT_TRUE (m.isPolynomialOnly (c));
  int compared = 0, floored = 0;
  // Inside and far outside the fitted range (the polynomial dips below the floor there).
  for (double r = 0.0; r <= 800.0; r += 7.3)
    for (double d : {-5.0, 0.0, 1.0, 350.0, 700.0, 1234.5, 1750.0, 4000.0, 9000.0, 30000.0, 1e6, HUGE_VAL,
                     std::nan ("")})
    {
      PixelContext ctx;
      ctx.radius_px = r;
      ctx.depth_mm = d;
      const double slow = m.sigmaMm (ctx), fast = pcl::texlet::kernels::polynomialSigmaMm (c, r, d, m.minSigmaMm ());
      if (std::isnan (slow))
      {
        EXPECT_TRUE (std::isnan (fast)) << "r " << r << " d " << d;
        continue;
      }
      std::uint64_t a, b;
      std::memcpy (&a, &slow, sizeof a);
      std::memcpy (&b, &fast, sizeof b);
      EXPECT_EQ (a, b) << "r " << r << " d " << d;
      floored += slow == 0.5 ? 1 : 0;
      ++compared;
    }
  EXPECT_GT (compared, 900);
  EXPECT_GT (floored, 0); // the floor was exercised

  // Any other term, or a subclass of the polynomial, takes the general path.
  NoiseModel two = NoiseModel::paper ();
  two.add (PolynomialSigmaTerm ());
  EXPECT_FALSE (two.isPolynomialOnly (c));
  EXPECT_FALSE (NoiseModel ().isPolynomialOnly (c));
  struct Scaled : PolynomialSigmaTerm
  {
    double variance (const PixelContext &ctx) const override { return 4.0 * PolynomialSigmaTerm::variance (ctx); }
    NoiseTerm::Ptr clone () const override { return std::make_shared<Scaled> (*this); }
  };
  NoiseModel sub;
  sub.add (Scaled ());
  EXPECT_FALSE (sub.isPolynomialOnly (c));
  EXPECT_FALSE (sub.depthSdIsPolynomial (c));
}

TEST (NoiseModel, DepthSdIsThePolynomialsWhereTheOtherTermsLeaveIt)
{
  // The polynomial with a window's share (spatial_correlation) or a drift (a bias only): the SD
  // is the polynomial's, bit for bit, so the per-pixel SD image may take the fast path; a term
  // with a variance (axial_quadratic) changes it.
  using pcl::texlet::EffectTermOf;
  namespace effects = pcl::texlet::effects;
  pcl::texlet::kernels::PolynomialCoefficients c;
  NoiseModel windowed = NoiseModel::paper ();
  windowed.add (EffectTermOf<effects::SpatialCorrelation> ({0.8, 9.0}));
  windowed.add (EffectTermOf<effects::TemporalDrift> ({0.2, 10.0, 0.0}));
  EXPECT_FALSE (windowed.isPolynomialOnly (c));
  ASSERT_TRUE (windowed.depthSdIsPolynomial (c));
  int compared = 0;
  for (double r = 0.0; r <= 800.0; r += 13.1)
    for (double d : {350.0, 700.0, 1234.5, 1750.0, 4000.0, 9000.0})
    {
      PixelContext ctx;
      ctx.radius_px = r;
      ctx.depth_mm = d;
      const double slow = windowed.sigmaMm (ctx);
      const double fast = pcl::texlet::kernels::polynomialSigmaMm (c, r, d, windowed.minSigmaMm ());
      std::uint64_t a, b;
      std::memcpy (&a, &slow, sizeof a);
      std::memcpy (&b, &fast, sizeof b);
      EXPECT_EQ (a, b) << "r " << r << " d " << d;
      ++compared;
    }
  EXPECT_GT (compared, 300);
  NoiseModel varied = windowed;
  varied.add (EffectTermOf<effects::AxialQuadratic> ({0.03}));
  EXPECT_FALSE (varied.depthSdIsPolynomial (c));
  EXPECT_FALSE (NoiseModel ().depthSdIsPolynomial (c));
}
