/*
 * pcl_texlet GPU: texlet extraction on a CUDA device, in the style of PCL's gpu modules.
 *
 * Needs CUDA's runtime and the kernels' headers only, not PCL: the device machine builds it
 * with CUDA and Eigen alone. The PCL-side conveniences (host pcl::PointCloud in, a
 * pcl::PointCloud<pcl::Texlet> out, CameraModel and NoiseModel conversion) are declared here
 * as templates and defined in texlet_estimation_pcl.h, which includes PCL.
 */
#pragma once

#include <pcl_texlet/gpu/containers/device_array.h>
#include <pcl_texlet/gpu/frame_texlet.h>
#include <pcl_texlet/features/texlet_parameters.h>

#include <cuda_runtime_api.h>

#include <cstdint>
#include <vector>

namespace pcl
{
template <typename PointT> class PointCloud;
struct Texlet;

namespace texlet
{
namespace gpu
{

/** \brief Floating-point type the device computes texlets in. */
enum class Precision : int
{
  Double = 0, ///< as the CPU path: the same results to rounding (default)
  Float = 1   ///< faster on most GPUs, but not the CPU's results: on a Kinect frame ~1% of PCA
              ///< normals differ by more than 1e-4 rad from the double path (a few near-degenerate
              ///< patches by far more); averaging agrees to 3e-7 rad
};

/** \brief How the device's threads share the texlets. */
enum class Strategy : int
{
  Thread = 0, ///< one thread per texlet running the texlet stages as the CPU does (default)
  Warp = 1    ///< one warp per texlet: RANSAC hypotheses and Monte Carlo samples across the lanes
              ///< (PCA and averaging fits; SVD and discs too large for shared memory, in double
              ///< precision from radius 11 on, use Thread)
};

/** \brief Checks every field of \a p by the CPU path's rules (texlet::parameterProblem).
  * \throws std::invalid_argument naming the field, the rule and the value
  */
void
validateParameters (const texlet::TexletParameters &p);

/** \brief Texlet extraction on the GPU: the CPU path's algorithm (pcl::TexletEstimation)
  * with one CUDA thread per texlet, run on an organised cloud on the device or on a 16-bit
  * depth image that is back-projected on the device (the paper's step 1).
  *
  * Each thread runs the texlet stages of kernels/texlet_stages.h on the device's frame
  * (DeviceFrame): the disc, the noise model per pixel, RANSAC, the fit and the uncertainty,
  * keyed by the centre pixel's index, as the CPU path does: for the same seed the two agree to
  * rounding (Precision::Double). The normals face the parameters' viewpoint.
  * Centres lie on the hexagonal grid of the spacing; the output holds one texlet per centre in
  * grid order, NaN with support 0 where none could be made. Mean colour is computed when the
  * cloud's rgba words carry colour (setColour). All calls are synchronous on the stream set
  * with setStream (default: the legacy default stream).
  *
  * \author pcl_texlet developers
  * \ingroup gpu
  */
class TexletEstimation
{
public:
  using PointType = DevicePoint;
  using OutputType = DeviceTexlet;

  TexletEstimation ();

  /** \brief All settings at once (defaults: the paper's Table 1). \throws std::invalid_argument */
  void
  setParameters (const texlet::TexletParameters &params);
  const texlet::TexletParameters &
  getParameters () const { return params_; }

  /** \brief Camera model: gives the back-projection of depth images and the noise model's r.
    * Required (there is no estimate from the cloud on the device). \throws std::invalid_argument
    */
  void
  setCamera (const DeviceCamera &camera);
  const DeviceCamera &
  getCamera () const { return camera_; }
  bool
  hasCamera () const { return has_camera_; }

  /** \brief Depth noise model (default: the paper's polynomial). \throws std::invalid_argument */
  void
  setNoise (const DeviceNoise &noise);
  const DeviceNoise &
  getNoise () const { return noise_; }

  /** \brief Thread (default) or Warp; see Strategy. */
  void
  setStrategy (Strategy s) { strategy_ = s; }
  Strategy
  getStrategy () const { return strategy_; }

  /** \brief The strategy compute() uses for the current parameters (Warp falls back to Thread
    * for the SVD fit and for discs too large for shared memory).
    */
  Strategy
  effectiveStrategy () const;

  void
  setPrecision (Precision p) { precision_ = p; }
  Precision
  getPrecision () const { return precision_; }

  /** \brief Whether the rgba words of the input cloud hold colour (default false). */
  void
  setColour (bool colour) { colour_ = colour; }

  void
  setStream (cudaStream_t stream) { stream_ = stream; }

  /** \brief Texlets made by the last compute (the others are NaN with support 0). */
  unsigned int
  getMadeCount () const { return made_; }

  /** \brief Texlets of an organised cloud on the device (metres; NaN or z <= 0: no reading).
    * \throws std::invalid_argument for an empty cloud or no camera, pcl::texlet::gpu::CudaError
    */
  void
  compute (const DeviceArray2D<DevicePoint> &cloud, DeviceArray<DeviceTexlet> &output);

  /** \brief Texlets of a 16-bit depth image in millimetres (0: no reading) on the device: it
    * is back-projected into an internal cloud (see backProject) first.
    */
  void
  compute (const DeviceArray2D<std::uint16_t> &depth_mm, DeviceArray<DeviceTexlet> &output);

  /** \brief Back-projects a depth image through the camera into an organised cloud, as
    * texlet::depthToCloud does on the host.
    */
  void
  backProject (const DeviceArray2D<std::uint16_t> &depth_mm, DeviceArray2D<DevicePoint> &cloud);

  /** \brief Number of texlets (grid centres) for an image of this size with the current spacing. */
  int
  texletCount (int width, int height) const;

  /** \brief Host-side, PCL: uploads \a cloud (any point type with x, y, z; colour too when it
    * has one), computes, and downloads into \a output (one texlet per centre, is_dense when
    * all were made). Defined in texlet_estimation_pcl.h.
    */
  template <typename PointT> void
  compute (const pcl::PointCloud<PointT> &cloud, pcl::PointCloud<pcl::Texlet> &output);

private:
  template <typename S> void
  run (const DeviceArray2D<DevicePoint> &cloud, DeviceArray<DeviceTexlet> &output);

  texlet::TexletParameters params_;
  DeviceCamera camera_;
  bool has_camera_ = false;
  DeviceNoise noise_;
  Precision precision_ = Precision::Double;
  Strategy strategy_ = Strategy::Thread;
  bool colour_ = false;
  cudaStream_t stream_ = nullptr;
  unsigned int made_ = 0;
  DeviceArray<int> disc_;            // pixel disc offsets, du then dv
  int disc_radius_ = -1;
  DeviceArray<unsigned char> scratch_; // per-thread scratch for discs too large for registers
  DeviceArray2D<DevicePoint> depth_cloud_; // back-projected depth image
  DeviceArray<unsigned int> made_counter_; // texlets made, counted on the device
};

/** \brief Downloads device texlets to the host. */
inline void
downloadTexlets (const DeviceArray<DeviceTexlet> &device, std::vector<DeviceTexlet> &host)
{
  device.download (host);
}

} // namespace gpu
} // namespace texlet
} // namespace pcl
