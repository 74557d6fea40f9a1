/*
 * Fuzz target: texlet extraction (pcl::TexletEstimation) on arbitrary organised clouds.
 *
 * The input is decoded (FuzzedDataProvider) into an image size up to 48 x 40, the extraction
 * settings (some in their valid ranges, some raw, so that validation is exercised too), an
 * optional pinhole camera (else one is estimated from the cloud) and one point per pixel: NaN,
 * infinities, zero, negative or huge depth, raw float triplets, or a point on a bumpy surface in
 * front of the camera, so that real texlets are fitted next to every kind of bad point.
 * Iterations and Monte Carlo samples are kept small so that one input runs in milliseconds; their
 * upper limits are not what this target looks for.
 */
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/features/point_types.h>
#include <pcl_texlet/features/texlet_estimation.h>
#include <pcl/exceptions.h>
#include <pcl/point_types.h>

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace
{

float
specialValue (FuzzedDataProvider &in)
{
  const float values[] = {std::numeric_limits<float>::quiet_NaN (), std::numeric_limits<float>::infinity (),
                          -std::numeric_limits<float>::infinity (), 0.0f, -0.0f, 1e-30f, -1.0f, 1e30f,
                          std::numeric_limits<float>::max (), std::numeric_limits<float>::denorm_min ()};
  return values[in.ConsumeIntegralInRange<int> (0, 9)];
}

} // namespace

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  FuzzedDataProvider in (data, size);
  const int width = in.ConsumeIntegralInRange<int> (0, 48);
  const int height = in.ConsumeIntegralInRange<int> (0, 40);

  pcl::texlet::TexletParameters p;
  p.spacing = in.ConsumeIntegralInRange<int> (-1, 12);
  // Radii up to 12 px; the limits (64 valid, 65 refused) only on tiny images, where they are cheap.
  p.radius = in.ConsumeIntegralInRange<int> (0, 12);
  if (width * height <= 64 && in.ConsumeBool ())
    p.radius = in.ConsumeIntegralInRange<int> (63, 65);
  p.ransac_iterations = in.ConsumeIntegralInRange<int> (0, 12);
  p.ransac_threshold = in.ConsumeBool () ? in.ConsumeFloatingPoint<double> () : in.ConsumeFloatingPointInRange<double> (0.0, 0.05);
  p.threshold_sigmas = in.ConsumeBool () ? in.ConsumeFloatingPoint<double> () : in.ConsumeFloatingPointInRange<double> (0.1, 5.0);
  p.fit = static_cast<pcl::texlet::PlaneFitMethod> (in.ConsumeIntegralInRange<int> (0, 2));
  p.uncertainty = static_cast<pcl::texlet::UncertaintyMethod> (in.ConsumeIntegralInRange<int> (0, 2));
  p.samples = in.ConsumeIntegralInRange<int> (1, 8);
  p.seed = in.ConsumeIntegral<std::uint32_t> ();
  p.min_support = in.ConsumeIntegralInRange<int> (2, 40);
  for (float &v : p.viewpoint)
    v = in.ConsumeBool () ? specialValue (in) : in.ConsumeFloatingPointInRange<float> (-2.0f, 2.0f);
  const bool with_camera = in.ConsumeBool ();
  const double fx = in.ConsumeFloatingPointInRange<double> (-10.0, 1000.0);
  const double fy = in.ConsumeFloatingPointInRange<double> (-10.0, 1000.0);
  const double cx = in.ConsumeFloatingPointInRange<double> (-50.0, 100.0);
  const double cy = in.ConsumeFloatingPointInRange<double> (-50.0, 100.0);

  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  cloud->width = static_cast<std::uint32_t> (width);
  cloud->height = static_cast<std::uint32_t> (height);
  cloud->is_dense = false;
  cloud->points.resize (static_cast<std::size_t> (width) * height);
  // A bumpy surface 0.5 to 4 m away, seen through a 60 px pinhole centred on the image.
  const float base = in.ConsumeFloatingPointInRange<float> (0.5f, 4.0f);
  const float slope = in.ConsumeFloatingPointInRange<float> (-0.05f, 0.05f);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
    {
      pcl::PointXYZ &pt = (*cloud)(u, v);
      const int kind = in.remaining_bytes () ? in.ConsumeIntegralInRange<int> (0, 15) : 15;
      if (kind == 0)
        pt.x = pt.y = pt.z = std::numeric_limits<float>::quiet_NaN ();
      else if (kind == 1)
        pt.x = specialValue (in), pt.y = specialValue (in), pt.z = specialValue (in);
      else if (kind == 2)
        pt.x = in.ConsumeFloatingPoint<float> (), pt.y = in.ConsumeFloatingPoint<float> (), pt.z = in.ConsumeFloatingPoint<float> ();
      else
      {
        const float z = base + slope * static_cast<float> (u + v) + 0.002f * static_cast<float> (kind - 8);
        pt.z = z;
        pt.x = (static_cast<float> (u) - 0.5f * static_cast<float> (width)) * z / 60.0f;
        pt.y = (static_cast<float> (v) - 0.5f * static_cast<float> (height)) * z / 60.0f;
      }
    }

  pcl::TexletEstimation<pcl::PointXYZ, pcl::Texlet> est;
  est.setNumberOfThreads (1);
  pcl::PointCloud<pcl::Texlet> out;
  try
  {
    est.setParameters (p);
    if (with_camera)
      est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (fx, fy, cx, cy));
    est.setInputCloud (cloud);
    est.compute (out);
  }
  catch (const pcl::PCLException &)
  {
    return 0;
  }
  // Every texlet fitted must have a finite centre and a unit normal.
  for (const pcl::Texlet &t : out.points)
  {
    if (!std::isfinite (t.x) && !std::isnan (t.x))
      std::abort ();
    if (std::isfinite (t.x))
    {
      const float n = std::sqrt (t.normal_x * t.normal_x + t.normal_y * t.normal_y + t.normal_z * t.normal_z);
      if (!(std::abs (n - 1.0f) < 1e-3f))
        std::abort ();
    }
  }
  return 0;
}
