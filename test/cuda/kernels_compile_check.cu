/*
 * Compiles the header-only kernels for the device: the CPU path's math must build under nvcc
 * unchanged, so the CUDA backend can run it. Built whenever CUDA is found (CI has nvcc but no
 * GPU, so this is a compile check; the GPU tests of the CUDA backend run it).
 */
#include <pcl_texlet/kernels/depth_sensor.h>
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/plumb_bob.h>
#include <pcl_texlet/kernels/ray_cast.h>
#include <pcl_texlet/kernels/texlet_kernel.h>
// Every effect file: its generative hooks and closed forms must run on the device.
#include <pcl_texlet/noise/effects/axial_quadratic.h>
#include <pcl_texlet/noise/effects/covariate_intensity.h>
#include <pcl_texlet/noise/effects/depth_distortion.h>
#include <pcl_texlet/noise/effects/disparity_quantization.h>
#include <pcl_texlet/noise/effects/incidence_angle.h>
#include <pcl_texlet/noise/effects/interference.h>
#include <pcl_texlet/noise/effects/intrinsics.h>
#include <pcl_texlet/noise/effects/lateral_noise.h>
#include <pcl_texlet/noise/effects/radial.h>
#include <pcl_texlet/noise/effects/row_bands.h>
#include <pcl_texlet/noise/effects/temporal_drift.h>
#include <pcl_texlet/noise/effects/vertical_stripes.h>

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

namespace fx = pcl::texlet::effects;

/** The simulator's per-pixel path: ray casting through a BVH, every effect's generative hooks,
  * one frame.
  */
__global__ void
simulatorKernelCompileCheck (SensorPixelMaps maps, SensorFrameSettings frame, const BvhNode<double> *nodes,
                             const Triangle<double> *triangles, float *columns, double *values, std::uint16_t *depth)
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

  fx::SimSensor sensor;
  sensor.width = maps.width;
  sensor.height = maps.height;
  sensor.cx = 319.5;
  sensor.cy = 239.5;
  sensor.r_corner = 400.0;
  sensor.fb = 43.5;
  fx::SimPixel px;
  px.u = u;
  px.v = v;
  px.radius_px = 100.0;
  px.depth_m = t;
  px.cos_incidence = 0.5;
  px.foreign_load = 1.0;
  if (u == 0)
    fx::VerticalStripes::addColumnOffsets (fx::VerticalStripes::SimParameters (), sensor, frame.frame, columns);
  fx::DisparityQuantization::frameSettings (fx::DisparityQuantization::SimParameters (), frame);
  fx::Interference::frameSettings (fx::Interference::SimParameters (), frame);
  fx::LateralNoise::frameSettings (fx::LateralNoise::SimParameters (), frame);
  double fx_px = 580, fy_px = 580, cx = 319.5, cy = 239.5;
  fx::Intrinsics::label (fx::Intrinsics::SimParameters (), fx_px, fy_px, cx, cy);
  const double variance = fx::AxialQuadratic::disparityVariance (fx::AxialQuadratic::SimParameters (), px);
  const double factor = fx::Radial::sdFactor (fx::Radial::SimParameters (), px) *
                        fx::IncidenceAngle::sdFactor (fx::IncidenceAngle::SimParameters (), px) *
                        fx::Interference::sdFactor (fx::Interference::SimParameters (), px);
  values[v * maps.width + u] =
      t + box_t + variance * factor + fx::DepthDistortion::disparityOffset (fx::DepthDistortion::SimParameters (), sensor, px) +
      fx::Interference::dropout (fx::Interference::SimParameters (), px) +
      fx::TemporalDrift::frameOffset (fx::TemporalDrift::SimParameters (), frame.frame) +
      quantiseDisparity (depthStep (1.5, 0.125, 43.5), 0.125) + relativeIrradiance (0.5, 1.0, 0.7, 1.2) + fx_px + cx +
      (fx::IncidenceAngle::readable (fx::IncidenceAngle::SimParameters (), px) ? 1.0 : 0.0);
  depth[v * maps.width + u] = simulateDepthPixel (maps, frame, u, v);
}

/** Every effect's closed-form term (the model lab's and the extractor's per-pixel math). */
__global__ void
effectTermsCompileCheck (const double *grid, double *out)
{
  pcl::texlet::PixelContext ctx;
  ctx.u = 100.0 + threadIdx.x;
  ctx.v = 200.0;
  ctx.radius_px = threadIdx.x;
  ctx.depth_mm = 1000.0 + threadIdx.x;
  ctx.true_depth_mm = ctx.depth_mm;
  ctx.cos_incidence = 0.7;
  ctx.active_projectors = 3.0;
  ctx.frame = threadIdx.x;
  ctx.edge_distance_px = 2.0;
  const fx::NoSettings none{};
  const double p1[1] = {0.3}, p2[2] = {0.2, 10.0};
  double bias = 0, var = fx::AxialQuadratic::variance (p1, none, ctx) + fx::LateralNoise::variance (p2, none, ctx);
  bias += fx::TemporalDrift::bias (p2, none, ctx);
  fx::DepthDistortion::TermSettings grid_settings;
  bias += fx::DepthDistortion::bias (grid, grid_settings, ctx);
  int index[4];
  double weight[4];
  fx::DepthDistortion::biasBasis (grid_settings, 100.0, 200.0, index, weight);
  const double factor = fx::Radial::varianceFactor (p1, fx::Radial::TermSettings (), ctx) *
                        fx::IncidenceAngle::varianceFactor (p1, none, ctx) *
                        fx::Interference::varianceFactor (p1, none, ctx);
  const double knots[4] = {1.0, 0.5, 0.25, 0.1};
  ctx.intensity = 0.4;
  const double grey_factor = fx::CovariateIntensity::varianceFactor (knots, none, ctx);
  ctx.image_height_px = 480;
  const double column = fx::VerticalStripes::columnVariance (p2, none, ctx) + fx::VerticalStripes::frameVariance (p2, none, ctx) +
                        fx::RowBands::rowVariance (p2, none, ctx) + fx::RowBands::rowCorrelationPx (p2, none, ctx);
  var *= factor * grey_factor;
  const double step[1] = {0.125};
  const fx::DisparityQuantization::TermSettings lattice;
  fx::DisparityQuantization::transformMoments (step, lattice, ctx, bias, var);
  double mean = 0, rounded = 0;
  fx::DisparityQuantization::roundingMoments (step, lattice, 43.5e3 / ctx.depth_mm, 0.03, mean, rounded);
  bias += fx::DepthDistortion::biasShape (grid_settings, ctx.depth_mm, 43.5);
  out[threadIdx.x] = bias + var + column + mean + rounded + weight[0] * index[0] + fx::depthPerDisparity (ctx);
}
