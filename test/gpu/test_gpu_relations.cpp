/*
 * The CUDA backend of the texlet relations (gpu::accumulateRelations) against the CPU
 * path (pcl::texlet::accumulateRelations, OpenMP), bin for bin, on texlets of the simulated
 * interference setup (three sensors around the paper's box). Without a CUDA device the
 * comparisons skip, and the backend is checked to refuse with a CudaError.
 *
 * Exactness: distances are the same float operations on both sides (--fmad=false), so every
 * count that depends on distances or labels only must agree exactly. The angle comes from
 * CUDA's acosf on the device and the host's acosf on the CPU, which may differ by an ulp or two;
 * a relation whose angle lies that close to a bin edge or an inlier box's angle edge may land
 * one bin over. The tests count those borderline relations on the host and allow no more
 * differences than that, and check that they are rare (so the bound is not vacuous).
 */
#include "interference_study.h" // (Random123 before CUDA's headers: see gpu/random123_host_sincospi.h)
#include <pcl_texlet/relations/texlet_relations.h>

#include <pcl_texlet/gpu/containers/cuda_error.h>
#include <pcl_texlet/gpu/texlet_relations.h>

#include "relation_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace kn = pcl::texlet::kernels;
using namespace pcl::texlet;

namespace
{

using pcl_texlet_test::absoluteDifference;
using pcl_texlet_test::borderlineRelations;

struct Comparison
{
  RelationStatistics cpu, gpu;
  std::uint64_t borderline = 0;
};

/** The same relations on the CPU and on the GPU backend, with the borderline count. */
Comparison
compare (const pcl::PointCloud<pcl::Texlet> &texlets, const KnownObject &object, RelationParameters params,
         const std::vector<int> &labels)
{
  Comparison c;
  c.cpu = accumulateRelations (texlets, object, params, labels);
  params.backend = [&c] (const kn::RelationInput<float> &in, const kn::RelationConfig &config,
                         kn::RelationCounts<std::uint64_t> &counts) {
    c.borderline = borderlineRelations (in, config);
    gpu::accumulateRelations (in, config, counts);
  };
  c.gpu = accumulateRelations (texlets, object, params, labels);
  return c;
}

void
expectSameCounts (const Comparison &c)
{
  const RelationStatistics &cpu = c.cpu, &gpu = c.gpu;
  // Exact: what does not depend on the angle.
  EXPECT_EQ (gpu.texlets, cpu.texlets);
  EXPECT_EQ (gpu.relation_count, cpu.relation_count);
  EXPECT_EQ (gpu.outside_histogram, cpu.outside_histogram);
  EXPECT_EQ (gpu.label_pairs, cpu.label_pairs);
  ASSERT_EQ (gpu.histogram.size (), cpu.histogram.size ());
  // Bin for bin, up to the borderline relations (each moved relation differs in two bins).
  const std::uint64_t moved = absoluteDifference (gpu.histogram, cpu.histogram);
  EXPECT_LE (moved, 2 * c.borderline) << moved << " counts differ, " << c.borderline << " borderline relations";
  EXPECT_LE (c.borderline, cpu.relation_count / 100) << "borderline relations should be rare";
  EXPECT_LE (absoluteDifference (gpu.relation_hits, cpu.relation_hits), 2 * c.borderline);
  EXPECT_LE (absoluteDifference (gpu.label_inliers, cpu.label_inliers), 2 * c.borderline);
  EXPECT_LE (gpu.inliers > cpu.inliers ? gpu.inliers - cpu.inliers : cpu.inliers - gpu.inliers, c.borderline);
  std::uint64_t total = 0;
  for (auto v : gpu.histogram)
    total += v;
  EXPECT_EQ (total + gpu.outside_histogram, gpu.relation_count);
}

class GpuRelations : public ::testing::Test
{
protected:
  static void
  SetUpTestSuite ()
  {
    if (gpu::cudaDeviceCount () == 0)
      return;
    SimulatedSetup setup;
    setup.width = 320;
    setup.height = 240;
    setup.seed = 7;
    const auto recordings = simulateInterferenceRecordings (setup, 2);
    texlets_ = new pcl::PointCloud<pcl::Texlet> (extractMergedTexlets (recordings, studyTexletParameters (6, 6)).texlets);
    object_ = new KnownObject (simulatedObject (setup));
    labels_ = new std::vector<int> (labelTexlets (*texlets_, *object_));
  }
  static void
  TearDownTestSuite ()
  {
    delete texlets_;
    delete object_;
    delete labels_;
  }

  void
  SetUp () override
  {
    if (gpu::cudaDeviceCount () == 0)
      GTEST_SKIP () << "no CUDA device: the GPU relations were compiled but are not run here";
  }

  static pcl::PointCloud<pcl::Texlet> *texlets_;
  static KnownObject *object_;
  static std::vector<int> *labels_;
};
pcl::PointCloud<pcl::Texlet> *GpuRelations::texlets_ = nullptr;
KnownObject *GpuRelations::object_ = nullptr;
std::vector<int> *GpuRelations::labels_ = nullptr;

} // namespace

TEST_F (GpuRelations, HistogramMatchesTheCpuBinForBinOnSimulatedTexlets)
{
  ASSERT_GT (texlets_->size (), 2000u);
  const RelationParameters params; // the paper's axes: 2 mm x 1 degree bins, in shared memory
  const auto launch = gpu::relationLaunch (static_cast<int> (texlets_->size ()), kn::RelationConfig ());
  EXPECT_TRUE (launch.shared_histogram);
  const Comparison c = compare (*texlets_, *object_, params, *labels_);
  expectSameCounts (c);
  // The study's figure: the inlier percentage, which the paper reports.
  EXPECT_NEAR (c.gpu.inlierPercent (), c.cpu.inlierPercent (), 100.0 * c.borderline / c.cpu.relation_count + 1e-12);
  EXPECT_GT (c.cpu.inliers, 0u);
}

TEST_F (GpuRelations, WithoutLabels)
{
  const Comparison c = compare (*texlets_, *object_, RelationParameters (), {});
  expectSameCounts (c);
  EXPECT_TRUE (c.gpu.label_pairs.empty ());
}

TEST_F (GpuRelations, HistogramTooBigForSharedMemoryUsesGlobalAtomics)
{
  RelationParameters params;
  params.axes.distance_bins = 20000; // 20000 x 180 bins: 14 MB, beyond any block's shared memory
  kn::RelationConfig config;
  config.axes = params.axes;
  EXPECT_FALSE (gpu::relationLaunch (1000, config).shared_histogram);
  expectSameCounts (compare (*texlets_, *object_, params, *labels_));
}

TEST_F (GpuRelations, FewAndNoTexlets)
{
  pcl::PointCloud<pcl::Texlet> few;
  for (int k = 0; k < 3; ++k)
    few.push_back ((*texlets_)[k]);
  expectSameCounts (compare (few, *object_, RelationParameters (), {}));
  pcl::PointCloud<pcl::Texlet> none;
  const Comparison c = compare (none, *object_, RelationParameters (), {});
  EXPECT_EQ (c.gpu.relation_count, 0u);
  EXPECT_EQ (c.gpu.histogram, c.cpu.histogram);
}

TEST (GpuRelationsWithoutDevice, TheBackendSaysThereIsNoDevice)
{
  if (gpu::cudaDeviceCount () > 0)
    GTEST_SKIP () << "a CUDA device is present";
  pcl::PointCloud<pcl::Texlet> texlets;
  pcl::Texlet t;
  t.x = t.y = 0.0f;
  t.z = 1.0f;
  t.normal_x = t.normal_y = 0.0f;
  t.normal_z = -1.0f;
  t.support = 10;
  texlets.push_back (t);
  t.z = 1.1f;
  texlets.push_back (t);
  RelationParameters params;
  params.backend = [] (const auto &in, const auto &config, auto &counts) {
    gpu::accumulateRelations (in, config, counts);
  };
  try
  {
    accumulateRelations (texlets, paperBoxObject (), params);
    FAIL () << "no exception without a device";
  }
  catch (const gpu::CudaError &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("no CUDA-capable device"), std::string::npos) << e.what ();
  }
}
