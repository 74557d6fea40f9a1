/*
 * Tests of the CUDA backend that need no PCL: containers, errors, back-projection, and the
 * GPU's texlets against computeTexletsReference (the texlet stages the CPU path runs, on the
 * device's frame, on the host; test_gpu_texlets_pcl checks it against pcl::TexletEstimation
 * itself). Tests that need a device skip with a message when cudaGetDeviceCount reports none.
 */
#include <pcl_texlet/gpu/containers/device_array.h>
#include <pcl_texlet/gpu/texlet_estimation.h>

#include "gpu/synthetic_frame.h"
#include "gpu/texlet_compare.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

namespace gpu = pcl::texlet::gpu;
using gpu::DeviceArray;
using gpu::DeviceArray2D;
using gpu::DeviceCamera;
using gpu::DeviceNoise;
using gpu::DevicePoint;
using gpu::DeviceTexlet;
using gpu::Precision;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::TexletParameters;
using pcl::texlet::UncertaintyMethod;
using pcl_texlet_test::compareTexlets;

#define REQUIRE_CUDA_DEVICE()                                                                                      \
  do                                                                                                               \
  {                                                                                                                \
    if (gpu::cudaDeviceCount () == 0)                                                                         \
      GTEST_SKIP () << "no CUDA device (cudaGetDeviceCount reports none): the GPU backend is compiled but not run"; \
  } while (0)

namespace
{

/** The synthetic frame as depth and as the host reference cloud. */
struct Frame
{
  pcl_texlet_test::SyntheticFrame scene;
  std::vector<std::uint16_t> depth;
  std::vector<DevicePoint> cloud;

  explicit Frame (int width = 320, int height = 240)
  {
    scene.width = width;
    scene.height = height;
    scene.camera = DeviceCamera::pinhole (290.0, 290.0, 159.5, 119.5);
    depth = scene.render ();
    gpu::backProjectReference (depth, width, height, scene.camera, cloud);
  }
};

std::vector<DeviceTexlet>
gpuTexlets (const Frame &f, const TexletParameters &params, Precision precision,
            gpu::Strategy strategy = gpu::Strategy::Thread)
{
  gpu::TexletEstimation est;
  est.setStrategy (strategy);
  est.setParameters (params);
  est.setCamera (f.scene.camera);
  est.setPrecision (precision);
  DeviceArray2D<std::uint16_t> depth;
  depth.upload (f.depth, f.scene.width);
  DeviceArray<DeviceTexlet> out;
  est.compute (depth, out);
  std::vector<DeviceTexlet> host;
  gpu::downloadTexlets (out, host);
  return host;
}

std::vector<DeviceTexlet>
hostTexlets (const Frame &f, const TexletParameters &params, Precision precision)
{
  std::vector<DeviceTexlet> out;
  if (precision == Precision::Double)
    gpu::computeTexletsReference<double> (f.cloud, f.scene.width, f.scene.height, f.scene.camera, DeviceNoise (),
                                               params, false, out);
  else
    gpu::computeTexletsReference<float> (f.cloud, f.scene.width, f.scene.height, f.scene.camera, DeviceNoise (),
                                              params, false, out);
  return out;
}

double
angleToWall (const pcl_texlet_test::SyntheticFrame &scene, const DeviceTexlet &t)
{
  double n[3], d;
  scene.wall (n, d);
  const double c = std::fabs (n[0] * t.normal_x + n[1] * t.normal_y + n[2] * t.normal_z);
  return std::acos (std::min (1.0, c));
}

} // namespace

// --- errors and parameters (no device needed) -----------------------------------------------

TEST (CudaErrorTest, NamesTheCallAndCudasMessage)
{
  try
  {
    gpu::detail::cudaCheck (cudaErrorInvalidValue, "cudaMemcpy (dst, src, n, kind)", "file.cu", 42);
    FAIL () << "no exception";
  }
  catch (const gpu::CudaError &e)
  {
    const std::string what = e.what ();
    EXPECT_NE (what.find ("cudaMemcpy (dst, src, n, kind) failed"), std::string::npos) << what;
    EXPECT_NE (what.find ("cudaErrorInvalidValue"), std::string::npos) << what;
    EXPECT_NE (what.find ("file.cu:42"), std::string::npos) << what;
    EXPECT_EQ (e.code (), cudaErrorInvalidValue);
  }
}

TEST (GpuParametersTest, BadValuesAreRejectedByName)
{
  gpu::TexletEstimation est;
  const auto expectRejected = [&] (TexletParameters p, const std::string &field) {
    try
    {
      est.setParameters (p);
      ADD_FAILURE () << field << ": no exception";
    }
    catch (const std::invalid_argument &e)
    {
      EXPECT_NE (std::string (e.what ()).find (field), std::string::npos) << e.what ();
    }
  };
  TexletParameters p;
  p.spacing = 1;
  expectRejected (p, "spacing");
  p = {};
  p.radius = 0;
  expectRejected (p, "radius");
  p = {};
  p.ransac_iterations = 0;
  expectRejected (p, "ransac_iterations");
  p = {};
  p.samples = 1;
  expectRejected (p, "samples");
  p = {};
  p.min_support = 2;
  expectRejected (p, "min_support");
  p = {};
  p.threshold_sigmas = -1;
  expectRejected (p, "threshold_sigmas");
  p = {};
  p.ransac_threshold = NAN;
  expectRejected (p, "ransac_threshold");
  EXPECT_THROW (est.setCamera (DeviceCamera::pinhole (0.0, 580.0, 320.0, 240.0)), std::invalid_argument);
  DeviceNoise noise;
  noise.min_sigma_mm = 0;
  EXPECT_THROW (est.setNoise (noise), std::invalid_argument);
}

TEST (GpuParametersTest, WarpStrategyFallsBackWhereItCannotRun)
{
  gpu::TexletEstimation est;
  EXPECT_EQ (est.effectiveStrategy (), gpu::Strategy::Thread); // the default
  est.setStrategy (gpu::Strategy::Warp);
  EXPECT_EQ (est.effectiveStrategy (), gpu::Strategy::Warp); // Table 1: PCA, radius 6
  TexletParameters p;
  p.fit = PlaneFitMethod::SVD; // needs a work buffer per sample: one thread per texlet
  est.setParameters (p);
  EXPECT_EQ (est.effectiveStrategy (), gpu::Strategy::Thread);
  p.fit = PlaneFitMethod::Averaging;
  p.radius = 12; // 441 points x 37 bytes x 4 warps: more than 48 KiB of shared memory
  est.setParameters (p);
  EXPECT_EQ (est.effectiveStrategy (), gpu::Strategy::Thread);
  est.setPrecision (Precision::Float); // 441 x 21 x 4 fits
  EXPECT_EQ (est.effectiveStrategy (), gpu::Strategy::Warp);
}

TEST (GpuParametersTest, ComputeWithoutCameraOrInputIsAnError)
{
  gpu::TexletEstimation est;
  DeviceArray2D<DevicePoint> empty;
  DeviceArray<DeviceTexlet> out;
  EXPECT_THROW (est.compute (empty, out), std::invalid_argument);
}

// --- the host reference itself against closed-form geometry (no device needed) --------------

TEST (HostReferenceTest, WallNormalsMatchTheGeometry)
{
  const Frame f;
  TexletParameters p;
  p.uncertainty = UncertaintyMethod::Analytic;
  const std::vector<DeviceTexlet> t = hostTexlets (f, p, Precision::Double);
  std::vector<double> angles;
  for (const DeviceTexlet &x : t)
  {
    const double c[3] = {x.x, x.y, x.z};
    if (x.support > 0 && !f.scene.onSphere (c, 0.05) && x.z > 0)
      angles.push_back (angleToWall (f.scene, x));
  }
  ASSERT_GT (angles.size (), t.size () / 2);
  std::nth_element (angles.begin (), angles.begin () + angles.size () / 2, angles.end ());
  // Depth noise of ~2 mm and 1 mm quantisation over a ~3 cm disc: a few degrees per texlet.
  EXPECT_LT (angles[angles.size () / 2], 0.05) << "median angle to the wall's normal, rad";
}

// --- containers (device) ------------------------------------------------------------------------

TEST (DeviceArrayTest, UploadDownloadRoundTrip)
{
  REQUIRE_CUDA_DEVICE ();
  std::vector<int> host (1000);
  std::iota (host.begin (), host.end (), -17);
  DeviceArray<int> a;
  a.upload (host);
  EXPECT_EQ (a.size (), host.size ());
  EXPECT_EQ (a.sizeBytes (), host.size () * sizeof (int));
  DeviceArray<int> b;
  a.copyTo (b);
  std::vector<int> back;
  b.download (back);
  EXPECT_EQ (back, host);
  DeviceArray<int> shared = a; // shallow, like PCL's
  EXPECT_EQ (shared.ptr (), a.ptr ());
  a.release ();
  EXPECT_TRUE (a.empty ());
  shared.download (back);
  EXPECT_EQ (back, host);
}

TEST (DeviceArrayTest, FailedAllocationNamesTheCall)
{
  REQUIRE_CUDA_DEVICE ();
  try
  {
    DeviceArray<double> huge (std::size_t (1) << 50); // 8 PiB
    FAIL () << "allocated 8 PiB";
  }
  catch (const gpu::CudaError &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("cudaMalloc"), std::string::npos) << e.what ();
    EXPECT_EQ (e.code (), cudaErrorMemoryAllocation);
  }
  DeviceArray<int> fine (10); // the error did not stick
  EXPECT_EQ (fine.size (), 10u);
}

TEST (DeviceArray2DTest, PitchedRoundTrip)
{
  REQUIRE_CUDA_DEVICE ();
  const int rows = 37, cols = 101;
  std::vector<std::uint16_t> host (rows * cols);
  for (std::size_t i = 0; i < host.size (); ++i)
    host[i] = static_cast<std::uint16_t> (i * 7919u);
  DeviceArray2D<std::uint16_t> a;
  a.upload (host, cols);
  EXPECT_EQ (a.rows (), rows);
  EXPECT_EQ (a.cols (), cols);
  EXPECT_GE (a.step (), cols * sizeof (std::uint16_t));
  std::vector<std::uint16_t> back;
  int back_cols = 0;
  a.download (back, back_cols);
  EXPECT_EQ (back_cols, cols);
  EXPECT_EQ (back, host);
  EXPECT_THROW (a.upload (host, 100), std::invalid_argument); // not a whole number of rows
}

// --- the backend (device) -----------------------------------------------------------------------

TEST (GpuTexletEstimationTest, BackProjectionMatchesTheHost)
{
  REQUIRE_CUDA_DEVICE ();
  for (const DeviceCamera &camera :
       {DeviceCamera::pinhole (290.0, 291.0, 160.2, 118.7, {0.1, -0.2, 0.001, -0.002, 0.05}),
        DeviceCamera::openniFov (320, 240, 1.0226, 0.7963)})
  {
    Frame f;
    gpu::TexletEstimation est;
    est.setCamera (camera);
    DeviceArray2D<std::uint16_t> depth;
    depth.upload (f.depth, f.scene.width);
    DeviceArray2D<DevicePoint> cloud;
    est.backProject (depth, cloud);
    std::vector<DevicePoint> gpu, host;
    int cols;
    cloud.download (gpu, cols);
    gpu::backProjectReference (f.depth, f.scene.width, f.scene.height, camera, host);
    ASSERT_EQ (gpu.size (), host.size ());
    double worst = 0;
    std::size_t nan_mismatch = 0;
    for (std::size_t i = 0; i < gpu.size (); ++i)
    {
      if (std::isnan (gpu[i].z) != std::isnan (host[i].z))
        ++nan_mismatch;
      else if (!std::isnan (host[i].z))
        worst = std::max ({worst, std::fabs (double (gpu[i].x) - host[i].x), std::fabs (double (gpu[i].y) - host[i].y),
                           std::fabs (double (gpu[i].z) - host[i].z)});
    }
    EXPECT_EQ (nan_mismatch, 0u);
    EXPECT_LT (worst, 1e-6) << "metres, camera kind " << camera.kind; // float rounding of the same doubles
  }
}

/** (fit, uncertainty, precision, strategy) */
class GpuMatchesHostTest
  : public ::testing::TestWithParam<std::tuple<PlaneFitMethod, UncertaintyMethod, Precision, gpu::Strategy>>
{
};

TEST_P (GpuMatchesHostTest, SameTexletsForTheSameSeed)
{
  REQUIRE_CUDA_DEVICE ();
  const Frame f;
  TexletParameters p;
  p.fit = std::get<0> (GetParam ());
  p.uncertainty = std::get<1> (GetParam ());
  p.seed = 1234;
  const Precision precision = std::get<2> (GetParam ());
  const std::vector<DeviceTexlet> gpu = gpuTexlets (f, p, precision, std::get<3> (GetParam ()));
  const std::vector<DeviceTexlet> host = hostTexlets (f, p, precision);
  ASSERT_EQ (gpu.size (), host.size ());
  const auto c = compareTexlets (gpu, host);
  SCOPED_TRACE (::testing::Message () << c);
  std::cout << "comparison: " << c << std::endl;
  EXPECT_EQ (c.pixel_mismatch, 0u);
  // The same code on both sides: only rounding (FMA contraction) can flip an inlier decision.
  const std::size_t flips_allowed = precision == Precision::Double ? gpu.size () / 1000 : gpu.size () / 100;
  EXPECT_LE (c.made_mismatch + c.support_mismatch, flips_allowed);
  EXPECT_GT (c.compared, gpu.size () / 2);
  if (precision == Precision::Double)
  {
    EXPECT_LT (c.max_normal_rad, 1e-4);
    if (p.uncertainty != UncertaintyMethod::None)
    {
      EXPECT_LT (c.max_cov_p_rel, 1e-3);
      EXPECT_LT (c.max_cov_n_rel, 1e-3);
    }
  }
  else
  {
    // Float: near-degenerate patches are ill-conditioned, so FMA contraction on the device can
    // move their normals, and central differences in float (analytic averaging) are sensitive
    // to the last bit; the bulk must still agree.
    EXPECT_LE (c.normal_over, c.compared / 100);
    if (p.uncertainty != UncertaintyMethod::None)
      EXPECT_LE (c.cov_over, c.compared / 20);
  }
}

std::string
methodName (const ::testing::TestParamInfo<GpuMatchesHostTest::ParamType> &info)
{
  const char *fits[] = {"PCA", "SVD", "Averaging"}, *unc[] = {"None", "Analytic", "MonteCarlo"};
  return std::string (fits[static_cast<int> (std::get<0> (info.param))]) + "_" +
         unc[static_cast<int> (std::get<1> (info.param))] + "_" +
         (std::get<2> (info.param) == Precision::Double ? "Double" : "Float") +
         (std::get<3> (info.param) == gpu::Strategy::Thread ? "_Thread" : "_Warp");
}

INSTANTIATE_TEST_SUITE_P (
    AllMethods, GpuMatchesHostTest,
    ::testing::Combine (::testing::Values (PlaneFitMethod::PCA, PlaneFitMethod::SVD, PlaneFitMethod::Averaging),
                        ::testing::Values (UncertaintyMethod::None, UncertaintyMethod::Analytic,
                                           UncertaintyMethod::MonteCarlo),
                        ::testing::Values (Precision::Double, Precision::Float),
                        ::testing::Values (gpu::Strategy::Thread, gpu::Strategy::Warp)),
    methodName);

TEST (GpuTexletEstimationTest, LargeDiscsUseGlobalScratchAndStillMatch)
{
  REQUIRE_CUDA_DEVICE ();
  const Frame f;
  TexletParameters p;
  p.radius = 12; // 441 points: beyond the local-array kernels
  p.spacing = 10;
  p.samples = 20;
  const auto c = compareTexlets (gpuTexlets (f, p, Precision::Double), hostTexlets (f, p, Precision::Double));
  SCOPED_TRACE (::testing::Message () << c);
  EXPECT_GT (c.compared, 100u);
  EXPECT_LT (c.max_normal_rad, 1e-4);
  EXPECT_LT (c.max_cov_p_rel, 1e-3);
  EXPECT_LT (c.max_cov_n_rel, 1e-3);
}

TEST (GpuTexletEstimationTest, WallNormalsMatchTheGeometry)
{
  REQUIRE_CUDA_DEVICE ();
  const Frame f;
  const std::vector<DeviceTexlet> t = gpuTexlets (f, TexletParameters (), Precision::Double);
  std::vector<double> angles;
  for (const DeviceTexlet &x : t)
  {
    const double c[3] = {x.x, x.y, x.z};
    if (x.support > 0 && !f.scene.onSphere (c, 0.05))
      angles.push_back (angleToWall (f.scene, x));
  }
  ASSERT_GT (angles.size (), t.size () / 2);
  std::nth_element (angles.begin (), angles.begin () + angles.size () / 2, angles.end ());
  EXPECT_LT (angles[angles.size () / 2], 0.05) << "median angle to the wall's normal, rad";
}

TEST (GpuTexletEstimationTest, AllInvalidDepthIsAnError)
{
  REQUIRE_CUDA_DEVICE ();
  gpu::TexletEstimation est;
  est.setCamera (DeviceCamera::pinhole (290.0, 290.0, 159.5, 119.5));
  DeviceArray2D<std::uint16_t> depth;
  depth.upload (std::vector<std::uint16_t> (320 * 240, 0), 320);
  DeviceArray<DeviceTexlet> out;
  try
  {
    est.compute (depth, out);
    FAIL () << "no exception";
  }
  catch (const std::runtime_error &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("no valid point"), std::string::npos) << e.what ();
  }
}
