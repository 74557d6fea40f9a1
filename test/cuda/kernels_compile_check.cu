/*
 * Compiles the header-only kernels for the device: the CPU path's math must build under nvcc
 * unchanged, so the CUDA backend can run it. Built whenever CUDA is found (CI has nvcc but no
 * GPU, so this is a compile check; the GPU tests of the CUDA backend run it).
 */
#include <pcl_texlet/kernels/depth_sensor.h>
#include <pcl_texlet/kernels/effect_terms.h>
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/plumb_bob.h>
#include <pcl_texlet/kernels/ray_cast.h>
#include <pcl_texlet/kernels/sensor_effects.h>
#include <pcl_texlet/kernels/texlet_kernel.h>

using namespace pcl::texlet::kernels;

template <typename S>
__global__ void
texletKernelCompileCheck (Neighbourhood<S> nb, TexletSettings<S> st, unsigned char *mask, S *work,
                          TexletResult<S> *out, int *centres)
{
  const HexGrid g = makeHexGrid (640, 480, 6);
  int u, v;
  hexCentre (g, threadIdx.x, u, v);
  double x, y;
  undistortPlumbBob (PlumbBob{0.1, -0.2, 0.001, 0.001, 0.05}, 0.01 * u, 0.01 * v, x, y);
  centres[threadIdx.x] = v * 640 + u + pixelDiscSize (6) + static_cast<int> (x + y);
  computeTexlet (nb, st, threadIdx.x, mask, work, out[threadIdx.x]);
}

template __global__ void texletKernelCompileCheck<float> (Neighbourhood<float>, TexletSettings<float>, unsigned char *,
                                                          float *, TexletResult<float> *, int *);
template __global__ void texletKernelCompileCheck<double> (Neighbourhood<double>, TexletSettings<double>,
                                                           unsigned char *, double *, TexletResult<double> *, int *);

/** The simulator's per-pixel path: ray casting through a BVH, the effects' terms, one frame. */
__global__ void
simulatorKernelCompileCheck (SensorPixelMaps maps, SensorFrameSettings frame, const BvhNode<double> *nodes,
                             const Triangle<double> *triangles, VerticalStripes stripes, DepthDistortion distortion,
                             Radial radial, IncidenceAngle incidence, Interference interference, TemporalDrift drift,
                             Intrinsics intrinsics, float *columns, double *values, std::uint16_t *depth)
{
  const int u = threadIdx.x, v = blockIdx.x;
  const Vec3<double> origin = {0, 0, 0}, direction = {(u - 319.5) / 580.0, (v - 239.5) / 580.0, 1.0};
  double t = 1e30;
  std::int32_t triangle = -1;
  rayBvh (nodes, triangles, origin, direction, 1e-9, t, triangle);
  double box_t, sign;
  int axis;
  const Vec3<double> lo = {-1, -1, 1}, hi = {1, 1, 2};
  rayBoxEntry (origin, direction, lo, hi, box_t, axis, sign);
  if (u == 0)
    stripeColumnOffsets (stripes, 1u, 0u, frame.frame, maps.width, columns);
  double fx = 580, fy = 580, cx = 319.5, cy = 239.5;
  labelledIntrinsics (intrinsics, fx, fy, cx, cy);
  values[v * maps.width + u] = t + box_t + distortionOffset (distortion, 1u, 0u, u, v, cx, cy, 400.0) *
                                               radialFactor (radial, 100.0) * incidenceFactor (incidence, 0.5) *
                                               interferenceFactor (interference, 1.0) +
                               interferenceDropout (interference, 1.0) + driftOffset (drift, frame.frame) +
                               quantiseDisparity (depthStep (1.5, 0.125, 43.5), 0.125) +
                               (incidenceTooOblique (incidence, 0.1) ? 1.0 : 0.0);
  depth[v * maps.width + u] = simulateDepthPixel (maps, frame, u, v);
}

/** The noise model's effect terms (the model lab's per-pixel math). */
__global__ void
effectTermsCompileCheck (const double *grid, double *out)
{
  const double z = 1000.0 + threadIdx.x, J = depthPerDisparityMm (z, 43.5);
  double mean = 0, var = 0;
  quantizedMoments (43.5e3 / z, 0.03, 0.125, mean, var);
  int index[4];
  double weight[4];
  bilinearGridWeights (17, 13, 640, 480, 100.0, 200.0, index, weight);
  out[threadIdx.x] = J * (mean + var) + radialVarianceFactor (0.3, threadIdx.x, 400.0) +
                     incidenceVarianceFactor (0.5, 0.7) + interferenceVarianceFactor (1.0, 3.0) +
                     driftDisparityOffset (0.2, 10.0, threadIdx.x) + lateralVariance (1.0, 1.5, 2.0) +
                     bilinearGrid (grid, 17, 13, 640, 480, 100.0, 200.0) + weight[0] * index[0];
}
