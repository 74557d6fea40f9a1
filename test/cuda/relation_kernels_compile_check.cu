/*
 * Compiles the texlet-relation kernels for the device (the multi-sensor study's pair math), so
 * that a CUDA backend can run one row of pairs per thread unchanged. A compile check only:
 * the CPU driver gives every thread its own counters; a device version would give each block
 * its own (in shared memory, with atomic increments).
 */
#include <pcl_texlet/kernels/relation_histogram.h>
#include <pcl_texlet/kernels/texlet_relation.h>

using namespace pcl::texlet::kernels;

__global__ void
relationRowCompileCheck (RelationInput<float> in, RelationConfig config, RelationCounts<unsigned long long> *counts,
                         float *angles)
{
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= in.count)
    return;
  accumulateRelationRow (i, in, config, counts[i]);
  angles[i] = normalAngleDeg (in.normal[i], in.normal[0]) + normalDistance (in.centre[i], in.centre[0], in.normal[0]) +
              static_cast<float> (relationBin (config.axes, 0.1f, 45.0f) +
                                  matchRelationBox (config.boxes, config.box_count, 0.1f, 90.0f));
}
