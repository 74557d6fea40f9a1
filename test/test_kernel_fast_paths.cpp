/*
 * The fast paths of the texlet kernels against the straightforward ones they replace: the
 * block-parallel normals against normalQuad (Random123's Box-Muller), the Jacobi re-fit against
 * the closed-form eigen solve, and the analytic covariances against the textbook loop. Results
 * must agree to floating-point rounding; the draws to a few float ulps. (The Monte Carlo PCA
 * covariances draw from a different, statistically equivalent sampler since issue 6: they are
 * compared with the per-point re-fit statistically, in test_pca_sampler.cpp.)
 */
#include <pcl_texlet/kernels/normal_blocks.h>
#include <pcl_texlet/kernels/texlet_kernel.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

using namespace pcl::texlet;
using namespace pcl::texlet::kernels;

namespace
{

int
ulpDistance (float a, float b)
{
  std::int32_t ia, ib;
  std::memcpy (&ia, &a, sizeof ia);
  std::memcpy (&ib, &b, sizeof ib);
  return std::abs (ia - ib);
}

/** A noisy round planar patch of a depth image seen at \a depth metres, with \a outliers
  * points pushed off the plane: points, depth SDs and ring as TexletWorker gathers them. */
struct Patch
{
  std::vector<double> x, y, z, sigma;
  Neighbourhood<double> nb;

  Patch (std::mt19937 &rng, double depth, int outliers)
  {
    std::normal_distribution<double> g (0, 1);
    const Eigen::Vector3d n = Eigen::Vector3d (0.3 * g (rng), 0.3 * g (rng), -1).normalized ();
    const double f = 525.0, cu = 40 * g (rng), cv = 40 * g (rng);
    for (int dv = -6; dv <= 6; ++dv)
      for (int du = -6; du <= 6; ++du)
      {
        if (du * du + dv * dv > 36)
          continue;
        // Ray through the pixel, cut with the plane n.p = n.(0, 0, depth).
        const Eigen::Vector3d ray ((cu + du) / f, (cv + dv) / f, 1.0);
        const double t = n.z () * depth / n.dot (ray);
        const double sd = 1.5e-3 * t * t;
        Eigen::Vector3d p = (t + sd * g (rng)) * ray;
        if (static_cast<int> (x.size ()) < outliers)
          p *= 1.05;
        x.push_back (p.x ()); y.push_back (p.y ()); z.push_back (p.z ());
        sigma.push_back (sd);
      }
    nb.x = x.data (); nb.y = y.data (); nb.z = z.data (); nb.sigma = sigma.data ();
    nb.count = static_cast<int> (x.size ());
    for (int k = 0; k < 7; ++k)
    {
      nb.ring[k] = nb.point (k * 16);
      nb.ring_sigma[k] = sigma[k * 16];
      nb.ring_valid[k] = true;
    }
  }
};

/** The analytic covariances as the plain per-inlier loop (the reference of the lane sums). */
void
referenceAnalytic (const Neighbourhood<double> &nb, const unsigned char *mask, const PlaneFit<double> &fit,
                   const Vec3<double> &t1, const Vec3<double> &t2, double cov_p[6], double cov_n[3])
{
  double n_in = 0;
  for (int k = 0; k < nb.count; ++k)
    n_in += mask[k] ? 1 : 0;
  const double d1 = n_in * (fit.lambda[1] - fit.lambda[0]), d2 = n_in * (fit.lambda[2] - fit.lambda[0]);
  for (int i = 0; i < 6; ++i)
    cov_p[i] = 0;
  for (int i = 0; i < 3; ++i)
    cov_n[i] = 0;
  for (int k = 0; k < nb.count; ++k)
  {
    if (!mask[k])
      continue;
    const Vec3<double> p = nb.point (k), r = (1.0 / p.z) * p, q = p - fit.P;
    const double var = nb.sigma[k] * nb.sigma[k];
    cov_p[0] += var * r.x * r.x; cov_p[1] += var * r.x * r.y; cov_p[2] += var * r.x * r.z;
    cov_p[3] += var * r.y * r.y; cov_p[4] += var * r.y * r.z; cov_p[5] += var * r.z * r.z;
    const double h = dot (q, fit.N), re0 = dot (r, fit.N);
    const double c1 = -(dot (fit.e1, r) * h + dot (fit.e1, q) * re0) / d1;
    const double c2 = -(dot (fit.e2, r) * h + dot (fit.e2, q) * re0) / d2;
    const double j1 = c1 * dot (fit.e1, t1) + c2 * dot (fit.e2, t1), j2 = c1 * dot (fit.e1, t2) + c2 * dot (fit.e2, t2);
    cov_n[0] += var * j1 * j1; cov_n[1] += var * j1 * j2; cov_n[2] += var * j2 * j2;
  }
  for (int i = 0; i < 6; ++i)
    cov_p[i] /= n_in * n_in;
}

double
relativeDifference (const double *a, const double *b, int n)
{
  double d = 0, s = 0;
  for (int i = 0; i < n; ++i)
  {
    d += (a[i] - b[i]) * (a[i] - b[i]);
    s += b[i] * b[i];
  }
  return std::sqrt (d / s);
}

} // namespace

TEST (NormalBlocks, PhiloxWordsAreBitForBitThoseOfRandom123)
{
  std::uint32_t w[4][40];
  for (std::uint32_t texlet : {0u, 1u, 307199u, 0xffffffffu})
    for (std::uint32_t counter : {0u, 49u, 12345u})
    {
      philoxBlocks (7u, texlet, counter, RandomStream::MonteCarlo, 3, 40, w[0], w[1], w[2], w[3]);
      for (int b = 0; b < 40; ++b)
      {
        const auto ref = philoxWords (7u, texlet, counter, 3u + b, RandomStream::MonteCarlo);
        for (int i = 0; i < 4; ++i)
          ASSERT_EQ (w[i][b], ref.v[i]) << "texlet " << texlet << " counter " << counter << " block " << b;
      }
    }
}

TEST (NormalBlocks, NormalsMatchBoxMullerToAFewUlps)
{
  std::uint32_t words[4 * 29];
  double g[4 * 29];
  int worst = 0, same = 0, total = 0;
  for (std::uint32_t texlet = 0; texlet < 3000; ++texlet)
    for (std::uint32_t sample = 0; sample < 5; ++sample)
    {
      normalBlocks (11u, texlet, sample, 0, 29, words, g);
      for (int b = 0; b < 29; ++b)
      {
        float ref[4];
        normalQuad (11u, texlet, sample, static_cast<std::uint32_t> (b), ref);
        for (int i = 0; i < 4; ++i)
        {
          const float mine = static_cast<float> (g[4 * b + i]);
          EXPECT_EQ (static_cast<double> (mine), g[4 * b + i]); // a float draw, widened
          // Tiny draws (|x| < 1e-3) come from angles near a multiple of pi/2, where the
          // float product pi x of Box-Muller is itself rounded: compare those absolutely.
          if (std::fabs (ref[i]) > 1e-3f)
            worst = std::max (worst, ulpDistance (mine, ref[i]));
          else
            EXPECT_NEAR (mine, ref[i], 1e-9);
          same += mine == ref[i];
          ++total;
        }
      }
    }
  EXPECT_LE (worst, 8);
  EXPECT_GT (same, total / 2); // most draws are the very same floats
}

TEST (SymEigen3Near, MatchesTheClosedFormFromANearbyBasis)
{
  std::mt19937 rng (3);
  std::normal_distribution<double> g (0, 1);
  for (int trial = 0; trial < 2000; ++trial)
  {
    // A patch covariance (l0 << l1 <= l2) and a perturbed copy, as in Monte Carlo re-fits.
    const Eigen::Matrix3d R = Eigen::Quaterniond::UnitRandom ().toRotationMatrix ();
    const Eigen::Vector3d l (1e-6 * std::exp (g (rng)), 3e-5 * std::exp (0.3 * g (rng)), 4e-5 * std::exp (0.3 * g (rng)));
    const Eigen::Matrix3d C = R * l.asDiagonal () * R.transpose ();
    Eigen::Matrix3d E = 2e-7 * Eigen::Matrix3d::NullaryExpr ([&] () { return g (rng); });
    const Eigen::Matrix3d Cp = C + E + E.transpose ();
    const double c[6] = {C (0, 0), C (0, 1), C (0, 2), C (1, 1), C (1, 2), C (2, 2)};
    const double cp[6] = {Cp (0, 0), Cp (0, 1), Cp (0, 2), Cp (1, 1), Cp (1, 2), Cp (2, 2)};
    SymEigen3<double> base, near, closed;
    ASSERT_TRUE (symmetricEigen3 (c, base));
    ASSERT_TRUE (symmetricEigen3Near (cp, base.vectors, near));
    ASSERT_TRUE (symmetricEigen3 (cp, closed));
    const Eigen::Vector3d a (near.vectors[0].x, near.vectors[0].y, near.vectors[0].z);
    const Eigen::Vector3d b (closed.vectors[0].x, closed.vectors[0].y, closed.vectors[0].z);
    EXPECT_LT (std::atan2 (a.cross (b).norm (), std::fabs (a.dot (b))), 1e-10) << "trial " << trial;
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR (near.values[i], closed.values[i], 1e-12 * l.maxCoeff ());
    // Orthonormal vectors.
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        EXPECT_NEAR (dot (near.vectors[i], near.vectors[j]), i == j ? 1.0 : 0.0, 1e-12);
  }
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  SymEigen3<double> e;
  const Vec3<double> basis[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_FALSE (symmetricEigen3Near (zero, basis, e));
}

TEST (AnalyticCovariance, LaneSumsMatchThePlainLoop)
{
  std::mt19937 rng (9);
  for (int trial = 0; trial < 60; ++trial)
  {
    Patch patch (rng, 0.6 + 0.05 * trial, trial % 4 == 0 ? 7 : 0);
    TexletSettings<double> st;
    st.threshold = 3 * 1.5e-3 * 4.0;
    st.uncertainty = UncertaintyMethod::Analytic;
    std::vector<unsigned char> mask (patch.nb.count);
    std::vector<double> work (texletWorkSize (patch.nb.count));
    TexletResult<double> r;
    computeTexlet (patch.nb, st, 77u + trial, mask.data (), work.data (), r);
    ASSERT_TRUE (r.ok);
    PlaneMoments<double> m;
    m.reset (patch.nb.point (0));
    for (int k = 0; k < patch.nb.count; ++k)
      if (mask[k])
        m.add (patch.nb.point (k));
    PlaneFit<double> fit;
    ASSERT_TRUE (fitPlanePca (m, fit));
    Vec3<double> t1, t2;
    tangentFrame (r.N, t1, t2);
    double ref_p[6], ref_n[3];
    referenceAnalytic (patch.nb, mask.data (), fit, t1, t2, ref_p, ref_n);
    EXPECT_LT (relativeDifference (r.cov_p, ref_p, 6), 1e-12) << "trial " << trial;
    EXPECT_LT (relativeDifference (r.cov_n, ref_n, 3), 1e-12) << "trial " << trial;
  }
}
