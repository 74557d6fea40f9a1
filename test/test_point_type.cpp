/*
 * pcl::Texlet in PCD files: exact round trips, NaN texlets, and PCL's own tools.
 */
#include "support/temp_dir.h"

#include <pcl_texlet/features/point_types.h>

#include <pcl/io/pcd_io.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>

namespace fs = std::filesystem;

namespace
{

pcl::PointCloud<pcl::Texlet>
randomTexlets (std::size_t n, std::uint32_t seed)
{
  std::mt19937 rng (seed);
  // Full-precision floats over many magnitudes: every one needs all of its 9 digits.
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  std::uniform_int_distribution<std::uint32_t> i (0, 0xffffffffu);
  pcl::PointCloud<pcl::Texlet> cloud;
  for (std::size_t k = 0; k < n; ++k)
  {
    pcl::Texlet t;
    t.x = u (rng); t.y = u (rng); t.z = 1 + u (rng);
    t.normal_x = u (rng); t.normal_y = u (rng); t.normal_z = u (rng);
    t.rgba = i (rng);
    t.curvature = u (rng) * 1e-3f;
    t.radius = u (rng) * 1e-2f;
    t.support = i (rng);
    t.cov_p_xx = u (rng) * 1e-7f; t.cov_p_xy = u (rng) * 1e-9f; t.cov_p_xz = u (rng) * 1e-8f;
    t.cov_p_yy = u (rng) * 1e-7f; t.cov_p_yz = u (rng) * 1e-9f; t.cov_p_zz = u (rng) * 1e-6f;
    t.cov_n_11 = u (rng) * 1e-4f; t.cov_n_12 = u (rng) * 1e-5f; t.cov_n_22 = u (rng) * 1e-4f;
    t.pixel_index = i (rng);
    cloud.push_back (t);
  }
  // A failed texlet: NaN everywhere, support 0.
  pcl::Texlet bad;
  bad.x = bad.y = bad.z = bad.normal_x = bad.normal_y = bad.normal_z = std::nanf ("");
  bad.curvature = bad.radius = bad.cov_p_xx = bad.cov_n_22 = std::nanf ("");
  cloud.push_back (bad);
  cloud.is_dense = false;
  return cloud;
}

bool
sameFloat (float a, float b) { return (std::isnan (a) && std::isnan (b)) || a == b; }

void
expectEqual (const pcl::PointCloud<pcl::Texlet> &a, const pcl::PointCloud<pcl::Texlet> &b)
{
  ASSERT_EQ (a.size (), b.size ());
  for (std::size_t k = 0; k < a.size (); ++k)
  {
    const pcl::Texlet &p = a[k], &q = b[k];
    const float fa[] = {p.x, p.y, p.z, p.normal_x, p.normal_y, p.normal_z, p.curvature, p.radius,
                        p.cov_p_xx, p.cov_p_xy, p.cov_p_xz, p.cov_p_yy, p.cov_p_yz, p.cov_p_zz,
                        p.cov_n_11, p.cov_n_12, p.cov_n_22};
    const float fb[] = {q.x, q.y, q.z, q.normal_x, q.normal_y, q.normal_z, q.curvature, q.radius,
                        q.cov_p_xx, q.cov_p_xy, q.cov_p_xz, q.cov_p_yy, q.cov_p_yz, q.cov_p_zz,
                        q.cov_n_11, q.cov_n_12, q.cov_n_22};
    for (std::size_t f = 0; f < sizeof (fa) / sizeof (float); ++f)
      ASSERT_TRUE (sameFloat (fa[f], fb[f])) << "texlet " << k << " field " << f << ": " << fa[f] << " vs " << fb[f];
    ASSERT_EQ (p.rgba, q.rgba);
    ASSERT_EQ (p.support, q.support);
    ASSERT_EQ (p.pixel_index, q.pixel_index);
  }
}

using pcl_texlet_test::TempDir;

} // namespace

TEST (TexletPointType, FieldsAreRegistered)
{
  std::vector<pcl::PCLPointField> fields;
  pcl::getFields<pcl::Texlet> (fields);
  std::vector<std::string> names;
  for (const auto &f : fields)
    names.push_back (f.name);
  const std::vector<std::string> expected = {"x", "y", "z", "normal_x", "normal_y", "normal_z", "rgb", "curvature",
                                             "radius", "support", "cov_p_xx", "cov_p_xy", "cov_p_xz", "cov_p_yy",
                                             "cov_p_yz", "cov_p_zz", "cov_n_11", "cov_n_12", "cov_n_22",
                                             "pixel_index"};
  EXPECT_EQ (names, expected);
  EXPECT_TRUE (pcl::traits::has_normal_v<pcl::Texlet>);
  EXPECT_TRUE (pcl::traits::has_color_v<pcl::Texlet>);
}

TEST (TexletPointType, CovarianceSettersAreTheGettersInverse)
{
  pcl::Texlet t;
  Eigen::Matrix3f cp;
  cp << 4e-6f, 1e-6f, -5e-7f, 1e-6f, 3e-6f, 2e-7f, -5e-7f, 2e-7f, 9e-6f;
  t.setCovarianceP (cp);
  EXPECT_EQ (t.covarianceP (), cp);
  EXPECT_EQ (t.cov_p_xz, -5e-7f);
  EXPECT_EQ (t.cov_p_yz, 2e-7f);

  Eigen::Matrix2f cn;
  cn << 4e-4f, 1.0e-4f, 2.0e-4f, 1e-4f; // an asymmetric product: the off-diagonal's mean is kept
  t.setCovarianceN (cn);
  EXPECT_EQ (t.cov_n_11, 4e-4f);
  EXPECT_FLOAT_EQ (t.cov_n_12, 1.5e-4f);
  EXPECT_EQ (t.cov_n_22, 1e-4f);
  EXPECT_EQ (t.covarianceN () (0, 1), t.covarianceN () (1, 0));
}

TEST (TexletPointType, BinaryPcdRoundTripIsExact)
{
  TempDir dir;
  const auto cloud = randomTexlets (500, 1);
  for (const bool compressed : {false, true})
  {
    const std::string file = (dir.path () / (compressed ? "c.pcd" : "b.pcd")).string ();
    if (compressed)
      ASSERT_EQ (pcl::io::savePCDFileBinaryCompressed (file, cloud), 0);
    else
      ASSERT_EQ (pcl::io::savePCDFile (file, cloud, true), 0);
    pcl::PointCloud<pcl::Texlet> back;
    ASSERT_EQ (pcl::io::loadPCDFile (file, back), 0);
    expectEqual (cloud, back);
  }
}

TEST (TexletPointType, AsciiPcdRoundTripIsExactWithNineDigits)
{
  TempDir dir;
  const auto cloud = randomTexlets (500, 2);
  // 9 significant digits identify every float; PCDWriter's default of 8 does not.
  const std::string file = (dir.path () / "a.pcd").string ();
  ASSERT_EQ (pcl::PCDWriter ().writeASCII (file, cloud, 9), 0);
  pcl::PointCloud<pcl::Texlet> back;
  ASSERT_EQ (pcl::io::loadPCDFile (file, back), 0);
  expectEqual (cloud, back);

  // savePCDFile's ASCII default keeps 8 digits: within 1e-7 relative, integers exact.
  const std::string file8 = (dir.path () / "a8.pcd").string ();
  ASSERT_EQ (pcl::io::savePCDFileASCII (file8, cloud), 0);
  ASSERT_EQ (pcl::io::loadPCDFile (file8, back), 0);
  ASSERT_EQ (back.size (), cloud.size ());
  for (std::size_t k = 0; k + 1 < cloud.size (); ++k)
  {
    EXPECT_NEAR (back[k].cov_p_zz, cloud[k].cov_p_zz, 1e-7 * std::fabs (cloud[k].cov_p_zz));
    EXPECT_NEAR (back[k].x, cloud[k].x, 1e-7 * std::fabs (cloud[k].x));
    EXPECT_EQ (back[k].pixel_index, cloud[k].pixel_index);
    EXPECT_EQ (back[k].rgba, cloud[k].rgba);
  }
}

#ifdef PCL_CONVERT_TOOL
TEST (TexletPointType, PclToolsOpenTheFile)
{
  // PCL's pcl_convert_pcd_ascii_binary reads a texlet PCD and writes it back in binary.
  TempDir dir;
  const auto cloud = randomTexlets (50, 3);
  const fs::path in = dir.path () / "in.pcd", out = dir.path () / "out.pcd";
  ASSERT_EQ (pcl::PCDWriter ().writeASCII (in.string (), cloud, 9), 0);
  const std::string cmd = std::string (PCL_CONVERT_TOOL) + " " + in.string () + " " + out.string () + " 1 > " +
                          (dir.path () / "log.txt").string () + " 2>&1";
  ASSERT_EQ (std::system (cmd.c_str ()), 0);
  pcl::PointCloud<pcl::Texlet> back;
  ASSERT_EQ (pcl::io::loadPCDFile (out.string (), back), 0);
  expectEqual (cloud, back);
}
#endif
