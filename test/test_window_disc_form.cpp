/*
 * The window's form on a whole disc from tables made once (kernels/window_disc_form.h) against
 * the windows' sums (windowForm(), the definition): equal where the values are quadratics of
 * the pixel offset (the tables' basis), and close for the propagations' real values on tilted
 * planes and spheres, analytic and the moment sampler's linear part.
 */
#include <pcl_texlet/kernels/pca_sampler.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/ray_cast.h>
#include <pcl_texlet/kernels/texlet_kernel.h>
#include <pcl_texlet/kernels/window_disc_form.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

using namespace pcl::texlet;
using namespace pcl::texlet::kernels;

namespace
{

/** A whole disc of radius \a r px in disc order (pixelDiscOffsets()) on a plane, or with
  * \a curvature > 0 a sphere, through depth \a depth on the ray of pixel (cu, cv) from the
  * principal point (f = 525), its normal \a tilt_deg from the centre ray, towards \a azimuth;
  * depth SD 1.5e-3 z^2 m (the paper's order), readings noisy. */
struct WholeDisc
{
  std::vector<int> du, dv, pixel;
  std::vector<double> x, y, z, sigma;
  Neighbourhood<double> nb;

  WholeDisc (std::mt19937 &rng, int r, double depth, double tilt_deg, double azimuth, double curvature, double cu,
             double cv)
  {
    const int n = pixelDiscSize (r);
    du.resize (n);
    dv.resize (n);
    pixelDiscOffsets (r, du.data (), dv.data (), n);
    std::normal_distribution<double> g (0, 1);
    const double t = tilt_deg * M_PI / 180.0, f = 525.0;
    const Eigen::Vector3d touch = depth * Eigen::Vector3d (cu / f, cv / f, 1.0);
    // Tilted by tilt_deg from facing the centre ray.
    const Eigen::Vector3d back = -touch.normalized (), a = back.unitOrthogonal (), b = back.cross (a);
    const Eigen::Vector3d normal =
        std::cos (t) * back + std::sin (t) * (std::cos (azimuth) * a + std::sin (azimuth) * b);
    const Vec3<double> origin = {0.0, 0.0, 0.0}, n3 = {normal.x (), normal.y (), normal.z ()};
    const Eigen::Vector3d centre = touch - normal / (curvature > 0 ? curvature : 1.0);
    for (int o = 0; o < n; ++o)
    {
      const Eigen::Vector3d ray ((cu + du[o]) / f, (cv + dv[o]) / f, 1.0);
      const Vec3<double> r3 = {ray.x (), ray.y (), ray.z ()};
      double s = 0;
      const bool hit = curvature > 0 ? raySphere (origin, r3, {centre.x (), centre.y (), centre.z ()}, 1.0 / curvature, s)
                                     : rayPlane (origin, r3, n3, normal.dot (touch), s);
      EXPECT_TRUE (hit);
      const double sd = 1.5e-3 * s * s;
      const Eigen::Vector3d p = (s + sd * g (rng)) * ray;
      x.push_back (p.x ());
      y.push_back (p.y ());
      z.push_back (p.z ());
      sigma.push_back (sd);
      pixel.push_back ((400 + dv[o]) * 1000 + 500 + du[o]);
    }
    nb.x = x.data (); nb.y = y.data (); nb.z = z.data (); nb.sigma = sigma.data ();
    nb.pixel = pixel.data ();
    nb.width = 1000;
    nb.count = n;
    nb.has_centre_ray = true;
    nb.centre_ray = {cu / f, cv / f, 1.0};
  }
};

/** Largest |A_ij - B_ij| / sqrt(B_ii B_jj) of two packed D x D forms, over the block lo .. hi - 1. */
template <int D>
double
scaledDifference (const double *a, const double *b, int lo, int hi)
{
  double worst = 0;
  for (int i = lo; i < hi; ++i)
    for (int j = i; j < hi; ++j)
    {
      const double scale = std::sqrt (b[packedIndex<D> (i, i)] * b[packedIndex<D> (j, j)]);
      worst = std::max (worst, std::fabs (a[packedIndex<D> (i, j)] - b[packedIndex<D> (i, j)]) / scale);
    }
  return worst;
}

/** Relative Frobenius difference of two packed symmetric 3 x 3 (6 values) or 2 x 2 (3) matrices. */
double
relativeDifference (const double *a, const double *b, int n)
{
  double d = 0, s = 0;
  for (int k = 0; k < n; ++k)
  {
    const double w = (n == 6 ? (k == 0 || k == 3 || k == 5) : (k == 0 || k == 2)) ? 1.0 : 2.0;
    d += w * (a[k] - b[k]) * (a[k] - b[k]);
    s += w * b[k] * b[k];
  }
  return std::sqrt (d / s);
}

} // namespace

TEST (WindowDiscForm, EqualsTheWindowsSumsWhereTheValuesAreQuadratics)
{
  // The tables drop only the part of the values that no quadratic of the offset holds: for
  // values that are quadratics (random coefficients), the form is the windows' sums' to rounding.
  std::mt19937 rng (7);
  std::normal_distribution<double> g (0, 1);
  for (const int r : {3, 6, 9})
    for (const int w : {2, 5, 9, 15})
    {
      const int n = pixelDiscSize (r);
      std::vector<int> du (n), dv (n), u (n), v (n);
      pixelDiscOffsets (r, du.data (), dv.data (), n);
      WindowDiscForm<double> form;
      ASSERT_TRUE (makeWindowDiscForm (du.data (), dv.data (), n, w, form)) << "radius " << r << " window " << w;
      double c[9][6];
      for (auto &row : c)
        for (double &x : row)
          x = g (rng);
      std::vector<double[9]> G (n);
      for (int o = 0; o < n; ++o)
      {
        u[o] = 100 + du[o];
        v[o] = 50 + dv[o];
        const double q[6] = {1.0, double (du[o]), double (dv[o]), double (du[o] * du[o]), double (du[o] * dv[o]),
                             double (dv[o] * dv[o])};
        for (int k = 0; k < 9; ++k)
        {
          G[o][k] = 0;
          for (int a = 0; a < 6; ++a)
            G[o][k] += c[k][a] * q[a];
        }
      }
      double exact[45], tables[45];
      windowForm<double, 9> (G.data (), u.data (), v.data (), n, 100 - r, 50 - r, 2 * r + 1, 2 * r + 1, w, exact);
      windowDiscForm<double, 9> (G.data (), form, tables);
      EXPECT_LT (scaledDifference<9> (tables, exact, 0, 9), 1e-9) << "radius " << r << " window " << w;
    }
}

TEST (WindowDiscForm, RefusesDiscsTooSmallAndWindowsTooNarrow)
{
  int du[9], dv[9];
  const int n = pixelDiscOffsets (1, du, dv, 9);
  WindowDiscForm<double> form;
  EXPECT_FALSE (makeWindowDiscForm (du, dv, n, 5, form)); // 5 offsets, 6 quadratics
  WindowDiscForms<double> forms (du, dv, n);
  EXPECT_EQ (forms.of (5), nullptr);
  EXPECT_EQ (forms.of (1), nullptr); // a 1 px window shares nothing
  // Narrow windows keep the windows' sums (the tables' error grows there, docs/benchmarks.md).
  int du6[113], dv6[113];
  WindowDiscForms<double> whole (du6, dv6, pixelDiscOffsets (6, du6, dv6, 113));
  EXPECT_EQ (whole.of (kMinWindowDiscPx - 1), nullptr);
  EXPECT_NE (whole.of (kMinWindowDiscPx), nullptr);
}

/** The largest differences of the tables' covariances from the windows' sums over many discs. */
struct Agreement
{
  double worst_p = 0, worst_n = 0, median_n = 0, worst_mc_p = 0, worst_mc_n = 0;
};

/** Whole discs of radius 6 px (the default) on planes tilted up to 70 degrees and on spheres,
  * 0.6 to 3.5 m, anywhere in the image, windows of 6 to 15 px, share 0.8, depth SD 1.5e-3 z^2
  * (the paper's order), with \a outliers of their points outliers (half the discs a run of them
  * in disc order, as at an edge, half scattered): Sigma_P and Sigma_N of the analytic
  * propagation (P on the centre ray and the inliers' mean), and on every fourth disc of the
  * moment sampler (20,000 samples, one seed for both: a change of the model changes the draws'
  * transform, so the two differ by about their sampling error, 1 to 3 %), by the tables against
  * the windows' sums. P on the centre ray is heavy-tailed under the sampler where the normal's
  * SD is large, so its Monte Carlo Sigma_P is compared where the normal's SD is below 6 deg.
  */
Agreement
agreementOfTheTables (std::uint32_t seed, int outliers, int missing = 0)
{
  std::mt19937 rng (seed);
  std::uniform_real_distribution<double> uni (0, 1);
  Agreement r;
  std::vector<double> all_n;
  const bool ring_use[7] = {false, false, false, false, false, false, false};
  for (int trial = 0; trial < 200; ++trial)
  {
    // Spheres (every fourth) of radius 0.2 to 0.5 m, tilted up to 30 degrees: the disc stays on them.
    const bool sphere = trial % 4 == 3;
    const double depth = 0.6 + 2.9 * uni (rng), tilt = (sphere ? 30.0 : 70.0) * uni (rng),
                 azimuth = 2 * M_PI * uni (rng), curvature = sphere ? 1.0 / (0.2 + 0.3 * uni (rng)) : 0.0;
    WholeDisc disc (rng, 6, depth, tilt, azimuth, curvature, 600 * uni (rng) - 300, 440 * uni (rng) - 220);
    const int w = kMinWindowDiscPx + trial % (kMaxWindowPx - kMinWindowDiscPx + 1);
    disc.nb.window_fraction = 0.8;
    disc.nb.window_px = w;
    WindowDiscForms<double> forms (disc.du.data (), disc.dv.data (), disc.nb.count);
    // Pixels without a reading: a run of them in disc order (a hole's edge), or scattered.
    std::vector<int> offset;
    if (missing > 0)
    {
      std::vector<bool> gone (disc.nb.count, false);
      const int start = static_cast<int> (uni (rng) * (disc.nb.count - missing));
      for (int k = 0, marked = 0; marked < missing; ++k)
      {
        const int o = trial % 2 ? start + k : static_cast<int> (uni (rng) * disc.nb.count);
        marked += gone[o] ? 0 : 1;
        gone[o] = true;
      }
      int kept = 0;
      for (int o = 0; o < disc.nb.count; ++o)
        if (!gone[o])
        {
          disc.x[kept] = disc.x[o]; disc.y[kept] = disc.y[o]; disc.z[kept] = disc.z[o];
          disc.sigma[kept] = disc.sigma[o]; disc.pixel[kept] = disc.pixel[o];
          offset.push_back (o);
          ++kept;
        }
      disc.nb.count = kept;
      disc.nb.disc_offset = offset.data ();
      EXPECT_EQ (forms.offsetsOf (disc.pixel.data (), kept, 500, 400, 1000, 800)[kept - 1], offset.back ());
    }
    std::vector<unsigned char> mask (disc.nb.count, 1);
    const int run_start = static_cast<int> (uni (rng) * (disc.nb.count - outliers));
    for (int k = 0, marked = 0; marked < outliers; ++k)
    {
      const int o = trial % 2 ? run_start + k : static_cast<int> (uni (rng) * disc.nb.count);
      marked += mask[o] ? 1 : 0;
      mask[o] = 0;
    }
    PlaneFit<double> fit;
    EXPECT_TRUE (fitInliersPca (disc.nb, mask.data (), fit));
    Vec3<double> N = fit.N, t1, t2;
    if (dot (N, fit.P) > 0)
      N = -N;
    tangentFrame (N, t1, t2);
    for (const TexletCentre where : {TexletCentre::CentreRay, TexletCentre::InlierMean})
    {
      const TexletCentrePoint<double> centre = texletCentre (disc.nb, fit, N, t1, t2, where, PlaneFitMethod::PCA);
      double exact_p[6], exact_n[3], tables_p[6], tables_n[3];
      disc.nb.window_disc = nullptr;
      analyticCovariance (disc.nb, mask.data (), ring_use, PlaneFitMethod::PCA, fit, centre, exact_p, exact_n);
      disc.nb.window_disc = forms.of (w);
      EXPECT_NE (disc.nb.window_disc, nullptr);
      analyticCovariance (disc.nb, mask.data (), ring_use, PlaneFitMethod::PCA, fit, centre, tables_p, tables_n);
      r.worst_p = std::max (r.worst_p, relativeDifference (tables_p, exact_p, 6));
      r.worst_n = std::max (r.worst_n, relativeDifference (tables_n, exact_n, 3));
      all_n.push_back (relativeDifference (tables_n, exact_n, 3));
    }
    if (trial % 4 != 0)
      continue;
    const TexletCentrePoint<double> centre =
        texletCentre (disc.nb, fit, N, t1, t2, TexletCentre::CentreRay, PlaneFitMethod::PCA);
    double exact_p[6], exact_n[3], tables_p[6], tables_n[3];
    disc.nb.window_disc = nullptr;
    monteCarloPcaCovariance (disc.nb, mask.data (), fit, 20000, 5u, 9u, centre, exact_p, exact_n);
    disc.nb.window_disc = forms.of (w);
    monteCarloPcaCovariance (disc.nb, mask.data (), fit, 20000, 5u, 9u, centre, tables_p, tables_n);
    r.worst_mc_n = std::max (r.worst_mc_n, relativeDifference (tables_n, exact_n, 3));
    if (exact_n[0] + exact_n[2] < 2 * std::pow (6 * M_PI / 180, 2))
      r.worst_mc_p = std::max (r.worst_mc_p, relativeDifference (tables_p, exact_p, 6));
  }
  std::sort (all_n.begin (), all_n.end ());
  r.median_n = all_n[all_n.size () / 2];
  std::cout << outliers << " outliers, " << missing << " pixels without a reading: largest relative difference, analytic: Sigma_P " << r.worst_p << ", Sigma_N "
            << r.worst_n << " (median " << r.median_n << "); Monte Carlo: Sigma_P " << r.worst_mc_p << ", Sigma_N "
            << r.worst_mc_n << "\n";
  return r;
}

TEST (WindowDiscForm, PropagatedCovariancesAgreeWithTheWindowsSums)
{
  const Agreement r = agreementOfTheTables (2203, 0);
  EXPECT_LT (r.worst_p, 0.02);
  EXPECT_LT (r.worst_n, 0.08);
  EXPECT_LT (r.median_n, 0.002);
  EXPECT_LT (r.worst_mc_p, 0.05);
  EXPECT_LT (r.worst_mc_n, 0.08);
}

TEST (WindowDiscForm, GapsFilledFromTheTablesAgreeWithTheWindowsSums)
{
  // Outliers and pixels without a reading: gaps of the disc that the quadratics' fit fills.
  for (const auto &c : {std::make_pair (1, 0), std::make_pair (3, 0), std::make_pair (8, 0), std::make_pair (0, 1),
                        std::make_pair (0, 8), std::make_pair (3, 5)})
  {
    const int outliers = c.first, missing = c.second;
    const Agreement r = agreementOfTheTables (2207 + outliers + 31 * missing, outliers, missing);
    EXPECT_LT (r.worst_p, 0.02) << outliers << " " << missing;
    EXPECT_LT (r.worst_n, 0.08) << outliers << " " << missing;
    EXPECT_LT (r.median_n, 0.002) << outliers << " " << missing;
    EXPECT_LT (r.worst_mc_p, 0.05) << outliers << " " << missing;
    EXPECT_LT (r.worst_mc_n, 0.08) << outliers << " " << missing;
  }
}
