/*
 * pcl_texlet GPU: one texlet of a whole frame, as the CPU path computes it, for host and device.
 *
 * TexletEstimation (impl/texlet_estimation.hpp) gathers each texlet's pixel disc from the
 * organised cloud, evaluates the noise model per pixel, derives the RANSAC threshold and runs
 * kernels::computeTexlet. The GPU backend must do the same without PCL types, so this header
 * repeats that gathering step on plain data (a pitched image of DevicePoint, a camera and a
 * noise model as PODs) and calls the very same computeTexlet with the same Philox key (the
 * centre pixel's index). Everything is PCL_TEXLET_HD: the CUDA kernel runs frameTexlet once
 * per thread, and computeTexletsReference runs it on the host, which gives the GPU tests a
 * CPU reference on machines without PCL.
 *
 * Needs no PCL: only the kernels, Random123 and (for the host compiler) CUDA's runtime API header.
 */
#pragma once

#include <pcl_texlet/gpu/random123_host_sincospi.h> // before Random123, see there

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/noise_terms.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/plumb_bob.h>
#include <pcl_texlet/kernels/texlet_kernel.h>
#include <pcl_texlet/features/texlet_parameters.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace pcl
{
namespace gpu
{

namespace kernels = texlet::kernels;

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
  * pcl::PointCloud<pcl::Texlet>. Fields and units as pcl::Texlet.
  */
struct alignas (16) DeviceTexlet
{
  float x, y, z, data_w;                 ///< centre P, metres; data_w = 1 as in PCL
  float normal_x, normal_y, normal_z, data_nw; ///< unit normal facing the viewpoint; data_nw = 0
  std::uint32_t rgba;                    ///< mean colour of the inliers, PCL's packing (a r g b)
  float curvature;                       ///< l0 / (l0 + l1 + l2)
  float data_c2, data_c3;                ///< padding, 0
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
  hasDistortion () const
  {
    return distortion.k1 != 0 || distortion.k2 != 0 || distortion.p1 != 0 || distortion.p2 != 0 || distortion.k3 != 0;
  }

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
    const double xd = (u - cx) / fx, yd = (v - cy) / fy;
    if (!hasDistortion ())
    {
      x = xd;
      y = yd;
      return;
    }
    if (!kernels::undistortPlumbBob (distortion, xd, yd, x, y))
      x = y = NAN;
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

/** \brief Everything frameTexlet needs besides the cloud, fixed for a frame. */
template <typename S>
struct FrameTexletContext
{
  DeviceCamera camera;
  DeviceNoise noise;
  texlet::TexletParameters params;
  kernels::TexletSettings<S> settings; ///< from params; the threshold is set per texlet
  const int *disc_du = nullptr;        ///< pixel disc offsets (pixelDiscOffsets), disc entries
  const int *disc_dv = nullptr;
  int disc = 0;
  bool colour = false;                 ///< the cloud's rgba words hold colour

  /** \brief Depth SD in metres at pixel (u, v) and depth z (metres): depthSigmaMetres. */
  PCL_TEXLET_HD double
  sigmaMetres (int u, int v, double z) const
  {
    return noise.sigmaMm (camera.principalPointDistance (u, v), z * 1000.0) * 1e-3;
  }
};

/** \brief The kernel's settings from the user's parameters, as TexletWorker sets them. */
template <typename S> kernels::TexletSettings<S>
texletSettings (const texlet::TexletParameters &p)
{
  kernels::TexletSettings<S> s;
  s.ransac_iterations = p.ransac_iterations;
  s.fit = p.fit;
  s.uncertainty = p.uncertainty;
  s.samples = p.samples;
  s.seed = p.seed;
  s.min_support = p.min_support;
  s.viewpoint = {S (p.viewpoint[0]), S (p.viewpoint[1]), S (p.viewpoint[2])};
  return s;
}

/** \brief Scratch of one texlet: disc-sized x, y, z, sigma and mask, and texletWorkSize (disc) work values. */
template <typename S>
struct TexletScratch
{
  S *x, *y, *z, *sigma, *work;
  unsigned char *mask;
};

/** \brief A texlet that could not be made: NaN, support 0 (TexletWorker::fail). */
PCL_TEXLET_HD void
failTexlet (std::uint32_t centre, DeviceTexlet &out)
{
  const float nan = NAN;
  out.x = out.y = out.z = nan;
  out.data_w = 1.0f;
  out.normal_x = out.normal_y = out.normal_z = nan;
  out.data_nw = 0.0f;
  out.rgba = 0;
  out.curvature = out.radius = nan;
  out.data_c2 = out.data_c3 = 0.0f;
  out.support = 0;
  out.cov_p_xx = out.cov_p_xy = out.cov_p_xz = out.cov_p_yy = out.cov_p_yz = out.cov_p_zz = nan;
  out.cov_n_11 = out.cov_n_12 = out.cov_n_22 = nan;
  out.pixel_index = centre;
}

/** \brief The texlet centred on pixel (cu, cv) of \a cloud into \a out, exactly as
  * TexletWorker::compute does on the CPU: the disc's valid points in disc order, the
  * hexagonal ring, per-point depth SDs from the noise model, the automatic threshold from the
  * mean depth, then kernels::computeTexlet keyed by the centre pixel's index.
  * \return false (and a NaN texlet) where none could be made
  */
template <typename S> PCL_TEXLET_HD bool
frameTexlet (const CloudView &cloud, const FrameTexletContext<S> &ctx, int cu, int cv, const TexletScratch<S> &ws,
             DeviceTexlet &out)
{
  const int w = cloud.width, h = cloud.height;
  const std::uint32_t centre = static_cast<std::uint32_t> (cv) * static_cast<std::uint32_t> (w) + cu;
  const bool need_sigma = ctx.params.uncertainty != texlet::UncertaintyMethod::None;
  kernels::Neighbourhood<S> nb;
  int count = 0;
  double zsum = 0.0;
  for (int o = 0; o < ctx.disc; ++o)
  {
    const int u = cu + ctx.disc_du[o], v = cv + ctx.disc_dv[o];
    if (u < 0 || v < 0 || u >= w || v >= h)
      continue;
    const DevicePoint &p = cloud.at (u, v);
    if (!isValidDevicePoint (p))
      continue;
    ws.x[count] = p.x;
    ws.y[count] = p.y;
    ws.z[count] = p.z;
    if (need_sigma)
      ws.sigma[count] = static_cast<S> (ctx.sigmaMetres (u, v, p.z));
    zsum += p.z;
    ++count;
  }
  nb.x = ws.x;
  nb.y = ws.y;
  nb.z = ws.z;
  nb.sigma = need_sigma ? ws.sigma : nullptr;
  nb.count = count;
  if (count == 0)
  {
    failTexlet (centre, out);
    return false;
  }

  // Ring for normal averaging: the centre and its six hexagonal neighbours at `radius`.
  for (int k = 0; k < 7; ++k)
  {
    int du = 0, dv = 0;
    if (k > 0)
      kernels::hexNeighbourOffset (k - 1, ctx.params.radius, du, dv);
    const int u = cu + du, v = cv + dv;
    nb.ring_valid[k] = false;
    nb.ring[k] = {S (0), S (0), S (0)};
    nb.ring_sigma[k] = S (0);
    if (u < 0 || v < 0 || u >= w || v >= h || !isValidDevicePoint (cloud.at (u, v)))
      continue;
    const DevicePoint &p = cloud.at (u, v);
    nb.ring[k] = {S (p.x), S (p.y), S (p.z)};
    nb.ring_valid[k] = true;
    nb.ring_sigma[k] = static_cast<S> (ctx.sigmaMetres (u, v, p.z));
  }

  kernels::TexletSettings<S> settings = ctx.settings;
  settings.threshold = static_cast<S> (ctx.params.ransac_threshold > 0.0
                                           ? ctx.params.ransac_threshold
                                           : ctx.params.threshold_sigmas * ctx.sigmaMetres (cu, cv, zsum / count));

  kernels::TexletResult<S> r;
  kernels::computeTexlet (nb, settings, centre, ws.mask, ws.work, r);
  if (!r.ok)
  {
    failTexlet (centre, out);
    return false;
  }

  out.x = static_cast<float> (r.P.x);
  out.y = static_cast<float> (r.P.y);
  out.z = static_cast<float> (r.P.z);
  out.data_w = 1.0f;
  out.normal_x = static_cast<float> (r.N.x);
  out.normal_y = static_cast<float> (r.N.y);
  out.normal_z = static_cast<float> (r.N.z);
  out.data_nw = 0.0f;
  out.curvature = static_cast<float> (r.curvature);
  out.data_c2 = out.data_c3 = 0.0f;
  out.radius = static_cast<float> (r.radius);
  out.support = static_cast<std::uint32_t> (r.support);
  out.cov_p_xx = static_cast<float> (r.cov_p[0]);
  out.cov_p_xy = static_cast<float> (r.cov_p[1]);
  out.cov_p_xz = static_cast<float> (r.cov_p[2]);
  out.cov_p_yy = static_cast<float> (r.cov_p[3]);
  out.cov_p_yz = static_cast<float> (r.cov_p[4]);
  out.cov_p_zz = static_cast<float> (r.cov_p[5]);
  out.cov_n_11 = static_cast<float> (r.cov_n[0]);
  out.cov_n_12 = static_cast<float> (r.cov_n[1]);
  out.cov_n_22 = static_cast<float> (r.cov_n[2]);
  out.pixel_index = centre;

  out.rgba = 0;
  if (ctx.colour)
  {
    // Mean colour of the inliers: walk the disc again in the same order to find their pixels.
    unsigned rs = 0, gs = 0, bs = 0, n = 0;
    int k = 0;
    for (int o = 0; o < ctx.disc; ++o)
    {
      const int u = cu + ctx.disc_du[o], v = cv + ctx.disc_dv[o];
      if (u < 0 || v < 0 || u >= w || v >= h)
        continue;
      const DevicePoint &p = cloud.at (u, v);
      if (!isValidDevicePoint (p))
        continue;
      if (ws.mask[k++])
      {
        rs += (p.rgba >> 16) & 0xffu;
        gs += (p.rgba >> 8) & 0xffu;
        bs += p.rgba & 0xffu;
        ++n;
      }
    }
    const unsigned r8 = (rs + n / 2) / n, g8 = (gs + n / 2) / n, b8 = (bs + n / 2) / n;
    out.rgba = (0xffu << 24) | (r8 << 16) | (g8 << 8) | b8;
  }
  return true;
}

/** \brief The hexagonal grid of centres TexletEstimation uses for a frame. */
inline kernels::HexGrid
frameGrid (int width, int height, const texlet::TexletParameters &params)
{
  return kernels::makeHexGrid (width, height, params.spacing);
}

/** \brief Host reference: every texlet of the frame's hexagonal grid, one after the other,
  * through frameTexlet (the GPU's code compiled for the host).
  */
template <typename S> void
computeTexletsReference (const std::vector<DevicePoint> &cloud, int width, int height, const DeviceCamera &camera,
                         const DeviceNoise &noise, const texlet::TexletParameters &params, bool colour,
                         std::vector<DeviceTexlet> &out)
{
  FrameTexletContext<S> ctx;
  ctx.camera = camera;
  ctx.noise = noise;
  ctx.params = params;
  ctx.settings = texletSettings<S> (params);
  ctx.colour = colour;
  const int disc = kernels::pixelDiscSize (params.radius);
  std::vector<int> du (disc), dv (disc);
  kernels::pixelDiscOffsets (params.radius, du.data (), dv.data (), disc);
  ctx.disc_du = du.data ();
  ctx.disc_dv = dv.data ();
  ctx.disc = disc;
  std::vector<S> x (disc), y (disc), z (disc), s (disc), work (kernels::texletWorkSize (disc));
  std::vector<unsigned char> mask (disc);
  const TexletScratch<S> ws = {x.data (), y.data (), z.data (), s.data (), work.data (), mask.data ()};
  const CloudView view = {cloud.data (), width * sizeof (DevicePoint), width, height};
  const kernels::HexGrid grid = frameGrid (width, height, params);
  out.resize (grid.size ());
  for (int i = 0; i < grid.size (); ++i)
  {
    int u, v;
    kernels::hexCentre (grid, i, u, v);
    frameTexlet (view, ctx, u, v, ws, out[i]);
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
} // namespace pcl
