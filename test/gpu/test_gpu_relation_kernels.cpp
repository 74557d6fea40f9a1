/*
 * gpu::accumulateRelations against the CPU path's own kernel (kernels::accumulateRelationRow
 * over every row, as pcl::texlet::accumulateRelations runs it), without PCL: this test builds
 * on the device machine with CUDA alone (gpu/build_with_nvcc.sh). Texlets are noisy patches on
 * the faces of the paper's Table 2 box (128 x 112 x 240 mm), labelled by face, with the box's
 * expected relations as inlier boxes (test/gpu/synthetic_box_texlets.h). Without a CUDA device the comparisons skip.
 *
 * Distances agree exactly (both sides the same float operations, --fmad=false); the angle's
 * acosf may differ by an ulp between CUDA and the host, so relations whose angle lies within
 * 1e-4 degrees of a bin or box edge are counted on the host and bound the differences.
 */
#include <pcl_texlet/gpu/containers/cuda_error.h>
#include <pcl_texlet/gpu/texlet_relations.h>
#include <pcl_texlet/kernels/relation_histogram.h>

#include "gpu/synthetic_box_texlets.h"
#include "relation_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace gpu = pcl::texlet::gpu;
namespace kn = pcl::texlet::kernels;

namespace
{

using Texlets = pcl_texlet_test::BoxTexlets;

Texlets
boxTexlets (int per_face, std::uint32_t seed)
{
  return pcl_texlet_test::syntheticBoxTexlets (per_face, seed);
}

std::vector<kn::RelationBox>
boxRelations ()
{
  return pcl_texlet_test::syntheticBoxRelations ();
}

struct Counts
{
  std::vector<std::uint64_t> histogram, box_hits, label_pairs, label_inliers;
  kn::RelationCounts<std::uint64_t> c;

  Counts (const kn::RelationConfig &config)
    : histogram (static_cast<std::size_t> (config.axes.distance_bins) * config.axes.angle_bins, 0),
      box_hits (config.box_count, 0), label_pairs (config.label_count * config.label_count, 0),
      label_inliers (config.label_count * config.label_count, 0)
  {
    c.histogram = histogram.data ();
    c.box_hits = box_hits.data ();
    c.label_pairs = label_pairs.empty () ? nullptr : label_pairs.data ();
    c.label_inliers = label_inliers.empty () ? nullptr : label_inliers.data ();
  }
};

void
compareWithCpu (const Texlets &t, bool labelled, const kn::HistogramAxes &axes)
{
  const std::vector<kn::RelationBox> boxes = boxRelations ();
  kn::RelationConfig config;
  config.axes = axes;
  config.boxes = boxes.data ();
  config.box_count = static_cast<int> (boxes.size ());
  config.label_count = labelled ? 5 : 0;
  const kn::RelationInput<float> in = t.input (labelled);

  Counts cpu (config), gpu (config);
  for (int i = 0; i < in.count; ++i)
    kn::accumulateRelationRow (i, in, config, cpu.c);
  gpu::accumulateRelations (in, config, gpu.c);
  const std::uint64_t edge = pcl_texlet_test::borderlineRelations (in, config);

  EXPECT_EQ (gpu.c.relations, cpu.c.relations);
  EXPECT_EQ (gpu.c.relations, std::uint64_t (in.count) * (in.count - 1));
  EXPECT_EQ (gpu.c.outside_histogram, cpu.c.outside_histogram);
  EXPECT_EQ (gpu.label_pairs, cpu.label_pairs);
  EXPECT_LE (pcl_texlet_test::absoluteDifference (gpu.histogram, cpu.histogram), 2 * edge) << edge << " borderline relations";
  EXPECT_LE (pcl_texlet_test::absoluteDifference (gpu.box_hits, cpu.box_hits), 2 * edge);
  EXPECT_LE (pcl_texlet_test::absoluteDifference (gpu.label_inliers, cpu.label_inliers), 2 * edge);
  EXPECT_LE (gpu.c.inliers > cpu.c.inliers ? gpu.c.inliers - cpu.c.inliers : cpu.c.inliers - gpu.c.inliers, edge);
  EXPECT_LE (edge, cpu.c.relations / 100) << "borderline relations should be rare";
  EXPECT_GT (cpu.c.inliers, cpu.c.relations / 4) << "a box's texlets are mostly inliers";
}

class GpuRelationKernels : public ::testing::Test
{
protected:
  void
  SetUp () override
  {
    if (gpu::cudaDeviceCount () == 0)
      GTEST_SKIP () << "no CUDA device: the GPU relations were compiled but are not run here";
  }
};

} // namespace

TEST_F (GpuRelationKernels, SharedMemoryHistogramMatchesTheCpuKernel)
{
  const Texlets t = boxTexlets (600, 1);
  kn::HistogramAxes axes; // 150 x 180 bins: the paper's, in shared memory
  kn::RelationConfig config;
  config.axes = axes;
  EXPECT_TRUE (gpu::relationLaunch (3000, config).shared_histogram);
  compareWithCpu (t, true, axes);
  compareWithCpu (t, false, axes);
}

TEST_F (GpuRelationKernels, GlobalAtomicsHistogramMatchesTheCpuKernel)
{
  kn::HistogramAxes axes;
  axes.distance_bins = 20000; // 3.6 million bins: beyond shared memory
  kn::RelationConfig config;
  config.axes = axes;
  EXPECT_FALSE (gpu::relationLaunch (3000, config).shared_histogram);
  compareWithCpu (boxTexlets (300, 2), true, axes);
}

TEST_F (GpuRelationKernels, ManyRowsPerBlockStayBelowTheCounterLimit)
{
  // The grid grows with n so that no block's 32-bit counters can overflow.
  kn::RelationConfig config;
  const auto launch = gpu::relationLaunch (2000000, config);
  const long long rows = (2000000ll + launch.blocks - 1) / launch.blocks;
  EXPECT_LT (rows * 2 * 2000000ll, 1ll << 31);
}

TEST (GpuRelationKernelsInput, BadConfigurationIsRefused)
{
  const Texlets t = boxTexlets (10, 3);
  kn::RelationConfig config;
  Counts counts (config);
  config.axes.distance_bins = 0;
  EXPECT_THROW (gpu::accumulateRelations (t.input (false), config, counts.c), std::invalid_argument);
  config.axes.distance_bins = 150;
  config.box_count = kn::kMaxRelationBoxes + 1;
  EXPECT_THROW (gpu::accumulateRelations (t.input (false), config, counts.c), std::invalid_argument);
}

TEST (GpuRelationKernelsInput, WithoutADeviceItSaysSo)
{
  if (gpu::cudaDeviceCount () > 0)
    GTEST_SKIP () << "a CUDA device is present";
  const Texlets t = boxTexlets (10, 4);
  kn::RelationConfig config;
  Counts counts (config);
  try
  {
    gpu::accumulateRelations (t.input (false), config, counts.c);
    FAIL () << "no exception without a device";
  }
  catch (const gpu::CudaError &e)
  {
    EXPECT_EQ (e.code (), cudaErrorNoDevice);
    EXPECT_NE (std::string (e.what ()).find ("no CUDA-capable device"), std::string::npos) << e.what ();
  }
}
