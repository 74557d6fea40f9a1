/*
 * pcl_texlet GPU: texlet relations accumulated on the device (gpu/texlet_relations.h).
 *
 * Work split: block b takes rows i = b, b + gridDim.x, ... (interleaved, so the long first rows
 * and the short last ones spread evenly); the block's threads stride over j > i in the row, so
 * neighbouring threads read neighbouring texlets. Each pair gives both directed relations
 * (n_ij, theta) and (n_ji, theta), as kernels::accumulateRelationRow does on the CPU.
 *
 * Counting: a block's histogram, box hits and label matrices live in shared memory as 32-bit
 * counters bumped with shared atomics; the per-thread inlier and outside counts stay in
 * registers. At the end the block adds its non-zero counters into the 64-bit global arrays with
 * one atomic each. The grid is made large enough that no block can see 2^31 relations, so the
 * 32-bit counters cannot overflow. When the histogram does not fit in shared memory (huge axes),
 * the global arrays are bumped directly.
 */
#include <pcl_texlet/gpu/containers/device_array.h>
#include <pcl_texlet/gpu/texlet_relations.h>
#include <pcl_texlet/kernels/texlet_relation.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pcl
{
namespace texlet
{
namespace gpu
{

namespace kn = texlet::kernels;

namespace
{

constexpr int kThreadsPerBlock = 256;

/** Global 64-bit counts the blocks add into. */
struct GlobalCounts
{
  unsigned long long *histogram;
  unsigned long long *box_hits;
  unsigned long long *label_pairs;   // null without labels
  unsigned long long *label_inliers; // null without labels
  unsigned long long *scalars;       // [0] inliers, [1] outside the histogram
};

/** Sum over the warp, then one atomic per warp. */
__device__ void
addWarpSum (unsigned long long *target, unsigned long long value)
{
  for (int offset = 16; offset > 0; offset /= 2)
    value += __shfl_down_sync (0xffffffffu, value, offset);
  if ((threadIdx.x & 31) == 0 && value != 0)
    atomicAdd (target, value);
}

template <bool SharedHistogram>
__global__ void
relationKernel (kn::RelationInput<float> in, kn::RelationConfig config, GlobalCounts out)
{
  extern __shared__ unsigned int shared_counts[];
  __shared__ kn::RelationBox boxes[kn::kMaxRelationBoxes];

  const int bins = config.axes.distance_bins * config.axes.angle_bins;
  const int labels = in.label ? config.label_count : 0;
  const int cells = labels * labels;
  const int box_count = config.box_count;
  // Shared layout (SharedHistogram): histogram | box hits | label pairs | label inliers.
  unsigned int *s_histogram = shared_counts;
  unsigned int *s_box_hits = shared_counts + (SharedHistogram ? bins : 0);
  unsigned int *s_label_pairs = s_box_hits + box_count;
  unsigned int *s_label_inliers = s_label_pairs + cells;
  const int shared_size = SharedHistogram ? bins + box_count + 2 * cells : 0;

  for (int k = threadIdx.x; k < shared_size; k += blockDim.x)
    shared_counts[k] = 0u;
  for (int b = threadIdx.x; b < box_count; b += blockDim.x)
    boxes[b] = config.boxes[b];
  __syncthreads ();

  unsigned long long inliers = 0, outside = 0;
  for (int i = blockIdx.x; i < in.count; i += gridDim.x)
  {
    const kn::Vec3<float> p_i = in.centre[i], n_i = in.normal[i];
    const int label_i = labels ? in.label[i] : -1;
    for (int j = i + 1 + static_cast<int> (threadIdx.x); j < in.count; j += blockDim.x)
    {
      const kn::PairRelation<float> r = kn::texletRelation (p_i, n_i, in.centre[j], in.normal[j]);
      const int label_j = labels ? in.label[j] : -1;
      const bool labelled = label_i >= 0 && label_j >= 0 && label_i < labels && label_j < labels;
      for (int direction = 0; direction < 2; ++direction)
      {
        const float distance = direction == 0 ? r.distance_ij : r.distance_ji;
        const int bin = kn::relationBin (config.axes, distance, r.angle_deg);
        if (bin < 0)
          ++outside;
        else if (SharedHistogram)
          atomicAdd (&s_histogram[bin], 1u);
        else
          atomicAdd (&out.histogram[bin], 1ull);
        const int box = kn::matchRelationBox (boxes, box_count, distance, r.angle_deg);
        if (box >= 0)
        {
          ++inliers;
          if (SharedHistogram)
            atomicAdd (&s_box_hits[box], 1u);
          else
            atomicAdd (&out.box_hits[box], 1ull);
        }
        if (labelled)
        {
          const int cell = direction == 0 ? label_i * labels + label_j : label_j * labels + label_i;
          if (SharedHistogram)
          {
            atomicAdd (&s_label_pairs[cell], 1u);
            if (box >= 0)
              atomicAdd (&s_label_inliers[cell], 1u);
          }
          else
          {
            atomicAdd (&out.label_pairs[cell], 1ull);
            if (box >= 0)
              atomicAdd (&out.label_inliers[cell], 1ull);
          }
        }
      }
    }
  }

  addWarpSum (&out.scalars[0], inliers);
  addWarpSum (&out.scalars[1], outside);
  if (!SharedHistogram)
    return;
  __syncthreads ();
  for (int k = threadIdx.x; k < shared_size; k += blockDim.x)
  {
    const unsigned int c = shared_counts[k];
    if (c == 0u)
      continue;
    unsigned long long *target;
    if (k < bins)
      target = &out.histogram[k];
    else if (k < bins + box_count)
      target = &out.box_hits[k - bins];
    else if (k < bins + box_count + cells)
      target = &out.label_pairs[k - bins - box_count];
    else
      target = &out.label_inliers[k - bins - box_count - cells];
    atomicAdd (target, static_cast<unsigned long long> (c));
  }
}

void
checkConfig (const kn::RelationConfig &config)
{
  const kn::HistogramAxes &a = config.axes;
  if (!(a.distance_max > 0.0f) || a.distance_bins < 1 || a.angle_bins < 1 || a.distance_bins > 100000 ||
      a.angle_bins > 100000)
    throw std::invalid_argument ("pcl::texlet::gpu::accumulateRelations: the histogram needs a positive distance range and "
                                 "1 to 100000 bins per axis");
  if (config.box_count < 0 || config.box_count > kn::kMaxRelationBoxes || (config.box_count > 0 && !config.boxes))
    throw std::invalid_argument ("pcl::texlet::gpu::accumulateRelations: " + std::to_string (config.box_count) +
                                 " expected relations (0 to " + std::to_string (kn::kMaxRelationBoxes) + ", with boxes)");
  if (config.label_count < 0 || config.label_count > 4096)
    throw std::invalid_argument ("pcl::texlet::gpu::accumulateRelations: label_count " + std::to_string (config.label_count) +
                                 " (0 to 4096)");
}

} // namespace

RelationLaunch
relationLaunch (int texlets, const kn::RelationConfig &config)
{
  checkConfig (config);
  int device = 0, sms = 0, shared_optin = 0;
  PCL_TEXLET_CUDA_CHECK (cudaGetDevice (&device));
  PCL_TEXLET_CUDA_CHECK (cudaDeviceGetAttribute (&sms, cudaDevAttrMultiProcessorCount, device));
  PCL_TEXLET_CUDA_CHECK (cudaDeviceGetAttribute (&shared_optin, cudaDevAttrMaxSharedMemoryPerBlockOptin, device));

  RelationLaunch launch;
  launch.threads_per_block = kThreadsPerBlock;
  const std::size_t bins = static_cast<std::size_t> (config.axes.distance_bins) * config.axes.angle_bins;
  const std::size_t cells = static_cast<std::size_t> (config.label_count) * config.label_count;
  const std::size_t shared_bytes = sizeof (unsigned int) * (bins + config.box_count + 2 * cells);
  const std::size_t static_bytes = sizeof (kn::RelationBox) * kn::kMaxRelationBoxes;
  launch.shared_histogram = shared_bytes + static_bytes <= static_cast<std::size_t> (shared_optin);
  launch.shared_bytes = launch.shared_histogram ? shared_bytes : 0;

  int per_sm = 0;
  if (launch.shared_histogram)
  {
    PCL_TEXLET_CUDA_CHECK (cudaFuncSetAttribute (relationKernel<true>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                                                 static_cast<int> (launch.shared_bytes)));
    PCL_TEXLET_CUDA_CHECK (cudaOccupancyMaxActiveBlocksPerMultiprocessor (&per_sm, relationKernel<true>,
                                                                          kThreadsPerBlock, launch.shared_bytes));
  }
  else
    PCL_TEXLET_CUDA_CHECK (
        cudaOccupancyMaxActiveBlocksPerMultiprocessor (&per_sm, relationKernel<false>, kThreadsPerBlock, 0));
  long long blocks = static_cast<long long> (sms) * std::max (per_sm, 1);
  // No block may count 2^31 relations in its 32-bit counters: it holds at most
  // ceil(n / blocks) rows of at most n - 1 pairs, two relations each.
  const long long n = std::max (texlets, 1);
  const long long limit = (1ll << 31) - 1;
  const long long rows_per_block = std::max (1ll, limit / (2 * n));
  blocks = std::max (blocks, (n + rows_per_block - 1) / rows_per_block);
  blocks = std::min (blocks, n); // a block per row at most
  launch.blocks = static_cast<int> (std::max (blocks, 1ll));
  return launch;
}

void
accumulateRelations (const kn::RelationInput<float> &in, const kn::RelationConfig &config,
                     kn::RelationCounts<std::uint64_t> &counts, cudaStream_t stream)
{
  checkConfig (config);
  if (in.count < 0 || (in.count > 0 && (!in.centre || !in.normal)))
    throw std::invalid_argument ("pcl::texlet::gpu::accumulateRelations: no centre or normal array for " +
                                 std::to_string (in.count) + " texlets");
  const int labels = in.label ? config.label_count : 0;
  const std::size_t bins = static_cast<std::size_t> (config.axes.distance_bins) * config.axes.angle_bins;
  const std::size_t cells = static_cast<std::size_t> (labels) * labels;
  if (!counts.histogram || (config.box_count > 0 && !counts.box_hits) ||
      (cells > 0 && (!counts.label_pairs || !counts.label_inliers)))
    throw std::invalid_argument ("pcl::texlet::gpu::accumulateRelations: the counts' arrays are missing");
  if (cudaDeviceCount () == 0)
    throw CudaError (cudaErrorNoDevice, "cudaGetDeviceCount", __FILE__, __LINE__);

  const std::uint64_t pairs =
      in.count > 1 ? static_cast<std::uint64_t> (in.count) * static_cast<std::uint64_t> (in.count - 1) / 2 : 0;
  counts.relations += 2 * pairs;
  if (pairs == 0)
    return;

  const RelationLaunch launch = relationLaunch (in.count, config);

  DeviceArray<kn::Vec3<float>> centre, normal;
  centre.upload (in.centre, in.count);
  normal.upload (in.normal, in.count);
  DeviceArray<int> label;
  if (labels > 0)
    label.upload (in.label, in.count);
  DeviceArray<kn::RelationBox> boxes;
  if (config.box_count > 0)
    boxes.upload (config.boxes, config.box_count);
  // One zeroed block of 64-bit counters: histogram | box hits | label pairs | label inliers | 2 scalars.
  const std::size_t total = bins + config.box_count + 2 * cells + 2;
  DeviceArray<unsigned long long> global (total);
  PCL_TEXLET_CUDA_CHECK (cudaMemsetAsync (global.ptr (), 0, total * sizeof (unsigned long long), stream));

  kn::RelationInput<float> d_in;
  d_in.centre = centre.ptr ();
  d_in.normal = normal.ptr ();
  d_in.label = labels > 0 ? label.ptr () : nullptr;
  d_in.count = in.count;
  kn::RelationConfig d_config = config;
  d_config.boxes = config.box_count > 0 ? boxes.ptr () : nullptr;
  d_config.label_count = labels;
  GlobalCounts out;
  out.histogram = global.ptr ();
  out.box_hits = out.histogram + bins;
  out.label_pairs = cells ? out.box_hits + config.box_count : nullptr;
  out.label_inliers = cells ? out.label_pairs + cells : nullptr;
  out.scalars = global.ptr () + total - 2;

  if (launch.shared_histogram)
    relationKernel<true><<<launch.blocks, launch.threads_per_block, launch.shared_bytes, stream>>> (d_in, d_config, out);
  else
    relationKernel<false><<<launch.blocks, launch.threads_per_block, 0, stream>>> (d_in, d_config, out);
  PCL_TEXLET_CUDA_CHECK (cudaGetLastError ());
  PCL_TEXLET_CUDA_CHECK (cudaStreamSynchronize (stream));

  std::vector<unsigned long long> host (total);
  global.download (host.data ());
  for (std::size_t k = 0; k < bins; ++k)
    counts.histogram[k] += host[k];
  for (int b = 0; b < config.box_count; ++b)
    counts.box_hits[b] += host[bins + b];
  for (std::size_t c = 0; c < cells; ++c)
  {
    counts.label_pairs[c] += host[bins + config.box_count + c];
    counts.label_inliers[c] += host[bins + config.box_count + cells + c];
  }
  counts.inliers += host[total - 2];
  counts.outside_histogram += host[total - 1];
}

} // namespace gpu
} // namespace texlet
} // namespace pcl
