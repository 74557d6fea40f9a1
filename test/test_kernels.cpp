/*
 * Tests of the header-only kernels against closed-form geometry and Eigen's solvers.
 */
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/noise_terms.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/plane_fit.h>
#include <pcl_texlet/kernels/ransac.h>
#include <pcl_texlet/kernels/tangent_frame.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

using namespace pcl::texlet::kernels;

namespace
{
Eigen::Vector3d
toEigen (const Vec3<double> &v) { return {v.x, v.y, v.z}; }

double
axisAngle (const Eigen::Vector3d &a, const Eigen::Vector3d &b)
{
  return std::atan2 (a.cross (b).norm (), std::fabs (a.dot (b)));
}
} // namespace

TEST (HexGrid, CountMatchesEnumerationAndCentresAreInside)
{
  for (int spacing : {2, 3, 6, 7, 8, 13})
    for (auto [w, h] : {std::pair<int, int>{640, 480}, {33, 17}, {5, 5}})
    {
      const HexGrid g = makeHexGrid (w, h, spacing);
      std::set<std::pair<int, int>> seen;
      for (int i = 0; i < g.size (); ++i)
      {
        int u, v;
        hexCentre (g, i, u, v);
        ASSERT_GE (u, 0);
        ASSERT_LT (u, w);
        ASSERT_GE (v, 0);
        ASSERT_LT (v, h);
        seen.insert ({u, v});
      }
      EXPECT_EQ (static_cast<int> (seen.size ()), g.size ()) << "duplicate centres, spacing " << spacing;
      // Brute force: every row start and column step that lies in the image.
      int expected = 0;
      for (int row = 0;; ++row)
      {
        const int v = static_cast<int> (std::floor (0.5 * spacing + row * spacing * std::sqrt (3.0) / 2));
        if (v >= h)
          break;
        for (int u = static_cast<int> (std::floor (hexFirstColumn (spacing, row))); u < w; u += spacing)
          ++expected;
      }
      EXPECT_EQ (g.size (), expected) << "spacing " << spacing << " size " << w << "x" << h;
    }
}

TEST (HexGrid, NeighboursAreEquidistant)
{
  // In a hexagonal grid, a centre's nearest neighbours lie at about the spacing, in six directions.
  const int spacing = 12;
  const HexGrid g = makeHexGrid (200, 200, spacing);
  int u0, v0;
  hexCentre (g, g.cols_even + g.cols_odd + g.cols_even / 2, u0, v0); // an inner centre on row 2
  int close = 0;
  for (int i = 0; i < g.size (); ++i)
  {
    int u, v;
    hexCentre (g, i, u, v);
    const double d = std::hypot (u - u0, v - v0);
    if (d > 0 && d < 1.3 * spacing)
    {
      EXPECT_NEAR (d, spacing, 1.0);
      ++close;
    }
  }
  EXPECT_EQ (close, 6);
  // 640x480 at the paper's spacing of 6 px.
  EXPECT_EQ (makeHexGrid (640, 480, 6).size (), 46 * 107 + 46 * 106); // 9798 (the paper: 9,814)
  EXPECT_EQ (makeHexGrid (640, 480, 1).size (), 0); // spacing 1 is not a hexagonal grid
}

TEST (PixelDisc, CountsAndMembership)
{
  EXPECT_EQ (pixelDiscSize (1), 5);
  EXPECT_EQ (pixelDiscSize (2), 13);
  EXPECT_EQ (pixelDiscSize (6), 113);
  int du[200], dv[200];
  const int n = pixelDiscOffsets (6, du, dv, 200);
  ASSERT_EQ (n, 113);
  for (int i = 0; i < n; ++i)
    EXPECT_LE (du[i] * du[i] + dv[i] * dv[i], 36);
  EXPECT_EQ (pixelDiscOffsets (6, du, dv, 10), 113); // reports the size even when capacity is short
}

TEST (Philox, DeterministicAndDistinctTriples)
{
  const auto a = philoxWords (7, 11, 3, 0, RandomStream::Ransac);
  const auto b = philoxWords (7, 11, 3, 0, RandomStream::Ransac);
  const auto c = philoxWords (7, 11, 3, 0, RandomStream::MonteCarlo);
  const auto d = philoxWords (8, 11, 3, 0, RandomStream::Ransac);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ (a.v[i], b.v[i]);
  EXPECT_NE (a.v[0], c.v[0]);
  EXPECT_NE (a.v[0], d.v[0]);
  for (int n : {3, 4, 10, 113})
    for (std::uint32_t it = 0; it < 2000; ++it)
    {
      int i, j, k;
      distinctTriple (philoxWords (1, 2, it, 0, RandomStream::Ransac), n, i, j, k);
      ASSERT_TRUE (i != j && j != k && i != k);
      ASSERT_TRUE (i >= 0 && j >= 0 && k >= 0 && i < n && j < n && k < n);
    }
  // Box-Muller draws: mean 0, variance 1.
  double s = 0, ss = 0;
  const int blocks = 20000;
  for (int b = 0; b < blocks; ++b)
  {
    float g[4];
    normalQuad (3, 5, 0, b, g);
    for (float x : g)
    {
      s += x;
      ss += x * x;
    }
  }
  EXPECT_NEAR (s / (4 * blocks), 0.0, 0.02);
  EXPECT_NEAR (ss / (4 * blocks), 1.0, 0.03);
}

TEST (SymEigen3, MatchesEigenOnRandomAndNearDegenerateMatrices)
{
  std::mt19937 rng (42);
  std::normal_distribution<double> g (0, 1);
  for (int trial = 0; trial < 2000; ++trial)
  {
    // Random rotation and spectrum; every third case has two nearly equal eigenvalues, as a
    // round planar patch does.
    const Eigen::Matrix3d R = Eigen::Quaterniond (g (rng), g (rng), g (rng), g (rng)).normalized ().toRotationMatrix ();
    Eigen::Vector3d l (std::exp (g (rng)), std::exp (g (rng)), 1e-3 * std::exp (g (rng)));
    if (trial % 3 == 0)
      l[1] = l[0] * (1 + 1e-9 * g (rng));
    const Eigen::Matrix3d A = R * l.asDiagonal () * R.transpose ();
    const double packed[6] = {A (0, 0), A (0, 1), A (0, 2), A (1, 1), A (1, 2), A (2, 2)};
    SymEigen3<double> mine;
    ASSERT_TRUE (symmetricEigen3 (packed, mine));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ref (A);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR (mine.values[i], ref.eigenvalues ()[i], 1e-9 * ref.eigenvalues ()[2]);
    EXPECT_LT (axisAngle (toEigen (mine.vectors[0]), ref.eigenvectors ().col (0)), 1e-6);
    // Orthonormal, and each vector satisfies A v = l v.
    for (int i = 0; i < 3; ++i)
    {
      EXPECT_NEAR (toEigen (mine.vectors[i]).norm (), 1.0, 1e-12);
      EXPECT_LT ((A * toEigen (mine.vectors[i]) - mine.values[i] * toEigen (mine.vectors[i])).norm (),
                 1e-8 * ref.eigenvalues ()[2]);
    }
    EXPECT_NEAR (toEigen (mine.vectors[0]).dot (toEigen (mine.vectors[1])), 0.0, 1e-12);
  }
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  SymEigen3<double> e;
  EXPECT_FALSE (symmetricEigen3 (zero, e));
}

TEST (PlaneFit, PcaSvdAndReferenceAgreeOnNoisyPatches)
{
  std::mt19937 rng (7);
  std::normal_distribution<double> g (0, 1);
  for (int trial = 0; trial < 200; ++trial)
  {
    const Eigen::Vector3d n = Eigen::Vector3d (g (rng), g (rng), g (rng)).normalized ();
    const Eigen::Vector3d a = n.unitOrthogonal (), b = n.cross (a);
    const Eigen::Vector3d c (0.1 * g (rng), 0.1 * g (rng), 1.0 + 0.2 * g (rng));
    const int count = 60;
    std::vector<double> pts (3 * count);
    Eigen::MatrixXd M (count, 3);
    PlaneMoments<double> m;
    for (int i = 0; i < count; ++i)
    {
      const Eigen::Vector3d p = c + 0.01 * g (rng) * a + 0.01 * g (rng) * b + 0.0005 * g (rng) * n;
      M.row (i) = p.transpose ();
      if (i == 0)
        m.reset ({p.x (), p.y (), p.z ()});
      m.add ({p.x (), p.y (), p.z ()});
    }
    const Eigen::RowVector3d mean = M.colwise ().mean ();
    const Eigen::MatrixXd C = M.rowwise () - mean;
    for (int i = 0; i < count; ++i)
      for (int j = 0; j < 3; ++j)
        pts[3 * i + j] = C (i, j);
    PlaneFit<double> pca, svd;
    ASSERT_TRUE (fitPlanePca (m, pca));
    ASSERT_TRUE (fitPlaneSvd (pts.data (), count, {mean.x (), mean.y (), mean.z ()}, svd));
    Eigen::JacobiSVD<Eigen::MatrixXd> ref (C, Eigen::ComputeThinV);
    const Eigen::Vector3d ref_n = ref.matrixV ().col (2);
    EXPECT_LT (axisAngle (toEigen (pca.N), ref_n), 1e-9);
    EXPECT_LT (axisAngle (toEigen (svd.N), ref_n), 1e-9);
    EXPECT_LT ((toEigen (pca.P) - mean.transpose ()).norm (), 1e-12);
    EXPECT_NEAR (svd.lambda[0], ref.singularValues ()[2] * ref.singularValues ()[2] / count, 1e-12);
    EXPECT_NEAR (pca.lambda[0], svd.lambda[0], 1e-10);
  }
}

TEST (PlaneFit, CollinearPointsHaveNoPlane)
{
  PlaneMoments<double> m;
  m.reset ({0, 0, 1});
  std::vector<double> pts;
  for (int i = 0; i < 10; ++i)
  {
    m.add ({0.01 * i, 0.02 * i, 1.0 + 0.005 * i});
    pts.insert (pts.end (), {0.01 * i - 0.045, 0.02 * i - 0.09, 0.005 * i - 0.0225});
  }
  PlaneFit<double> fit;
  EXPECT_FALSE (fitPlanePca (m, fit));
  EXPECT_FALSE (fitPlaneSvd (pts.data (), 10, {0.045, 0.09, 1.0225}, fit));
}

TEST (PlaneFit, AveragingRecoversAnExactPlane)
{
  // Ring on the plane z = 1 + 0.3 x - 0.2 y, in angular order.
  const Eigen::Vector3d n = Eigen::Vector3d (0.3, -0.2, -1).normalized ();
  Vec3<double> ring[7];
  bool use[7];
  for (int k = 0; k < 7; ++k)
  {
    const double a = (k - 1) * M_PI / 3, r = k == 0 ? 0.0 : 0.01;
    const double x = r * std::cos (a), y = r * std::sin (a);
    ring[k] = {x, y, 1 + 0.3 * x - 0.2 * y};
    use[k] = true;
  }
  Vec3<double> out;
  ASSERT_TRUE (averagingNormal (ring, use, out));
  EXPECT_LT (axisAngle (toEigen (out), n), 1e-12);
  use[2] = use[5] = false; // two opposite gaps leave the pairs (3,4) and (6,1)
  ASSERT_TRUE (averagingNormal (ring, use, out));
  EXPECT_LT (axisAngle (toEigen (out), n), 1e-12);
  use[0] = false;
  EXPECT_FALSE (averagingNormal (ring, use, out));
}

TEST (Ransac, OneHypothesisAtATimePicksTheSequentialLoopsPlane)
{
  // The GPU's warp strategy tries hypotheses one a lane, counts every point and keeps the first
  // with the most inliers; the sequential loop stops counting hopeless ones. Same plane.
  std::mt19937 rng (5);
  std::uniform_real_distribution<double> u (-0.03, 0.03), noise (-2e-4, 2e-4);
  for (int trial = 0; trial < 50; ++trial)
  {
    std::vector<double> x, y, z;
    const int n = 40 + trial;
    for (int i = 0; i < n; ++i)
    {
      const double a = u (rng), b = u (rng);
      x.push_back (a);
      y.push_back (b);
      z.push_back (i % 4 == 0 ? 1.02 + 0.3 * b : 1 + 0.2 * a + noise (rng)); // a quarter elsewhere
    }
    const double threshold = 3e-4;
    Plane<double> sequential;
    const int best = ransacPlane (x.data (), y.data (), z.data (), n, 20, threshold, 7u, 1000u + trial, sequential);
    int most = 0;
    Plane<double> first = {{0, 0, 0}, 0};
    for (int it = 0; it < 20; ++it)
    {
      Plane<double> h;
      if (!ransacHypothesis (x.data (), y.data (), z.data (), n, ransacWords (7u, 1000u + trial, it), h))
        continue;
      const int count = countInliers (h, x.data (), y.data (), z.data (), 0, n, threshold);
      if (count > most)
      {
        most = count;
        first = h;
      }
    }
    ASSERT_EQ (most, best) << "trial " << trial;
    EXPECT_EQ (first.n.x, sequential.n.x);
    EXPECT_EQ (first.n.y, sequential.n.y);
    EXPECT_EQ (first.n.z, sequential.n.z);
    EXPECT_EQ (first.d, sequential.d);
  }
}

TEST (Ransac, FindsThePlaneAmongOutliers)
{
  std::mt19937 rng (3);
  std::uniform_real_distribution<double> u (-0.02, 0.02);
  std::vector<double> x, y, z;
  for (int i = 0; i < 70; ++i) // plane z = 1 + 0.5 x
  {
    const double a = u (rng), b = u (rng);
    x.push_back (a); y.push_back (b); z.push_back (1 + 0.5 * a);
  }
  for (int i = 0; i < 30; ++i) // a second surface 5 cm behind
  {
    const double a = u (rng), b = u (rng);
    x.push_back (a); y.push_back (b); z.push_back (1.05 - 0.8 * b);
  }
  Plane<double> plane;
  const int count = ransacPlane (x.data (), y.data (), z.data (), 100, 20, 1e-4, 0u, 99u, plane);
  EXPECT_EQ (count, 70);
  EXPECT_LT (axisAngle (toEigen (plane.n), Eigen::Vector3d (0.5, 0, -1).normalized ()), 1e-9);
  // Same seed and texlet: same plane.
  Plane<double> again;
  ransacPlane (x.data (), y.data (), z.data (), 100, 20, 1e-4, 0u, 99u, again);
  EXPECT_EQ (again.d, plane.d);
}

TEST (TangentFrame, RightHandedOrthonormalAndCameraAligned)
{
  std::mt19937 rng (5);
  std::normal_distribution<double> g (0, 1);
  for (int i = 0; i < 1000; ++i)
  {
    const Vec3<double> n = normalized (make3 (g (rng), g (rng), g (rng)));
    Vec3<double> t1, t2;
    tangentFrame (n, t1, t2);
    EXPECT_NEAR (norm (t1), 1, 1e-12);
    EXPECT_NEAR (norm (t2), 1, 1e-12);
    EXPECT_NEAR (dot (t1, n), 0, 1e-12);
    EXPECT_NEAR (dot (t2, n), 0, 1e-12);
    EXPECT_LT ((toEigen (cross (t1, t2)) - toEigen (n)).norm (), 1e-12);
  }
  Vec3<double> t1, t2;
  tangentFrame (make3 (0.0, 0.0, -1.0), t1, t2); // a wall facing the camera
  EXPECT_NEAR (t1.x, 1, 1e-15);                  // right in the image
  EXPECT_NEAR (t2.y, -1, 1e-15);                 // up in the image (v grows downward)
}

TEST (NoiseTerms, PaperPolynomialClosedForm)
{
  const PolynomialCoefficients c = paperPolynomial ();
  // f(0, 1000) = 2.344 - 2.734 + 1.233
  EXPECT_NEAR (evaluatePolynomial (c, 0, 1000), 0.843, 1e-12);
  // f(100, 1500) = 2.344 - 1.202 - 4.101 + 0.1818 + 0.9774 + 2.77425
  EXPECT_NEAR (evaluatePolynomial (c, 100, 1500), 0.97445, 1e-12);
}
