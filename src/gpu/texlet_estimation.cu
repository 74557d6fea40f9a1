/*
 * pcl_texlet GPU: the CUDA kernels and pcl::texlet::gpu::TexletEstimation's device side.
 *
 * Strategy::Thread: one thread per texlet runs the texlet stages (kernels::frameTexlet), the
 * CPU path's code, so both give the same results to rounding. Each thread's disc (x, y, z,
 * sigma, pixel, mask, SVD work) lives in fixed-size local arrays for discs up to 320 points
 * (radius 10), which the compiler interleaves across the threads of a warp; larger discs use a
 * per-thread slice of a global scratch buffer. Strategy::Warp: texlet_warp_kernel.cuh.
 */
#include <pcl_texlet/gpu/texlet_estimation.h>

#include "texlet_warp_kernel.cuh"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pcl
{
namespace texlet
{
namespace gpu
{
namespace
{

constexpr int kBlock = 128;

/** Scratch bytes of one thread for a disc of \a disc points, 16-byte aligned. */
template <typename S> __host__ __device__ std::size_t
scratchBytes (int disc)
{
  const std::size_t values = 4 * static_cast<std::size_t> (disc) + kernels::texletWorkSize (disc);
  const std::size_t b = sizeof (S) * values + (sizeof (int) + 1) * static_cast<std::size_t> (disc);
  return (b + 15) / 16 * 16;
}

template <typename S>
__device__ kernels::TexletScratch<S>
globalScratch (unsigned char *base, int disc, int thread)
{
  S *p = reinterpret_cast<S *> (base + scratchBytes<S> (disc) * thread);
  int *pixel = reinterpret_cast<int *> (p + 4 * disc + kernels::texletWorkSize (disc));
  return {p, p + disc, p + 2 * disc, p + 3 * disc, p + 4 * disc, pixel, reinterpret_cast<unsigned char *> (pixel + disc)};
}

/** One texlet per thread. Cap > 0: the disc in local arrays of Cap points; 0: global scratch. */
template <typename S, int Cap>
__global__ void __launch_bounds__ (kBlock)
texletKernel (DeviceFrame frame, kernels::FrameSettings<S> fs, kernels::HexGrid grid, unsigned char *scratch,
              DeviceTexlet *out, unsigned int *made)
{
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= grid.size ())
    return;
  int u, v;
  kernels::hexCentre (grid, i, u, v);
  DeviceTexlet t;
  bool ok;
  if constexpr (Cap > 0)
  {
    S x[Cap], y[Cap], z[Cap], s[Cap], work[kernels::texletWorkSize (Cap)];
    int pixel[Cap];
    unsigned char mask[Cap];
    const kernels::TexletScratch<S> ws = {x, y, z, s, work, pixel, mask};
    ok = deviceTexlet (frame, fs, u, v, ws, t);
  }
  else
    ok = deviceTexlet (frame, fs, u, v, globalScratch<S> (scratch, fs.disc.size, i), t);
  out[i] = t;
  if (ok)
    atomicAdd (made, 1u);
}

__global__ void
backProjectKernel (const std::uint16_t *depth, std::size_t depth_step, int width, int height, DeviceCamera camera,
                   DevicePoint *cloud, std::size_t cloud_step)
{
  const int u = blockIdx.x * blockDim.x + threadIdx.x, v = blockIdx.y * blockDim.y + threadIdx.y;
  if (u >= width || v >= height)
    return;
  const std::uint16_t d = reinterpret_cast<const std::uint16_t *> (reinterpret_cast<const char *> (depth) + v * depth_step)[u];
  reinterpret_cast<DevicePoint *> (reinterpret_cast<char *> (cloud) + v * cloud_step)[u] = backProjectPixel (camera, u, v, d);
}

__global__ void
countValidKernel (CloudView cloud, unsigned int *valid)
{
  const int u = blockIdx.x * blockDim.x + threadIdx.x, v = blockIdx.y * blockDim.y + threadIdx.y;
  if (u < cloud.width && v < cloud.height && isValidDevicePoint (cloud.at (u, v)))
    atomicAdd (valid, 1u);
}

} // namespace

void
validateParameters (const texlet::TexletParameters &p)
{
  const std::string problem = texlet::parameterProblem (p);
  if (!problem.empty ())
    throw std::invalid_argument ("pcl::texlet::gpu::TexletEstimation: " + problem);
}

TexletEstimation::TexletEstimation () = default;

void
TexletEstimation::setParameters (const texlet::TexletParameters &params)
{
  validateParameters (params);
  params_ = params;
}

void
TexletEstimation::setCamera (const DeviceCamera &c)
{
  const bool ok = c.kind == DeviceCamera::Pinhole
                      ? c.fx > 0 && c.fy > 0 && std::isfinite (c.fx) && std::isfinite (c.fy) && std::isfinite (c.cx) &&
                            std::isfinite (c.cy) && std::isfinite (c.distortion.k1) && std::isfinite (c.distortion.k2) &&
                            std::isfinite (c.distortion.p1) && std::isfinite (c.distortion.p2) &&
                            std::isfinite (c.distortion.k3)
                      : c.kind == DeviceCamera::OpenNIFov && c.width > 0 && c.height > 0 && c.tan_h > 0 &&
                            c.tan_v > 0 && std::isfinite (c.tan_h) && std::isfinite (c.tan_v);
  if (!ok)
  {
    std::ostringstream msg;
    msg << "pcl::texlet::gpu::TexletEstimation::setCamera: invalid camera (kind " << static_cast<int> (c.kind) << ", fx " << c.fx
        << ", fy " << c.fy << ", cx " << c.cx << ", cy " << c.cy << ", " << c.width << "x" << c.height
        << "): focal lengths and fields of view must be positive and all values finite";
    throw std::invalid_argument (msg.str ());
  }
  camera_ = c;
  has_camera_ = true;
}

void
TexletEstimation::setNoise (const DeviceNoise &n)
{
  bool ok = n.terms >= 0 && n.terms <= DeviceNoise::kMaxTerms && n.min_sigma_mm > 0 && std::isfinite (n.min_sigma_mm);
  for (int i = 0; ok && i < n.terms; ++i)
  {
    const kernels::PolynomialCoefficients &c = n.polynomial[i];
    ok = std::isfinite (c.p00) && std::isfinite (c.p10) && std::isfinite (c.p01) && std::isfinite (c.p20) &&
         std::isfinite (c.p11) && std::isfinite (c.p02);
  }
  if (!ok)
  {
    std::ostringstream msg;
    msg << "pcl::texlet::gpu::TexletEstimation::setNoise: invalid noise model (" << n.terms << " terms, at most "
        << DeviceNoise::kMaxTerms << ", floor " << n.min_sigma_mm << " mm): coefficients must be finite, floor > 0";
    throw std::invalid_argument (msg.str ());
  }
  noise_ = n;
}

namespace
{
/** Shared memory a block of the warp kernel may use without opting in to more. */
constexpr std::size_t kWarpBlockBytes = 48 * 1024;
} // namespace

Strategy
TexletEstimation::effectiveStrategy () const
{
  if (strategy_ != Strategy::Warp || params_.fit == texlet::PlaneFitMethod::SVD)
    return Strategy::Thread;
  const int disc = kernels::pixelDiscSize (params_.radius);
  const std::size_t bytes = warp::kWarpsPerBlock * (precision_ == Precision::Double ? warp::warpBytes<double> (disc)
                                                                                  : warp::warpBytes<float> (disc));
  return bytes <= kWarpBlockBytes ? Strategy::Warp : Strategy::Thread;
}

int
TexletEstimation::texletCount (int width, int height) const
{
  return frameGrid (width, height, params_).size ();
}

void
TexletEstimation::backProject (const DeviceArray2D<std::uint16_t> &depth, DeviceArray2D<DevicePoint> &cloud)
{
  if (depth.empty ())
    throw std::invalid_argument ("pcl::texlet::gpu::TexletEstimation::backProject: the depth image is empty");
  if (!has_camera_)
    throw std::invalid_argument ("pcl::texlet::gpu::TexletEstimation::backProject: no camera was set (setCamera)");
  cloud.create (depth.rows (), depth.cols ());
  const dim3 block (32, 8), grid ((depth.cols () + 31) / 32, (depth.rows () + 7) / 8);
  backProjectKernel<<<grid, block, 0, stream_>>> (depth.ptr (), depth.step (), depth.cols (), depth.rows (), camera_,
                                                  cloud.ptr (), cloud.step ());
  PCL_TEXLET_CUDA_CHECK (cudaGetLastError ());
}

void
TexletEstimation::compute (const DeviceArray2D<std::uint16_t> &depth, DeviceArray<DeviceTexlet> &output)
{
  const bool colour = colour_;
  colour_ = false; // a depth image has no colour
  try
  {
    backProject (depth, depth_cloud_);
    compute (depth_cloud_, output);
  }
  catch (...)
  {
    colour_ = colour;
    throw;
  }
  colour_ = colour;
}

void
TexletEstimation::compute (const DeviceArray2D<DevicePoint> &cloud, DeviceArray<DeviceTexlet> &output)
{
  if (cloud.empty ())
    throw std::invalid_argument ("pcl::texlet::gpu::TexletEstimation::compute: the input cloud is empty");
  if (cloud.rows () < 2)
    throw std::invalid_argument ("pcl::texlet::gpu::TexletEstimation::compute: the input cloud is not organised (one row); "
                                 "texlets need the pixel grid of a depth image");
  if (!has_camera_)
    throw std::invalid_argument ("pcl::texlet::gpu::TexletEstimation::compute: no camera was set (setCamera)");
  if (precision_ == Precision::Double)
    run<double> (cloud, output);
  else
    run<float> (cloud, output);
}

template <typename S> void
TexletEstimation::run (const DeviceArray2D<DevicePoint> &cloud, DeviceArray<DeviceTexlet> &output)
{
  const int disc = kernels::pixelDiscSize (params_.radius);
  if (disc_radius_ != params_.radius)
  {
    std::vector<int> offsets (2 * disc);
    kernels::pixelDiscOffsets (params_.radius, offsets.data (), offsets.data () + disc, disc);
    disc_.upload (offsets);
    disc_radius_ = params_.radius;
  }

  const kernels::HexGrid grid = frameGrid (cloud.cols (), cloud.rows (), params_);
  const int n = grid.size ();
  if (n == 0)
  {
    std::ostringstream msg;
    msg << "pcl::texlet::gpu::TexletEstimation::compute: a " << cloud.cols () << "x" << cloud.rows ()
        << " image holds no texlet centre at spacing " << params_.spacing;
    throw std::invalid_argument (msg.str ());
  }
  output.create (n);

  kernels::PixelDisc offsets;
  offsets.du = disc_.ptr ();
  offsets.dv = disc_.ptr () + disc;
  offsets.size = disc;
  offsets.radius = params_.radius;
  const kernels::FrameSettings<S> fs =
      texlet::frameSettings<S> (params_, params_.viewpoint, offsets, noise_.min_sigma_mm * 1e-3);
  const CloudView view = {cloud.ptr (), cloud.step (), cloud.cols (), cloud.rows ()};
  DeviceFrame frame;
  frame.cloud = view;
  frame.camera = camera_;
  frame.noise = noise_;
  frame.colour = colour_;

  DeviceArray<unsigned int> &made = made_counter_;
  made.create (1);
  PCL_TEXLET_CUDA_CHECK (cudaMemsetAsync (made.ptr (), 0, sizeof (unsigned int), stream_));
  const int blocks = (n + kBlock - 1) / kBlock;
  unsigned char *scratch = nullptr;
  if (effectiveStrategy () == Strategy::Warp)
  {
    const int wblocks = (n + warp::kWarpsPerBlock - 1) / warp::kWarpsPerBlock;
    warp::texletWarpKernel<S><<<wblocks, 32 * warp::kWarpsPerBlock, warp::kWarpsPerBlock * warp::warpBytes<S> (disc),
                                stream_>>> (frame, fs, grid, output.ptr (), made.ptr ());
  }
  else if (disc <= 64)
    texletKernel<S, 64><<<blocks, kBlock, 0, stream_>>> (frame, fs, grid, scratch, output.ptr (), made.ptr ());
  else if (disc <= 128)
    texletKernel<S, 128><<<blocks, kBlock, 0, stream_>>> (frame, fs, grid, scratch, output.ptr (), made.ptr ());
  else if (disc <= 320)
    texletKernel<S, 320><<<blocks, kBlock, 0, stream_>>> (frame, fs, grid, scratch, output.ptr (), made.ptr ());
  else
  {
    const std::size_t bytes = scratchBytes<S> (disc) * static_cast<std::size_t> (blocks) * kBlock;
    if (scratch_.size () < bytes)
      scratch_.create (bytes);
    scratch = scratch_.ptr ();
    texletKernel<S, 0><<<blocks, kBlock, 0, stream_>>> (frame, fs, grid, scratch, output.ptr (), made.ptr ());
  }
  PCL_TEXLET_CUDA_CHECK (cudaGetLastError ());

  unsigned int made_host = 0;
  PCL_TEXLET_CUDA_CHECK (cudaMemcpyAsync (&made_host, made.ptr (), sizeof made_host, cudaMemcpyDeviceToHost, stream_));
  PCL_TEXLET_CUDA_CHECK (cudaStreamSynchronize (stream_));
  made_ = made_host;
  if (made_host == 0)
  {
    // No texlet at all: say why when it is because there is no depth reading anywhere.
    DeviceArray<unsigned int> valid (1);
    PCL_TEXLET_CUDA_CHECK (cudaMemsetAsync (valid.ptr (), 0, sizeof (unsigned int), stream_));
    const dim3 block (32, 8), g2 ((cloud.cols () + 31) / 32, (cloud.rows () + 7) / 8);
    countValidKernel<<<g2, block, 0, stream_>>> (view, valid.ptr ());
    PCL_TEXLET_CUDA_CHECK (cudaGetLastError ());
    unsigned int valid_host = 0;
    PCL_TEXLET_CUDA_CHECK (cudaMemcpyAsync (&valid_host, valid.ptr (), sizeof valid_host, cudaMemcpyDeviceToHost, stream_));
    PCL_TEXLET_CUDA_CHECK (cudaStreamSynchronize (stream_));
    if (valid_host == 0)
      throw std::runtime_error ("pcl::texlet::gpu::TexletEstimation::compute: the input has no valid point (all depth is "
                                "invalid: NaN, infinite, zero or not in front of the camera)");
  }
}

template void TexletEstimation::run<float> (const DeviceArray2D<DevicePoint> &, DeviceArray<DeviceTexlet> &);
template void TexletEstimation::run<double> (const DeviceArray2D<DevicePoint> &, DeviceArray<DeviceTexlet> &);

} // namespace gpu
} // namespace texlet
} // namespace pcl
