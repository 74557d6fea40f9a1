/*
 * pcl_texlet GPU: texlet relations (normal distance x angle) accumulated on a CUDA device
 * straight into the 2D histogram and the inlier counts, without storing the pairs (the paper's
 * Sect. 4; the CPU driver is pcl::texlet::accumulateRelations, multi_sensor/texlet_relations.h).
 *
 * Needs CUDA's runtime and the kernels' headers only, not PCL. The per-pair math is the CPU
 * path's: kernels::texletRelation, kernels::relationBin and kernels::matchRelationBox. On the
 * device each block keeps its own histogram, box and label counts in shared memory (32-bit
 * counters, fed by shared-memory atomics from all its threads) and adds them into the 64-bit
 * global counts once at the end; a histogram too big for shared memory is counted with global
 * atomics instead.
 *
 * Agreement with the CPU: distances are computed with the same float operations in the same
 * order (this file is compiled with --fmad=false, as the CPU path with -ffp-contract=off), so
 * distance bins agree exactly; the angle uses CUDA's acosf, which may differ from the host's
 * by an ulp or two, so a relation whose angle lies within a few ulps of a bin or box edge may
 * be counted one bin over. test/gpu/test_gpu_relations.cpp bounds the difference by the
 * number of such relations.
 */
#pragma once

#include <pcl_texlet/kernels/relation_histogram.h>

#include <cuda_runtime_api.h>

#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace gpu
{

/** \brief Adds the relations of every pair of \a in (host arrays, unit normals) into \a counts
  * (host arrays sized as kernels::RelationCounts says, zeroed or holding earlier counts), on the
  * current CUDA device: the GPU backend of pcl::texlet::accumulateRelations, whose
  * RelationParameters::backend takes it. The call is synchronous on \a stream.
  * \throws std::invalid_argument for bad axes, more than kernels::kMaxRelationBoxes boxes or
  *         missing arrays; pcl::texlet::gpu::CudaError when there is no device or a CUDA call fails
  */
void
accumulateRelations (const texlet::kernels::RelationInput<float> &in, const texlet::kernels::RelationConfig &config,
                     texlet::kernels::RelationCounts<std::uint64_t> &counts, cudaStream_t stream = nullptr);

/** \brief How accumulateRelations shares out the work (for the benchmark and the tests). */
struct RelationLaunch
{
  int blocks = 0;                ///< one block per row at a time, rows interleaved over blocks
  int threads_per_block = 0;     ///< threads of a block stride over the row's pairs
  std::size_t shared_bytes = 0;  ///< per block
  bool shared_histogram = false; ///< false: histogram too big for shared memory, global atomics
};

/** \brief The launch accumulateRelations would use for \a texlets on the current device.
  * \throws pcl::texlet::gpu::CudaError without a device
  */
RelationLaunch
relationLaunch (int texlets, const texlet::kernels::RelationConfig &config);

} // namespace gpu
} // namespace texlet
} // namespace pcl
