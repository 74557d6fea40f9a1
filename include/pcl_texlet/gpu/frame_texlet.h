/*
 * pcl_texlet GPU: the device's frame of the texlet stages, for host and device.
 *
 * The texlet stages (kernels/texlet_stages.h) read a frame through an accessor; here it is a
 * pitched image of DevicePoint with a camera and a noise model as PODs (DeviceFrame), so the
 * CUDA kernels and computeTexletsReference (the same code on the host, the GPU tests' CPU
 * reference on machines without PCL) run the very stages pcl::TexletEstimation runs, with the
 * same Philox key (the centre pixel's index).
 *
 * Needs no PCL: only the kernels, Random123 and (for the host compiler) CUDA's runtime API header.
 */
#pragma once

#include <pcl_texlet/gpu/random123_host_sincospi.h> // before Random123, see there

#include <pcl_texlet/features/frame_settings.h>
#include <pcl_texlet/features/texlet_parameters.h>
#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/noise_terms.h>
#include <pcl_texlet/kernels/pinhole_ray.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/plumb_bob.h>
#include <pcl_texlet/kernels/texlet_stages.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace gpu
{

/** \brief A point of an organised cloud on the device: pcl::PointXYZ's 16 bytes, with the
  * fourth word holding PCL's packed rgba (0 when the cloud has no colour).
  */
struct alignas (16) DevicePoint
{
  float x, y, z;
  std::uint32_t rgba;
};

/** \brief A texlet with exactly pcl::Texlet's memory layout (96 bytes; checked by
  * static_assert where PCL is present), so device output downloads straight into a
  * pcl::PointCloud<pcl::Texlet>. Fields and units as pcl::Texlet; the padding holds
  * pcl::Texlet's values from construction on (kernels::writeTexlet leaves it alone).
  */
struct alignas (16) DeviceTexlet
{
  float x, y, z, data_w = 1.0f;          ///< centre P, metres; data_w = 1 as in PCL
  float normal_x, normal_y, normal_z, data_nw = 0.0f; ///< unit normal facing the viewpoint
  std::uint32_t rgba;                    ///< mean colour of the inliers, PCL's packing (a r g b)
  float curvature;                       ///< l0 / (l0 + l1 + l2)
  float data_c2 = 0.0f, data_c3 = 0.0f;  ///< padding
  float radius;                          ///< sqrt(2 (l1 + l2)), metres
  std::uint32_t support;                 ///< RANSAC inliers; 0 when no texlet could be made
  float cov_p_xx, cov_p_xy, cov_p_xz, cov_p_yy, cov_p_yz, cov_p_zz; ///< Sigma_P, m^2
  float cov_n_11, cov_n_12, cov_n_22;    ///< Sigma_N in the tangent frame of N, rad^2
  std::uint32_t pixel_index;             ///< centre pixel in the organised input
};
static_assert (sizeof (DeviceTexlet) == 96, "DeviceTexlet must have pcl::Texlet's 96 bytes");
static_assert (sizeof (DevicePoint) == 16, "DevicePoint must have pcl::PointXYZ's 16 bytes");

/** \brief The camera models of camera_model.h as a POD the device can evaluate: the
  * calibrated pinhole with plumb_bob distortion (PinholeModel) or OpenNI's field-of-view
  * back-projection (OpenNIFovModel). Formulas are those of src/camera/camera_model.cpp.
  */
struct DeviceCamera
{
  enum Kind : int
  {
    Pinhole = 0,
    OpenNIFov = 1
  };
  Kind kind = Pinhole;
  double fx = 0, fy = 0, cx = 0, cy = 0; ///< pinhole intrinsics, pixels
  kernels::PlumbBob distortion;          ///< pinhole distortion (all zero: none)
  int width = 0, height = 0;             ///< OpenNI model: resolution r_x, r_y
  double tan_h = 0, tan_v = 0;           ///< OpenNI model: tan(hFOV / 2), tan(vFOV / 2)

  /** \brief A pinhole camera (fx, fy > 0 are checked by TexletEstimation). */
  static DeviceCamera
  pinhole (double fx, double fy, double cx, double cy, const kernels::PlumbBob &d = {})
  {
    DeviceCamera c;
    c.kind = Pinhole;
    c.fx = fx; c.fy = fy; c.cx = cx; c.cy = cy;
    c.distortion = d;
    return c;
  }

  /** \brief OpenNI's model for a \a width x \a height image with fields of view in radians. */
  static DeviceCamera
  openniFov (int width, int height, double hfov, double vfov)
  {
    DeviceCamera c;
    c.kind = OpenNIFov;
    c.width = width;
    c.height = height;
    c.tan_h = std::tan (hfov / 2);
    c.tan_v = std::tan (vfov / 2);
    return c;
  }

  PCL_TEXLET_HD bool
  hasDistortion () const { return kernels::hasDistortion (distortion); }

  /** \brief Ray (x, y, 1) through pixel (u, v); NaN where the distortion cannot be inverted. */
  PCL_TEXLET_HD void
  pixelToRay (double u, double v, double &x, double &y) const
  {
    if (kind == OpenNIFov)
    {
      x = 2 * (u / width - 0.5) * tan_h;
      y = 2 * (v / height - 0.5) * tan_v;
      return;
    }
    kernels::pinholeRay (fx, fy, cx, cy, distortion, u, v, x, y);
  }

  /** \brief Distance of pixel (u, v) from the principal point, pixels (the noise model's r). */
  PCL_TEXLET_HD double
  principalPointDistance (double u, double v) const
  {
    if (kind == OpenNIFov)
      return std::hypot (u - 0.5 * width, v - 0.5 * height);
    return std::hypot (u - cx, v - cy);
  }
};

/** \brief The depth noise model of noise_model.h as a POD: a sum of up to kMaxTerms
  * polynomial sigma terms (the paper's Eq. 4), sigma = max(sqrt(sum max(f, 0)^2), floor).
  * The default is NoiseModel::paper().
  */
struct DeviceNoise
{
  static constexpr int kMaxTerms = 4;
  int terms = 1;
  kernels::PolynomialCoefficients polynomial[kMaxTerms] = {kernels::paperPolynomial ()};
  double min_sigma_mm = 0.1;

  /** \brief Depth SD in mm at distance \a r_px from the principal point and depth \a depth_mm;
    * NaN unless the depth is positive and finite. Same arithmetic as NoiseModel::sigmaMm.
    */
  PCL_TEXLET_HD double
  sigmaMm (double r_px, double depth_mm) const
  {
    if (!(depth_mm > 0.0) || !std::isfinite (depth_mm))
      return NAN;
    double var = 0.0;
    for (int i = 0; i < terms; ++i)
    {
      const double s = kernels::evaluatePolynomial (polynomial[i], r_px, depth_mm);
      var += s > 0.0 ? s * s : 0.0;
    }
    const double s = std::sqrt (var);
    return s > min_sigma_mm ? s : min_sigma_mm;
  }
};

/** \brief Read-only view of an organised cloud of DevicePoint, \a step bytes per row. */
struct CloudView
{
  const DevicePoint *data = nullptr;
  std::size_t step = 0;
  int width = 0, height = 0;

  PCL_TEXLET_HD const DevicePoint &
  at (int u, int v) const
  {
    return *reinterpret_cast<const DevicePoint *> (reinterpret_cast<const char *> (data) + v * step +
                                                   u * sizeof (DevicePoint));
  }
};

/** \brief Finite and in front of the camera: texlet::isValidDepthPoint. */
PCL_TEXLET_HD bool
isValidDevicePoint (const DevicePoint &p)
{
  return std::isfinite (p.x) && std::isfinite (p.y) && std::isfinite (p.z) && p.z > 0.0f;
}

/** \brief The point of depth pixel (u, v) holding \a depth_mm (0: no reading, NaN point), as
  * texlet::depthToCloud computes it: ray(u, v) * z, z in metres.
  */
PCL_TEXLET_HD DevicePoint
backProjectPixel (const DeviceCamera &camera, int u, int v, std::uint16_t depth_mm)
{
  DevicePoint p;
  p.rgba = 0;
  if (depth_mm == 0)
  {
    p.x = p.y = p.z = NAN;
    return p;
  }
  double rx, ry;
  camera.pixelToRay (u, v, rx, ry);
  const double z = depth_mm * 1e-3;
  p.x = static_cast<float> (rx * z);
  p.y = static_cast<float> (ry * z);
  p.z = static_cast<float> (z);
  return p;
}

/** \brief A device cloud with its camera and noise model as a frame of the texlet stages
  * (kernels/texlet_stages.h). The device has no per-pixel SD image (each SD comes from the
  * model), no incidence-angle term (no variance rescale) and no shared noise (its terms are
  * polynomials of independent per-pixel noise).
  */
struct DeviceFrame
{
  CloudView cloud;
  DeviceCamera camera;
  DeviceNoise noise;
  bool colour = false; ///< the cloud's rgba words hold colour

  PCL_TEXLET_HD int
  width () const { return cloud.width; }
  PCL_TEXLET_HD int
  height () const { return cloud.height; }

  PCL_TEXLET_HD const DevicePoint &
  point (int u, int v) const { return cloud.at (u, v); }
  PCL_TEXLET_HD const DevicePoint &
  point (std::ptrdiff_t index) const
  {
    const int i = static_cast<int> (index);
    return cloud.at (i % cloud.width, i / cloud.width);
  }

  static PCL_TEXLET_HD bool
  valid (const DevicePoint &p) { return isValidDevicePoint (p); }

  /** \brief Depth SD in metres at pixel (u, v) and depth z (metres): depthSigmaMetres. */
  PCL_TEXLET_HD double
  modelSigma (int u, int v, double z) const
  {
    return noise.sigmaMm (camera.principalPointDistance (u, v), z * 1000.0) * 1e-3;
  }
  PCL_TEXLET_HD double
  sigma (int index, double z) const { return modelSigma (index % cloud.width, index / cloud.width, z); }
  /** \brief The model's SD at a texlet's centre; none of the polynomial terms' variance is shared. */
  PCL_TEXLET_HD kernels::CentreNoise
  centreNoise (int u, int v, double z) const
  {
    kernels::CentreNoise c;
    c.sigma = modelSigma (u, v, z);
    return c;
  }

  PCL_TEXLET_HD bool
  hasColour () const { return colour; }
  PCL_TEXLET_HD void
  addColour (int index, unsigned &r, unsigned &g, unsigned &b) const
  {
    const std::uint32_t c = point (static_cast<std::ptrdiff_t> (index)).rgba;
    r += (c >> 16) & 0xffu;
    g += (c >> 8) & 0xffu;
    b += c & 0xffu;
  }

  template <typename S> PCL_TEXLET_HD double
  varianceScale (int, int, const kernels::TexletResult<S> &) const { return 1.0; }
};

/** \brief The texlet centred on pixel (cu, cv) of \a frame into \a out: kernels::frameTexlet,
  * its kernel computeTexlet inlined. \return false (and a NaN texlet) where none could be made
  */
template <typename S> PCL_TEXLET_HD bool
deviceTexlet (const DeviceFrame &frame, const kernels::FrameSettings<S> &fs, int cu, int cv,
              const kernels::TexletScratch<S> &ws, DeviceTexlet &out)
{
  return kernels::frameTexlet (frame, fs, cu, cv, ws, kernels::InlineTexletKernel (), out);
}

/** \brief The hexagonal grid of centres TexletEstimation uses for a frame. */
inline kernels::HexGrid
frameGrid (int width, int height, const texlet::TexletParameters &params)
{
  return kernels::makeHexGrid (width, height, params.spacing);
}

/** \brief Host reference: every texlet of the frame's hexagonal grid, one after the other,
  * through deviceTexlet (the GPU's code compiled for the host).
  */
template <typename S> void
computeTexletsReference (const std::vector<DevicePoint> &cloud, int width, int height, const DeviceCamera &camera,
                         const DeviceNoise &noise, const texlet::TexletParameters &params, bool colour,
                         std::vector<DeviceTexlet> &out)
{
  const int disc = kernels::pixelDiscSize (params.radius);
  std::vector<int> du (disc), dv (disc);
  kernels::pixelDiscOffsets (params.radius, du.data (), dv.data (), disc);
  kernels::PixelDisc offsets;
  offsets.du = du.data ();
  offsets.dv = dv.data ();
  offsets.size = disc;
  offsets.radius = params.radius;
  const kernels::FrameSettings<S> fs =
      texlet::frameSettings<S> (params, params.viewpoint, offsets, noise.min_sigma_mm * 1e-3);
  std::vector<S> x (disc), y (disc), z (disc), s (disc), work (kernels::texletWorkSize (disc));
  std::vector<int> pixel (disc);
  std::vector<unsigned char> mask (disc);
  const kernels::TexletScratch<S> ws = {x.data (), y.data (), z.data (), s.data (), work.data (), pixel.data (),
                                        mask.data ()};
  DeviceFrame frame;
  frame.cloud = {cloud.data (), width * sizeof (DevicePoint), width, height};
  frame.camera = camera;
  frame.noise = noise;
  frame.colour = colour;
  const kernels::HexGrid grid = frameGrid (width, height, params);
  out.resize (grid.size ());
  for (int i = 0; i < grid.size (); ++i)
  {
    int u, v;
    kernels::hexCentre (grid, i, u, v);
    deviceTexlet (frame, fs, u, v, ws, out[i]);
  }
}

/** \brief Host reference of the back-projection (row-major, width x height). */
inline void
backProjectReference (const std::vector<std::uint16_t> &depth_mm, int width, int height, const DeviceCamera &camera,
                      std::vector<DevicePoint> &cloud)
{
  cloud.resize (static_cast<std::size_t> (width) * height);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      cloud[static_cast<std::size_t> (v) * width + u] =
          backProjectPixel (camera, u, v, depth_mm[static_cast<std::size_t> (v) * width + u]);
}

} // namespace gpu
} // namespace texlet
} // namespace pcl
