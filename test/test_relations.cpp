/*
 * Texlet relations (the paper's Sect. 4): the pair kernel against closed-form geometry, the
 * histogram binning and inlier boxes at their edges, the OpenMP accumulation against a plain
 * double loop, texlets moved between frames (with Sigma_N re-expressed), merging, extrinsics
 * and object files, and face labels.
 */
#include "support/temp_dir.h"

#include <pcl_texlet/kernels/relation_histogram.h>
#include <pcl_texlet/kernels/texlet_relation.h>
#include <pcl_texlet/relations/extrinsics.h>
#include <pcl_texlet/relations/known_object.h>
#include <pcl_texlet/relations/texlet_merge.h>
#include <pcl_texlet/relations/texlet_relations.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/simulation/simulation_meta.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace fs = std::filesystem;
using namespace pcl::texlet;
using kernels::Vec3;

namespace
{

pcl::Texlet
makeTexlet (const Eigen::Vector3d &p, const Eigen::Vector3d &n)
{
  pcl::Texlet t;
  t.getVector3fMap () = p.cast<float> ();
  t.getNormalVector3fMap () = n.normalized ().cast<float> ();
  t.support = 50;
  return t;
}

/** Texlets on a regular grid over each face of \a object, with the faces' exact normals. */
pcl::PointCloud<pcl::Texlet>
texletsOnFaces (const KnownObject &object, int per_axis, std::vector<int> *labels = nullptr)
{
  pcl::PointCloud<pcl::Texlet> cloud;
  for (std::size_t f = 0; f < object.faces.size (); ++f)
  {
    const ObjectFace &face = object.faces[f];
    const Eigen::Vector3d v = face.normal.cross (face.axis_u);
    for (int a = 0; a < per_axis; ++a)
      for (int b = 0; b < per_axis; ++b)
      {
        const double s = (a + 0.5) / per_axis * 2 - 1, t = (b + 0.5) / per_axis * 2 - 1;
        // Stay 5 mm inside the face so that no texlet is on two faces' edges.
        const Eigen::Vector3d p =
            face.centre + s * (face.half_u_m - 0.005) * face.axis_u + t * (face.half_v_m - 0.005) * v;
        // Ground texlets under the box are hidden in reality; leave them out.
        if (face.name == "ground" && std::fabs (p.x ()) < 0.07 && std::fabs (p.y ()) < 0.062)
          continue;
        cloud.push_back (makeTexlet (p, face.normal));
        if (labels)
          labels->push_back (static_cast<int> (f));
      }
  }
  return cloud;
}

using RelationFiles = pcl_texlet_test::TempDirTest;

template <typename F>
std::string
ioError (F &&f)
{
  try
  {
    f ();
  }
  catch (const pcl::IOException &e)
  {
    return e.what ();
  }
  return "(no pcl::IOException)";
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Kernels

TEST (RelationKernel, ParallelPlanesGiveTheirDistanceBothWays)
{
  const Vec3<double> up{0, 0, 1};
  const auto r = kernels::texletRelation (Vec3<double>{0.1, -0.05, 0.24}, up, Vec3<double>{-0.12, 0.08, 0.0}, up);
  EXPECT_NEAR (r.distance_ij, 0.24, 1e-12);
  EXPECT_NEAR (r.distance_ji, 0.24, 1e-12);
  EXPECT_NEAR (r.angle_deg, 0.0, 1e-6);
  // Opposite sides of the paper's box: normals pointing apart, 128 mm.
  const auto s = kernels::texletRelation (Vec3<double>{0.064, 0.01, 0.1}, Vec3<double>{1, 0, 0},
                                          Vec3<double>{-0.064, -0.03, 0.2}, Vec3<double>{-1, 0, 0});
  EXPECT_NEAR (s.distance_ij, 0.128, 1e-12);
  EXPECT_NEAR (s.distance_ji, 0.128, 1e-12);
  EXPECT_NEAR (s.angle_deg, 180.0, 1e-6);
}

TEST (RelationKernel, OrthogonalPlanesGiveEachCentresOwnDistance)
{
  // Top texlet at height 0.1, side texlet 0.05 along x: n_ij = 0.05 (top centre from the side's
  // plane), n_ji = 0.1 (side centre from the top's plane).
  const auto r = kernels::texletRelation (Vec3<double>{0.0, 0.0, 0.1}, Vec3<double>{0, 0, 1},
                                          Vec3<double>{0.05, 0.0, 0.0}, Vec3<double>{1, 0, 0});
  EXPECT_NEAR (r.distance_ij, 0.05, 1e-12);
  EXPECT_NEAR (r.distance_ji, 0.1, 1e-12);
  EXPECT_NEAR (r.angle_deg, 90.0, 1e-9);
  // A general angle, and a cosine rounded just beyond 1 never gives NaN.
  const double a = 37.0 * M_PI / 180.0;
  EXPECT_NEAR (kernels::normalAngleDeg (Vec3<double>{0, 0, 1}, Vec3<double>{std::sin (a), 0, std::cos (a)}), 37.0, 1e-9);
  const Vec3<float> n{0.6f, 0.8f, 0.0f};
  EXPECT_EQ (kernels::normalAngleDeg (n, Vec3<float>{0.6f * 1.0000001f, 0.8f * 1.0000001f, 0.0f}), 0.0f);
}

TEST (RelationKernel, BinsAndBoxesAtTheirEdges)
{
  kernels::HistogramAxes axes; // 0-0.3 m in 150 bins, 0-180 degrees in 180 bins
  EXPECT_EQ (kernels::relationBin (axes, 0.0, 0.0), 0);
  EXPECT_EQ (kernels::relationBin (axes, 0.0021, 0.5), 1);
  EXPECT_EQ (kernels::relationBin (axes, 0.241, 0.5), 120);
  EXPECT_EQ (kernels::relationBin (axes, 0.001, 90.5), 90 * 150);
  EXPECT_EQ (kernels::relationBin (axes, 0.001, 180.0), 179 * 150); // 180 degrees is in the last bin
  EXPECT_EQ (kernels::relationBin (axes, 0.2999, 1.0), 150 + 149);
  EXPECT_EQ (kernels::relationBin (axes, 0.3001, 1.0), -1);
  EXPECT_EQ (kernels::relationBin (axes, -1e-6, 1.0), -1);
  EXPECT_EQ (kernels::relationBin (axes, std::nan (""), 1.0), -1);
  EXPECT_EQ (kernels::relationBin (axes, 0.1, std::nan ("")), -1);

  kernels::RelationBox top{0.0f, 0.24f, 0.24f, 10.0f, 0.005f};
  EXPECT_TRUE (kernels::insideRelationBox (top, 0.2449, 9.99));
  EXPECT_TRUE (kernels::insideRelationBox (top, 0.2351, -9.99));
  EXPECT_FALSE (kernels::insideRelationBox (top, 0.2449, 10.01));
  EXPECT_FALSE (kernels::insideRelationBox (top, 0.2349, 0.0));
  EXPECT_FALSE (kernels::insideRelationBox (top, 0.2452, 0.0));
  kernels::RelationBox ortho{90.0f, 0.0f, 0.24f, 10.0f, 0.005f};
  const kernels::RelationBox boxes[2] = {top, ortho};
  EXPECT_EQ (kernels::matchRelationBox (boxes, 2, 0.12, 85.0), 1);
  EXPECT_EQ (kernels::matchRelationBox (boxes, 2, 0.24, 3.0), 0);
  EXPECT_EQ (kernels::matchRelationBox (boxes, 2, 0.12, 45.0), -1);
  EXPECT_EQ (kernels::matchRelationBox (boxes, 2, std::nan (""), 90.0), -1);
}

// ---------------------------------------------------------------------------------------------
// Accumulation

TEST (TexletRelations, ExactBoxTexletsAreAllInliersWithPeaksAtTable2)
{
  const KnownObject box = paperBoxObject ();
  std::vector<int> labels;
  const auto cloud = texletsOnFaces (box, 8, &labels);
  const std::size_t n = cloud.size ();
  const RelationStatistics s = accumulateRelations (cloud, box, RelationParameters (), labels);
  EXPECT_EQ (s.texlets, n);
  EXPECT_EQ (s.relation_count, n * (n - 1));
  EXPECT_EQ (s.inliers, s.relation_count);
  EXPECT_EQ (s.outside_histogram, 0u);
  EXPECT_DOUBLE_EQ (s.inlierPercent (), 100.0);
  // Each point relation's peak is in the bin of its Table 2 value (2 mm x 1 degree bins; a value
  // on a bin edge may land on either side in float).
  struct Expect
  {
    double mm, deg;
  };
  for (const Expect e : {Expect{240, 0}, Expect{128, 180}, Expect{112, 180}, Expect{0, 0}})
  {
    const RelationPeak p = s.peakNear (e.mm / 1000.0, e.deg, 0.007, 20.0);
    EXPECT_NEAR (p.distance_m * 1000.0, e.mm, 1.0 + 1e-4) << e.mm << " mm, " << e.deg << " deg";
    EXPECT_NEAR (p.angle_deg, e.deg, 0.5 + 1e-4) << e.mm << " mm, " << e.deg << " deg";
    EXPECT_GT (p.count, 0u);
  }
  // Top vs ground: 64 top texlets x the ground texlets, both directions, all in the first box.
  const int top = box.faceIndex ("top"), ground = box.faceIndex ("ground");
  const std::size_t n_top = std::count (labels.begin (), labels.end (), top);
  const std::size_t n_ground = std::count (labels.begin (), labels.end (), ground);
  EXPECT_EQ (n_top, 64u);
  const std::size_t L = s.labels.size ();
  EXPECT_EQ (s.label_pairs[top * L + ground] + s.label_pairs[ground * L + top], 2 * n_top * n_ground);
  EXPECT_DOUBLE_EQ (s.labelPairInlierPercent (top, ground), 100.0);
  EXPECT_EQ (s.relations[0].name, "top vs ground");
  // Parallel same-direction pairs at 0 deg are either same plane (first match: top vs ground is
  // listed first and only takes 240 mm) or top vs ground.
  std::uint64_t hits = 0;
  for (auto h : s.relation_hits)
    hits += h;
  EXPECT_EQ (hits, s.inliers);
}

TEST (TexletRelations, EqualsAPlainDoubleLoopOnAnyThreadCount)
{
  // Random texlets around the box, some near the expected relations and most not.
  std::mt19937 rng (7);
  std::uniform_real_distribution<double> u (-0.2, 0.2);
  std::normal_distribution<double> g (0.0, 1.0);
  pcl::PointCloud<pcl::Texlet> cloud;
  std::vector<int> labels;
  const KnownObject box = paperBoxObject ();
  for (int i = 0; i < 700; ++i)
  {
    Eigen::Vector3d n (g (rng), g (rng), g (rng));
    if (i % 3 == 0)
      n = Eigen::Vector3d (0.02 * g (rng), 0.02 * g (rng), 1.0); // near-parallel planes
    cloud.push_back (makeTexlet (Eigen::Vector3d (u (rng), u (rng), u (rng) + 0.2), n));
    labels.push_back (i % 7 - 1); // -1 (unlabelled) to 5
  }
  cloud[13].support = 0;                         // a failed texlet: skipped
  cloud[14].x = std::numeric_limits<float>::quiet_NaN (); // and a NaN one

  RelationParameters params;
  params.threads = 1;
  const RelationStatistics one = accumulateRelations (cloud, box, params, labels);
  params.threads = 2;
  const RelationStatistics two = accumulateRelations (cloud, box, params, labels);
  params.threads = 5; // more threads than cores: still the same sums
  const RelationStatistics five = accumulateRelations (cloud, box, params, labels);

  // Reference: every ordered pair, in double precision where it does not change a bin.
  std::vector<std::uint64_t> hist (one.histogram.size (), 0);
  std::uint64_t relations = 0, inliers = 0;
  std::vector<std::uint64_t> pairs (36, 0);
  for (std::size_t i = 0; i < cloud.size (); ++i)
    for (std::size_t j = 0; j < cloud.size (); ++j)
    {
      if (i == j || !isValidTexlet (cloud[i]) || !isValidTexlet (cloud[j]))
        continue;
      const auto &a = cloud[i], &b = cloud[j];
      // Normals renormalised in float, as accumulateRelations does before the kernel.
      const auto unit = [] (const pcl::Texlet &t) {
        const float len = std::sqrt (t.normal_x * t.normal_x + t.normal_y * t.normal_y + t.normal_z * t.normal_z);
        return Vec3<float>{t.normal_x / len, t.normal_y / len, t.normal_z / len};
      };
      const Vec3<float> pa{a.x, a.y, a.z}, pb{b.x, b.y, b.z}, na = unit (a), nb = unit (b);
      const auto r = kernels::texletRelation (pa, na, pb, nb); // distance_ij: i's centre from j's plane
      ++relations;
      const int bin = kernels::relationBin (params.axes, r.distance_ij, r.angle_deg);
      if (bin >= 0)
        ++hist[bin];
      bool in = false;
      for (const auto &e : box.relations)
      {
        const double d = r.distance_ij, ang = r.angle_deg;
        in = in || (std::fabs (ang - e.angle_deg) <= 10.0 + 1e-4 && d >= e.distance_min_m - 0.005 - 1e-7 &&
                    d <= e.distance_max_m + 0.005 + 1e-7);
      }
      inliers += in ? 1 : 0;
      if (labels[i] >= 0 && labels[j] >= 0)
        ++pairs[labels[i] * 6 + labels[j]];
    }
  EXPECT_EQ (one.texlets, 698u);
  EXPECT_EQ (one.relation_count, 698u * 697u);
  EXPECT_EQ (one.relation_count, relations);
  EXPECT_EQ (one.histogram, hist);
  EXPECT_NEAR (static_cast<double> (one.inliers), static_cast<double> (inliers), 2.0); // float vs double at box edges
  EXPECT_EQ (one.label_pairs, pairs);
  EXPECT_GT (one.inliers, 0u);
  EXPECT_LT (one.inliers, one.relation_count);
  for (const RelationStatistics *other : {&two, &five})
  {
    EXPECT_EQ (other->histogram, one.histogram);
    EXPECT_EQ (other->inliers, one.inliers);
    EXPECT_EQ (other->relation_hits, one.relation_hits);
    EXPECT_EQ (other->label_pairs, one.label_pairs);
    EXPECT_EQ (other->label_inliers, one.label_inliers);
    EXPECT_EQ (other->outside_histogram, one.outside_histogram);
  }
}

TEST (TexletRelations, ClassGivesTheFreeFunctionsResult)
{
  const KnownObject box = paperBoxObject ();
  auto cloud = std::make_shared<pcl::PointCloud<pcl::Texlet>> (texletsOnFaces (box, 4));
  TexletRelations rel;
  RelationStatistics s;
  EXPECT_THROW (rel.compute (s), pcl::BadArgumentException);
  rel.setInputCloud (cloud);
  kernels::HistogramAxes axes;
  axes.distance_max = 0.25f;
  axes.distance_bins = 50;
  axes.angle_bins = 36;
  rel.setHistogramAxes (axes);
  rel.setNumberOfThreads (2);
  rel.compute (s);
  RelationParameters p;
  p.axes = axes;
  const RelationStatistics f = accumulateRelations (*cloud, box, p);
  EXPECT_EQ (s.histogram, f.histogram);
  EXPECT_EQ (s.histogram.size (), 50u * 36u);
  EXPECT_EQ (s.inliers, f.inliers);
}

TEST (TexletRelations, BackendGetsTheCompactedValidTexletsAndFillsTheStatistics)
{
  // RelationParameters::backend (how the GPU backend plugs in): the valid texlets compacted,
  // unit normals, labels beside them, the object's boxes; what it counts becomes the result.
  // Here a backend running the CPU path's row kernel in reverse row order, serially.
  const KnownObject box = paperBoxObject ();
  pcl::PointCloud<pcl::Texlet> cloud = texletsOnFaces (box, 4);
  cloud[3].support = 0; // skipped by the compaction
  std::vector<int> labels = labelTexlets (cloud, box);
  RelationParameters params;
  params.threads = 2;
  const RelationStatistics cpu = accumulateRelations (cloud, box, params, labels);
  int calls = 0, seen = 0;
  params.backend = [&] (const kernels::RelationInput<float> &in, const kernels::RelationConfig &config,
                        kernels::RelationCounts<std::uint64_t> &counts) {
    ++calls;
    seen = in.count;
    EXPECT_EQ (config.box_count, static_cast<int> (box.relations.size ()));
    EXPECT_EQ (config.label_count, static_cast<int> (box.faces.size ()));
    ASSERT_NE (in.label, nullptr);
    for (int i = 0; i < in.count; ++i)
      EXPECT_NEAR (kernels::dot (in.normal[i], in.normal[i]), 1.0f, 1e-6f);
    for (int i = in.count - 1; i >= 0; --i)
      kernels::accumulateRelationRow (i, in, config, counts);
  };
  const RelationStatistics other = accumulateRelations (cloud, box, params, labels);
  EXPECT_EQ (calls, 1);
  EXPECT_EQ (static_cast<std::size_t> (seen), cloud.size () - 1);
  EXPECT_EQ (other.texlets, cpu.texlets);
  EXPECT_EQ (other.relation_count, cpu.relation_count);
  EXPECT_EQ (other.histogram, cpu.histogram);
  EXPECT_EQ (other.inliers, cpu.inliers);
  EXPECT_EQ (other.relation_hits, cpu.relation_hits);
  EXPECT_EQ (other.label_pairs, cpu.label_pairs);
  EXPECT_EQ (other.label_inliers, cpu.label_inliers);
  EXPECT_EQ (other.outside_histogram, cpu.outside_histogram);
  EXPECT_GT (cpu.inliers, 0u);

  // The class passes it on; a backend's exception reaches the caller.
  TexletRelations rel;
  rel.setInputCloud (std::make_shared<pcl::PointCloud<pcl::Texlet>> (cloud));
  rel.setBackend ([] (const auto &, const auto &, auto &) { throw std::runtime_error ("no CUDA device"); });
  RelationStatistics s;
  EXPECT_THROW (rel.compute (s), std::runtime_error);
}

TEST (TexletRelations, BadInputIsNamed)
{
  const KnownObject box = paperBoxObject ();
  const auto cloud = texletsOnFaces (box, 2);
  RelationParameters p;
  p.axes.distance_bins = 0;
  EXPECT_THROW (accumulateRelations (cloud, box, p), pcl::BadArgumentException);
  p = RelationParameters ();
  p.axes.distance_max = -1.0f;
  EXPECT_THROW (accumulateRelations (cloud, box, p), pcl::BadArgumentException);
  EXPECT_THROW (accumulateRelations (cloud, box, RelationParameters (), std::vector<int> (3, 0)),
                pcl::BadArgumentException);
  EXPECT_THROW (accumulateRelations (cloud, box, RelationParameters (), std::vector<int> (cloud.size (), 6)),
                pcl::BadArgumentException);
  KnownObject empty = box;
  empty.relations.clear ();
  EXPECT_THROW (accumulateRelations (cloud, empty), pcl::BadArgumentException);
  // No texlets at all is not an error: no relations, no percentage.
  const RelationStatistics none = accumulateRelations (pcl::PointCloud<pcl::Texlet> (), box);
  EXPECT_EQ (none.relation_count, 0u);
  EXPECT_TRUE (std::isnan (none.inlierPercent ()));
}

// ---------------------------------------------------------------------------------------------
// Frames and merging

TEST (TexletMerge, RigidMotionMovesCentreNormalAndCovariances)
{
  pcl::Texlet t = makeTexlet (Eigen::Vector3d (0.1, -0.2, 1.1), Eigen::Vector3d (0.2, -0.1, -1.0));
  Eigen::Matrix3f cp;
  cp << 4e-6f, 1e-6f, -5e-7f, 1e-6f, 3e-6f, 2e-7f, -5e-7f, 2e-7f, 9e-6f;
  t.setCovarianceP (cp);
  t.cov_n_11 = 4e-4f;
  t.cov_n_12 = 1.5e-4f;
  t.cov_n_22 = 1e-4f;

  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
  pose.linear () = (Eigen::AngleAxisd (0.7, Eigen::Vector3d (1, 2, -0.5).normalized ()) *
                    Eigen::AngleAxisd (2.1, Eigen::Vector3d::UnitZ ()))
                       .toRotationMatrix ();
  pose.translation () = Eigen::Vector3d (0.3, -1.2, 0.8);
  pcl::Texlet m;
  transformTexlet (t, pose, m);
  const Eigen::Matrix3f r = pose.linear ().cast<float> ();
  EXPECT_LT ((m.getVector3fMap () - (pose * t.getVector3fMap ().cast<double> ()).cast<float> ()).norm (), 1e-6);
  EXPECT_LT ((m.getNormalVector3fMap () - r * t.getNormalVector3fMap ()).norm (), 1e-6);
  EXPECT_LT ((m.covarianceP () - r * cp * r.transpose ()).norm (), 1e-11);

  // Sigma_N: the deviations of N along its tangents, rotated, then read along the new
  // normal's own tangents, have the covariance the transform reports.
  const Eigen::Matrix<float, 3, 2> t_old = t.tangentFrame (), t_new = m.tangentFrame ();
  const Eigen::Matrix2f c_old = t.covarianceN ();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2f> es (c_old);
  Eigen::Matrix2f c_check = Eigen::Matrix2f::Zero ();
  for (int k = 0; k < 2; ++k)
    for (int sign : {-1, 1})
    {
      const Eigen::Vector2f d = sign * std::sqrt (es.eigenvalues ()[k]) * es.eigenvectors ().col (k);
      const Eigen::Vector3f n = (t.getNormalVector3fMap () + t_old * d).normalized ();
      const Eigen::Vector3f rn = r * n;
      const Eigen::Vector2f e = t_new.transpose () * rn; // small-angle deviation in the new frame
      c_check += 0.5f * e * e.transpose ();
    }
  EXPECT_LT ((m.covarianceN () - c_check).norm (), 2e-3 * c_old.norm ());
  // A rotation about N itself keeps N but turns the frame: Sigma_N must change with it... or
  // stay, if the tangent frame is the same function of the same N.
  pcl::Texlet failed = t;
  failed.support = 0;
  pcl::Texlet moved;
  transformTexlet (failed, pose, moved);
  EXPECT_EQ (moved.x, failed.x); // failed texlets are left as they are
}

TEST (TexletMerge, KeepsValidTexletsWithTheirSensor)
{
  pcl::PointCloud<pcl::Texlet> a, b;
  a.push_back (makeTexlet (Eigen::Vector3d (0, 0, 1), Eigen::Vector3d (0, 0, -1)));
  a.push_back (pcl::Texlet ()); // support 0
  a.push_back (makeTexlet (Eigen::Vector3d (0.1, 0, 1), Eigen::Vector3d (0, 0, -1)));
  b.push_back (makeTexlet (Eigen::Vector3d (0, 0.1, 2), Eigen::Vector3d (0, 0, -1)));
  pcl::Texlet nan = makeTexlet (Eigen::Vector3d (0, 0, 1), Eigen::Vector3d (0, 0, -1));
  nan.normal_y = std::numeric_limits<float>::quiet_NaN ();
  b.push_back (nan);
  Eigen::Isometry3d shift = Eigen::Isometry3d::Identity ();
  shift.translation () = Eigen::Vector3d (0, 0, -1);
  MergedTexlets m;
  m.add (a, Eigen::Isometry3d::Identity (), 0);
  m.add (b, shift, 1);
  ASSERT_EQ (m.texlets.size (), 3u);
  EXPECT_EQ (m.texlets.width, 3u);
  EXPECT_EQ (m.texlets.height, 1u);
  EXPECT_TRUE (m.texlets.is_dense);
  EXPECT_EQ (m.sensor, (std::vector<std::uint16_t>{0, 0, 1}));
  EXPECT_EQ (m.dropped, 2u);
  EXPECT_EQ (m.countFrom (0), 2u);
  EXPECT_EQ (m.countFrom (1), 1u);
  EXPECT_FLOAT_EQ (m.texlets[2].z, 1.0f);
  EXPECT_FLOAT_EQ (m.texlets[2].y, 0.1f);
}

TEST_F (RelationFiles, ExtrinsicsRoundTripAndBothPoseLayouts)
{
  std::vector<SensorExtrinsics> in (2);
  in[0].name = "sensor_0";
  in[1].name = "kinect b";
  in[1].pose.linear () = Eigen::AngleAxisd (1.1, Eigen::Vector3d (0.3, -1, 0.2).normalized ()).toRotationMatrix ();
  in[1].pose.translation () = Eigen::Vector3d (0.5, -0.25, 1.75);
  const std::string path = (dir_ / "extrinsics.yaml").string ();
  saveExtrinsicsYaml (path, in);
  const auto out = loadExtrinsicsYaml (path);
  ASSERT_EQ (out.size (), 2u);
  EXPECT_EQ (out[1].name, "kinect b");
  EXPECT_TRUE (out[1].pose.matrix ().isApprox (in[1].pose.matrix (), 1e-15));
  EXPECT_EQ (temp_.entries (), std::vector<std::string>{"extrinsics.yaml"}); // no temporary file left

  const auto rows = loadExtrinsicsYaml (write ("rows.yaml", "sensors:\n  - name: a\n    pose: [[0, -1, 0, 0.5], [1, 0, 0, 0], "
                                                            "[0, 0, 1, 1.0], [0, 0, 0, 1]]\n"));
  ASSERT_EQ (rows.size (), 1u);
  EXPECT_NEAR ((rows[0].pose * Eigen::Vector3d (1, 0, 0) - Eigen::Vector3d (0.5, 1, 1)).norm (), 0.0, 1e-15);
}

TEST_F (RelationFiles, BadExtrinsicsAreNamed)
{
  EXPECT_NE (ioError ([&] { loadExtrinsicsYaml ((dir_ / "missing.yaml").string ()); }).find ("missing.yaml"),
             std::string::npos);
  EXPECT_NE (ioError ([&] { loadExtrinsicsYaml (write ("bad.yaml", "sensors: [a: {")); }).find ("not valid YAML"),
             std::string::npos);
  EXPECT_NE (ioError ([&] { loadExtrinsicsYaml (write ("none.yaml", "cameras: []\n")); }).find ("'sensors'"),
             std::string::npos);
  EXPECT_NE (ioError ([&] {
               loadExtrinsicsYaml (write ("short.yaml", "sensors:\n  - {name: a, pose: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, "
                                                        "0, 0, 0, 0]}\n"));
             }).find ("got 15"),
             std::string::npos);
  EXPECT_NE (ioError ([&] {
               loadExtrinsicsYaml (write ("scaled.yaml", "sensors:\n  - {name: a, pose: [2, 0, 0, 0, 0, 1, 0, 0, 0, 0, "
                                                         "1, 0, 0, 0, 0, 1]}\n"));
             }).find ("not orthonormal"),
             std::string::npos);
  EXPECT_NE (ioError ([&] {
               loadExtrinsicsYaml (write ("mirror.yaml", "sensors:\n  - {name: a, pose: [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, "
                                                         "1, 0, 0, 0, 0, 1]}\n"));
             }).find ("determinant"),
             std::string::npos);
  EXPECT_NE (ioError ([&] {
               loadExtrinsicsYaml (write ("text.yaml", "sensors:\n  - {name: a, pose: [x, 0, 0, 0, 0, 1, 0, 0, 0, 0, "
                                                       "1, 0, 0, 0, 0, 1]}\n"));
             }).find ("16 numbers"),
             std::string::npos);
  const std::string twice = "sensors:\n  - {name: a, pose: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}\n"
                            "  - {name: a, pose: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}\n";
  EXPECT_NE (ioError ([&] { loadExtrinsicsYaml (write ("twice.yaml", twice)); }).find ("twice"), std::string::npos);
  EXPECT_NE (ioError ([&] { loadExtrinsicsYaml (write ("noname.yaml", "sensors:\n  - {pose: [1]}\n")); }).find ("'name'"),
             std::string::npos);
}

TEST_F (RelationFiles, MetaYamlPoseIsTheSimulatorsSensorPose)
{
  const sim::SceneSetup setup = sim::boxSetup (1.0, 45.0, 3);
  sim::DepthSensor model = sim::DepthSensor::kinect (64, 48);
  const sim::KinectSimulator simulator (setup.scene, setup.sensors (model), sim::SimulationSettings (), 1);
  for (std::size_t k = 0; k < 3; ++k)
  {
    const std::string meta = write ("meta" + std::to_string (k) + ".yaml", sim::simulationMetaYaml (setup, simulator, k, 0, 1));
    Eigen::Isometry3d pose;
    ASSERT_TRUE (poseFromMetaYaml (meta, pose));
    EXPECT_TRUE (pose.matrix ().isApprox (setup.sensor_poses[k].matrix (), 1e-9)) << k;
    EXPECT_EQ (projectorsFromMetaYaml (meta, 7), 3);
  }
  Eigen::Isometry3d pose;
  EXPECT_FALSE (poseFromMetaYaml ((dir_ / "none.yaml").string (), pose));
  EXPECT_FALSE (poseFromMetaYaml (write ("nopose.yaml", "scene: box\n"), pose));
  EXPECT_EQ (projectorsFromMetaYaml (write ("noproj.yaml", "scene: box\n"), 1), 1);
  EXPECT_THROW (projectorsFromMetaYaml (write ("zero.yaml", "projectors: 0\n")), pcl::IOException);
  EXPECT_THROW (poseFromMetaYaml (write ("badpose.yaml", "sensor_pose: [1, 2]\n"), pose), pcl::IOException);
}

// ---------------------------------------------------------------------------------------------
// Known object

TEST (KnownObject, PaperBoxHasTable2)
{
  const KnownObject box = paperBoxObject ();
  ASSERT_EQ (box.relations.size (), 5u);
  const double expect[5][3] = {{0, 240, 240}, {180, 128, 128}, {180, 112, 112}, {0, 0, 0}, {90, 0, 240}};
  for (int i = 0; i < 5; ++i)
  {
    EXPECT_DOUBLE_EQ (box.relations[i].angle_deg, expect[i][0]);
    EXPECT_NEAR (box.relations[i].distance_min_m * 1000, expect[i][1], 1e-9);
    EXPECT_NEAR (box.relations[i].distance_max_m * 1000, expect[i][2], 1e-9);
  }
  EXPECT_DOUBLE_EQ (box.angle_tol_deg, 10.0);
  EXPECT_DOUBLE_EQ (box.distance_tol_m, 0.005);
  EXPECT_EQ (box.faces.size (), 6u);
  EXPECT_THROW (boxOnPlate (Eigen::Vector3d (0.1, 0.1, 0.1), 0.05), pcl::BadArgumentException);
  EXPECT_THROW (boxOnPlate (Eigen::Vector3d (0.1, -0.1, 0.1), 0.5), pcl::BadArgumentException);
}

TEST (KnownObject, LabelsByPositionOnTheFaces)
{
  const KnownObject box = paperBoxObject ();
  EXPECT_EQ (labelPoint (box, {0.01, 0.02, 0.2405}), box.faceIndex ("top"));
  EXPECT_EQ (labelPoint (box, {0.064, 0.0, 0.1}), box.faceIndex ("side +x"));
  EXPECT_EQ (labelPoint (box, {-0.0655, 0.05, 0.2}), box.faceIndex ("side -x"));
  EXPECT_EQ (labelPoint (box, {0.0, 0.056, 0.01}), box.faceIndex ("side +y"));
  EXPECT_EQ (labelPoint (box, {0.0, -0.056, 0.23}), box.faceIndex ("side -y"));
  EXPECT_EQ (labelPoint (box, {0.15, -0.15, 0.001}), box.faceIndex ("ground"));
  EXPECT_EQ (labelPoint (box, {0.3, 0.0, 0.0}), -1);   // beyond the plate
  EXPECT_EQ (labelPoint (box, {0.0, 0.0, 0.3}), -1);   // above the box
  EXPECT_EQ (labelPoint (box, {0.0, 0.0, 0.12}), -1);  // inside, far from every face
  // faceQuality on exact texlets: no error at all.
  std::vector<int> labels;
  const auto cloud = texletsOnFaces (box, 3, &labels);
  EXPECT_EQ (labelTexlets (cloud, box), labels);
  for (const auto &q : faceQuality (cloud, labels, box))
  {
    EXPECT_GT (q.texlets, 0u) << q.name;
    EXPECT_LT (q.rms_distance_mm, 1e-3) << q.name;
    EXPECT_LT (q.rms_angle_deg, 0.05) << q.name;
    EXPECT_LT (q.median_angle_deg, 0.05) << q.name;
  }
}

TEST_F (RelationFiles, ObjectFilesAndTheirErrors)
{
  const KnownObject a = loadKnownObjectYaml (write ("box.yaml", "box: {size_mm: [100, 80, 200], plate_mm: 300}\n"
                                                                "tolerance: {angle_deg: 5, distance_mm: 3}\n"));
  ASSERT_EQ (a.relations.size (), 5u);
  EXPECT_NEAR (a.relations[0].distance_min_m, 0.2, 1e-12);
  EXPECT_NEAR (a.relations[1].distance_min_m, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ (a.angle_tol_deg, 5.0);
  EXPECT_NEAR (a.distance_tol_m, 0.003, 1e-12);
  EXPECT_EQ (a.faces.size (), 6u);

  const KnownObject b = loadKnownObjectYaml (
      write ("explicit.yaml", "relations:\n  - {name: steps, angle_deg: 0, distance_mm: 50}\n"
                              "  - {angle_deg: 90, distance_mm: [0, 100]}\n"
                              "faces:\n  - {name: step, centre_mm: [0, 0, 50], normal: [0, 0, 2], axis_u: [1, 0, 0], "
                              "half_size_mm: [20, 30]}\n"));
  ASSERT_EQ (b.relations.size (), 2u);
  EXPECT_EQ (b.relations[0].name, "steps");
  EXPECT_NEAR (b.relations[1].distance_max_m, 0.1, 1e-12);
  ASSERT_EQ (b.faces.size (), 1u);
  EXPECT_NEAR (b.faces[0].normal.norm (), 1.0, 1e-12);
  EXPECT_EQ (labelPoint (b, {0.01, 0.025, 0.05}), 0);

  const auto err = [&] (const std::string &name, const std::string &text) {
    return ioError ([&] { loadKnownObjectYaml (write (name, text)); });
  };
  EXPECT_NE (err ("empty.yaml", "name: x\n").find ("no relations"), std::string::npos);
  EXPECT_NE (err ("angle.yaml", "relations: [{angle_deg: 200, distance_mm: 1}]\n").find ("between 0 and 180"),
             std::string::npos);
  EXPECT_NE (err ("range.yaml", "relations: [{angle_deg: 0, distance_mm: [5, 1]}]\n").find ("min <= max"),
             std::string::npos);
  EXPECT_NE (err ("plate.yaml", "box: {size_mm: [100, 80, 200], plate_mm: 50}\n").find ("plate"), std::string::npos);
  EXPECT_NE (err ("nosize.yaml", "box: {plate_mm: 50}\n").find ("size_mm"), std::string::npos);
  EXPECT_NE (err ("face.yaml", "box: {size_mm: [1, 1, 1], plate_mm: 5}\nfaces: [{centre_mm: [0, 0, 0], normal: [0, 0, 1], "
                               "axis_u: [0, 0, 1], half_size_mm: [1, 1]}]\n")
                 .find ("orthogonal"),
             std::string::npos);
  EXPECT_NE (err ("tol.yaml", "box: {size_mm: [1, 1, 1], plate_mm: 5}\ntolerance: {angle_deg: 0}\n").find ("positive"),
             std::string::npos);
  EXPECT_NE (ioError ([&] { loadKnownObjectYaml ((dir_ / "absent.yaml").string ()); }).find ("absent.yaml"),
             std::string::npos);
}
