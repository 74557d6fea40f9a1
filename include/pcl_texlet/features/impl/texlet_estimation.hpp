/*
 * pcl_texlet: implementation of TexletEstimation and computeTexlet.
 */
#pragma once

#include <pcl_texlet/camera/camera_estimation.h>
#include <pcl_texlet/camera/valid_point.h>
#include <pcl_texlet/features/cloud_points.h>
#include <pcl_texlet/features/frame_settings.h>
#include <pcl_texlet/features/texlet_estimation.h>
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/texlet_stages.h>

#include <pcl/common/point_tests.h>
#include <pcl/exceptions.h>
#include <pcl/point_types.h> // pcl::traits::has_color_v

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <typeinfo>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pcl
{
namespace texlet
{
namespace detail
{

/** \brief kernels::computeTexlet in double precision, compiled into the library for the
  * baseline (src/features/texlet_estimation.cpp) and for x86-64-v3 with AVX2 intrinsics
  * (src/features/texlet_kernel_x86_64_v3.cpp); the first call picks the one the processor runs.
  */
PCL_EXPORTS void
computeTexletKernel (const kernels::Neighbourhood<double> &nb, const kernels::TexletSettings<double> &settings,
                     std::uint32_t texlet, unsigned char *mask, double *work, kernels::TexletResult<double> &out);

/** \brief The noise model's context of a point at pixel (u, v), depth z (metres) and grey
  * level \a intensity (NaN: unknown); the covariates a frame does not carry (frame index, f b,
  * projectors) come from \a base.
  */
inline PixelContext
pointContext (const CameraModel &camera, int u, int v, double z, double intensity, const PixelContext &base)
{
  PixelContext ctx = PixelContextBuilder (base).at (u, v, camera.principalPointDistance (u, v), z * 1000.0);
  ctx.intensity = intensity;
  return ctx;
}

/** \brief Depth SD in metres of a point at pixel (u, v), depth z (metres) and grey level
  * \a intensity (NaN: unknown); the other covariates as pointContext.
  */
inline double
depthSigmaMetres (const NoiseModel &noise, const CameraModel &camera, int u, int v, double z,
                  const PixelContext &base = PixelContext (),
                  double intensity = std::numeric_limits<double>::quiet_NaN ())
{
  return noise.sigmaMm (pointContext (camera, u, v, z, intensity, base)) * 1e-3;
}

/** \brief The factor (z - b) / z that takes the noise model's bias b at a reading of depth z
  * (metres) at pixel (u, v) off its depth, and off its point along its ray; 1 where b is not
  * finite or the point would move behind the camera. Covariates as pointContext.
  */
inline double
unbiasedDepthScale (const NoiseModel &noise, const CameraModel &camera, int u, int v, double z, const PixelContext &base,
                    double intensity)
{
  const double z_mm = z * 1000.0;
  const double s = (z_mm - noise.biasMm (pointContext (camera, u, v, z, intensity, base))) / z_mm;
  return std::isfinite (s) && s > 0.0 ? s : 1.0;
}

/** \brief Row \a v, columns [\a u0, \a u1), of \a out (a copy of \a cloud): each valid reading with
  * the noise model's bias taken off (unbiasedDepthScale).
  */
template <typename PointInT> void
unbiasReadings (const pcl::PointCloud<PointInT> &cloud, const CameraModel &camera, const NoiseModel &noise,
                const PixelContext &base, int v, int u0, int u1, pcl::PointCloud<PointInT> &out)
{
  for (int u = u0; u < u1; ++u)
  {
    const PointInT &p = cloud (u, v);
    if (!isValidDepthPoint (p))
      continue;
    const double s = unbiasedDepthScale (noise, camera, u, v, p.z, base, CloudPoints<PointInT>::intensity (p));
    PointInT &q = out (u, v);
    q.x = static_cast<float> (p.x * s);
    q.y = static_cast<float> (p.y * s);
    q.z = static_cast<float> (p.z * s);
  }
}

/** \brief An organised cloud with its depth noise as a frame of the texlet stages
  * (kernels/texlet_stages.h): the per-pixel SD image when there is one, the noise model where
  * not, and the rescale of a texlet's covariances to its own viewing angle.
  */
template <typename PointInT>
class CloudFrame : public CloudPoints<PointInT>
{
public:
  /** \param sigma_m per-pixel depth SD in metres, or null to evaluate the noise model here
    * \param context the noise model's covariates that a frame does not carry (frame index, f b,
    *        projectors), or null for the defaults
    * \param radius_px per-pixel distance from the principal point (the camera's), or null
    * \param viewpoint the point the normals face (the viewing rays start there)
    */
  CloudFrame (const pcl::PointCloud<PointInT> &cloud, const CameraModel &camera, const NoiseModel &noise,
              const double *sigma_m, const PixelContext *context, const double *radius_px, const float viewpoint[3])
    : CloudPoints<PointInT> (cloud), camera_ (camera), noise_ (noise), sigma_m_ (sigma_m), radius_px_ (radius_px),
      context_ (context ? *context : PixelContext ()), viewpoint_ {viewpoint[0], viewpoint[1], viewpoint[2]}
  {
    // The image's size sets the correlation lengths of offsets shared along its lines.
    context_.image_width_px = cloud.width;
    context_.image_height_px = cloud.height;
    // Does the model's variance depend on the incidence angle? Then each texlet's covariances
    // are rescaled to its own viewing angle (see varianceScale).
    PixelContext a = context_, b = context_;
    a.depth_mm = b.depth_mm = 2000.0;
    b.cos_incidence = 0.5;
    const double sa = noise.sigmaMm (a), sb = noise.sigmaMm (b);
    angle_dependent_ = std::isfinite (sa) && std::isfinite (sb) && sa != sb;
    polynomial_only_ = noise.isPolynomialOnly (polynomial_);
    sd_polynomial_ = noise.depthSdIsPolynomial (polynomial_);
  }

  /** Depth SD in metres of the point at pixel \a index with depth z (metres), from the
    * per-pixel image when there is one. */
  double
  sigma (int index, double z) const
  {
    const double s = sigma_m_ ? sigma_m_[index] : std::numeric_limits<double>::quiet_NaN ();
    return std::isfinite (s) ? s : modelSigma (index % this->width (), index / this->width (), z);
  }

  /** Depth SD in metres from the noise model at pixel (u, v) and depth z (metres). */
  double
  modelSigma (int u, int v, double z) const
  {
    if (sd_polynomial_) // the same bits without the noise terms' virtual calls
    {
      const double r = radius_px_ ? radius_px_[static_cast<std::size_t> (v) * this->width () + u]
                                  : camera_.principalPointDistance (u, v);
      return kernels::polynomialSigmaMm (polynomial_, r, z * 1000.0, noise_.minSigmaMm ()) * 1e-3;
    }
    return depthSigmaMetres (noise_, camera_, u, v, z, context_, this->intensity (this->point (u, v)));
  }

  /** The model at a texlet's centre pixel (u, v) and depth z (metres), from one evaluation: its
    * depth SD (as modelSigma), and the part of its variance that the texlet's points share: the
    * variance shared by a column (or a row) of pixels within a frame (bands, frame offsets) over
    * the whole, with its correlation length across those lines at this image's size, and the part
    * that neighbours share over a window. A model with both column and row variance shares both
    * along the larger one's lines (docs/texlet_covariances.md).
    */
  kernels::CentreNoise
  centreNoise (int u, int v, double z) const
  {
    kernels::CentreNoise s;
    if (polynomial_only_)
    {
      s.sigma = modelSigma (u, v, z);
      return s;
    }
    const PixelContext ctx = pointContext (camera_, u, v, z, this->intensity (this->point (u, v)), context_);
    const NoiseMoments m = noise_.moments (ctx);
    s.sigma = m.sigma_mm * 1e-3;
    const double total = m.sigma_mm * m.sigma_mm, shared = m.sharedVarianceMm2 ();
    s.fraction = total > 0.0 && std::isfinite (shared) ? shared / total : 0.0;
    s.lines_are_rows = m.row_variance_mm2 > m.column_variance_mm2;
    s.line_correlation_px = s.lines_are_rows ? m.row_correlation_px : m.column_correlation_px;
    s.window_fraction = total > 0.0 ? m.window_share * m.variance_mm2 / total : 0.0;
    s.window_px = m.window_px;
    return s;
  }

  /** The depth variances are evaluated per pixel before the fit, at a frontal view (a pixel
    * alone has no normal). Once the texlet's normal is known, the model's variance at the
    * centre pixel for the texlet's own incidence angle (between N and the viewing ray) over
    * that at a frontal view scales every disc point's variance alike, and so (first-order
    * propagation is linear in the variances) Sigma_P and Sigma_N.
    */
  double
  varianceScale (int cu, int cv, const kernels::TexletResult<double> &r) const
  {
    if (!angle_dependent_)
      return 1.0;
    const double rx = r.P.x - viewpoint_[0], ry = r.P.y - viewpoint_[1], rz = r.P.z - viewpoint_[2];
    const double rn = std::sqrt (rx * rx + ry * ry + rz * rz);
    const double nn = std::sqrt (r.N.x * r.N.x + r.N.y * r.N.y + r.N.z * r.N.z);
    if (!(rn > 0) || !(nn > 0))
      return 1.0;
    PixelContext ctx = context_;
    ctx.u = cu;
    ctx.v = cv;
    ctx.radius_px = camera_.principalPointDistance (cu, cv);
    ctx.depth_mm = r.P.z * 1000.0;
    ctx.intensity = this->intensity (this->point (cu, cv));
    const double frontal = noise_.sigmaMm (ctx);
    ctx.cos_incidence = std::min (1.0, std::fabs (r.N.x * rx + r.N.y * ry + r.N.z * rz) / (rn * nn));
    const double oblique = noise_.sigmaMm (ctx);
    const double f = oblique * oblique / (frontal * frontal);
    return std::isfinite (f) && f > 0 ? f : 1.0;
  }

private:
  const CameraModel &camera_;
  const NoiseModel &noise_;
  const double *sigma_m_;
  const double *radius_px_; // per-pixel distance from the principal point, or null
  PixelContext context_;
  float viewpoint_[3];
  bool angle_dependent_ = false;
  bool polynomial_only_ = false; // the noise model is the paper's polynomial alone
  bool sd_polynomial_ = false;   // its depth SD is the polynomial's (NoiseModel::depthSdIsPolynomial)
  kernels::PolynomialCoefficients polynomial_ = {};
};

/** \brief kernels::frameTexlet's kernel on the CPU: computeTexletKernel, the build the processor runs. */
struct LibraryTexletKernel
{
  void
  operator() (const kernels::Neighbourhood<double> &nb, const kernels::TexletSettings<double> &st, std::uint32_t texlet,
              unsigned char *mask, double *work, kernels::TexletResult<double> &out) const
  {
    computeTexletKernel (nb, st, texlet, mask, work, out);
  }
};

/** \brief Runs the texlet stages on an organised cloud with reusable scratch. One worker per
  * thread: nothing is allocated per texlet.
  */
template <typename PointInT>
class TexletWorker
{
public:
  /** \param sigma_m, context, radius_px, viewpoint as for CloudFrame */
  TexletWorker (const pcl::PointCloud<PointInT> &cloud, const TexletParameters &params, const CameraModel &camera,
                const NoiseModel &noise, const double *sigma_m, const PixelContext *context,
                const double *radius_px, const float viewpoint[3])
    : frame_ (cloud, camera, noise, sigma_m, context, radius_px, viewpoint)
  {
    const int n = kernels::pixelDiscSize (params.radius);
    du_.resize (n);
    dv_.resize (n);
    kernels::pixelDiscOffsets (params.radius, du_.data (), dv_.data (), n);
    offset_.resize (n);
    for (int o = 0; o < n; ++o)
      offset_[o] = static_cast<std::ptrdiff_t> (dv_[o]) * cloud.width + du_[o];
    x_.resize (n); y_.resize (n); z_.resize (n); s_.resize (n);
    pixel_.resize (n);
    mask_.resize (n);
    work_.resize (kernels::texletWorkSize (n));
    kernels::PixelDisc disc;
    disc.du = du_.data ();
    disc.dv = dv_.data ();
    disc.linear = offset_.data ();
    disc.size = n;
    disc.radius = params.radius;
    settings_ = frameSettings<double> (params, viewpoint, disc, noise.minSigmaMm () * 1e-3);
    if (!params.exact_window_form)
    {
      window_forms_.reset (new kernels::WindowDiscForms<double> (du_.data (), dv_.data (), n));
      settings_.window_disc_forms = window_forms_.get ();
    }
    scratch_ = {x_.data (), y_.data (), z_.data (), s_.data (), work_.data (), pixel_.data (), mask_.data ()};
  }

  /** \brief Texlet at pixel \a centre into \a out; false (and NaN) where none could be made. */
  template <typename PointOutT> bool
  compute (pcl::index_t centre, PointOutT &out)
  {
    const int w = frame_.width ();
    return kernels::frameTexlet (frame_, settings_, static_cast<int> (centre % w), static_cast<int> (centre / w),
                                 scratch_, LibraryTexletKernel (), out);
  }

private:
  CloudFrame<PointInT> frame_;
  kernels::FrameSettings<double> settings_;
  kernels::TexletScratch<double> scratch_;
  std::vector<int> du_, dv_;
  std::vector<std::ptrdiff_t> offset_; // dv * width + du of each disc pixel
  std::vector<double> x_, y_, z_, s_, work_;
  std::vector<int> pixel_;
  std::vector<unsigned char> mask_;
  std::unique_ptr<kernels::WindowDiscForms<double>> window_forms_; // made per window width when first needed
};

inline void
requireOrganised (std::uint32_t width, std::uint32_t height, std::size_t size, const char *who)
{
  if (height <= 1 || static_cast<std::size_t> (width) * height != size)
  {
    std::ostringstream msg;
    msg << who << ": the input cloud is not organised (width " << width << ", height " << height << ", " << size
        << " points); texlets need the pixel grid of a depth image";
    throw pcl::UnorganizedPointCloudException (msg.str ());
  }
}

} // namespace detail
} // namespace texlet

template <typename PointInT, typename PointOutT> bool
computeTexlet (const pcl::PointCloud<PointInT> &cloud, pcl::index_t centre, const texlet::TexletParameters &params,
               const texlet::CameraModel &camera, const texlet::NoiseModel &noise, PointOutT &texlet)
{
  texlet::validate (params);
  texlet::detail::requireOrganised (cloud.width, cloud.height, cloud.size (), "pcl::computeTexlet");
  if (centre < 0 || static_cast<std::size_t> (centre) >= cloud.size ())
  {
    std::ostringstream msg;
    msg << "pcl::computeTexlet: centre index " << centre << " is outside the cloud (" << cloud.size () << " points)";
    throw pcl::BadArgumentException (msg.str ());
  }
  // The model's bias off the readings a texlet reads: its disc, its ring and its centre ray's
  // neighbours (up to 3 pixels beyond the disc), in a copy of the cloud.
  pcl::PointCloud<PointInT> unbiased;
  const bool unbias = params.remove_model_bias && noise.movesMean ();
  if (unbias)
  {
    unbiased = cloud;
    texlet::PixelContext base;
    base.image_width_px = cloud.width;
    base.image_height_px = cloud.height;
    const int w = static_cast<int> (cloud.width), h = static_cast<int> (cloud.height), reach = params.radius + 3;
    const int cu = static_cast<int> (centre % w), cv = static_cast<int> (centre / w);
    for (int v = std::max (0, cv - reach); v <= std::min (h - 1, cv + reach); ++v)
      texlet::detail::unbiasReadings (cloud, camera, noise, base, v, std::max (0, cu - reach),
                                      std::min (w, cu + reach + 1), unbiased);
  }
  texlet::detail::TexletWorker<PointInT> worker (unbias ? unbiased : cloud, params, camera, noise, nullptr, nullptr,
                                                 nullptr, params.viewpoint);
  return worker.compute (centre, texlet);
}

#define PCL_TEXLET_SETTER(field, value) \
  do { texlet::TexletParameters p = params_; p.field = value; texlet::validate (p); params_ = p; } while (0)

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setSpacing (int pixels) { PCL_TEXLET_SETTER (spacing, pixels); }

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setRadius (int pixels) { PCL_TEXLET_SETTER (radius, pixels); }

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setRansacIterations (int iterations)
{
  PCL_TEXLET_SETTER (ransac_iterations, iterations);
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setRansacThreshold (double metres)
{
  PCL_TEXLET_SETTER (ransac_threshold, metres);
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setRansacThresholdSigmas (double sigmas)
{
  PCL_TEXLET_SETTER (threshold_sigmas, sigmas);
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setPlaneFitMethod (texlet::PlaneFitMethod method)
{
  PCL_TEXLET_SETTER (fit, method);
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setRobustThresholdSigmas (double sigmas)
{
  PCL_TEXLET_SETTER (robust_sigmas, sigmas);
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setCentreDefinition (texlet::TexletCentre centre)
{
  PCL_TEXLET_SETTER (centre, centre);
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setUncertaintyMethod (texlet::UncertaintyMethod method)
{
  PCL_TEXLET_SETTER (uncertainty, method);
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setMonteCarloSamples (int samples)
{
  PCL_TEXLET_SETTER (samples, samples);
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setMinSupport (int points) { PCL_TEXLET_SETTER (min_support, points); }

#undef PCL_TEXLET_SETTER

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setViewPoint (float vpx, float vpy, float vpz)
{
  texlet::TexletParameters p = params_;
  p.viewpoint[0] = vpx;
  p.viewpoint[1] = vpy;
  p.viewpoint[2] = vpz;
  texlet::validate (p);
  params_ = p;
  use_sensor_origin_ = false;
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::getViewPoint (float &vpx, float &vpy, float &vpz) const
{
  float vp[3];
  viewPoint (vp);
  vpx = vp[0];
  vpy = vp[1];
  vpz = vp[2];
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::viewPoint (float vp[3]) const
{
  for (int i = 0; i < 3; ++i)
    vp[i] = !use_sensor_origin_ ? params_.viewpoint[i] : input_ ? input_->sensor_origin_.coeff (i) : 0.0f;
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::setParameters (const texlet::TexletParameters &params)
{
  texlet::validate (params);
  const bool new_viewpoint = !std::equal (params.viewpoint, params.viewpoint + 3, params_.viewpoint);
  params_ = params;
  if (new_viewpoint)
    use_sensor_origin_ = false;
}

template <typename PointInT, typename PointOutT> bool
TexletEstimation<PointInT, PointOutT>::initCompute ()
{
  // Feature::initCompute would set up a metric search; texlets use the pixel grid instead.
  if (!input_)
    throw pcl::InitFailedException ("pcl::TexletEstimation: no input cloud was given (setInputCloud)");
  texlet::detail::requireOrganised (input_->width, input_->height, input_->size (), "pcl::TexletEstimation");
  if (!indices_ || this->fake_indices_)
  {
    const texlet::kernels::HexGrid grid = texlet::kernels::makeHexGrid (input_->width, input_->height, params_.spacing);
    auto centres = std::make_shared<pcl::Indices> (grid.size ());
    for (int i = 0; i < grid.size (); ++i)
    {
      int u, v;
      texlet::kernels::hexCentre (grid, i, u, v);
      (*centres)[i] = static_cast<pcl::index_t> (v) * input_->width + u;
    }
    indices_ = centres;
    this->fake_indices_ = true;
  }
  else
  {
    for (const pcl::index_t i : *indices_)
      if (i < 0 || static_cast<std::size_t> (i) >= input_->size ())
      {
        std::ostringstream msg;
        msg << "pcl::TexletEstimation: index " << i << " is outside the input cloud (" << input_->size () << " points)";
        throw pcl::BadArgumentException (msg.str ());
      }
  }
  return true;
}

template <typename PointInT, typename PointOutT> void
TexletEstimation<PointInT, PointOutT>::computeFeature (PointCloudOut &output)
{
  const pcl::PointCloud<PointInT> &input = *input_;
  const int w = static_cast<int> (input.width), h = static_cast<int> (input.height);
#ifdef _OPENMP
  const int threads = threads_ == 0 ? omp_get_num_procs () : static_cast<int> (threads_);
#endif

  // Is there a valid point at all? The first one ends the search (a real frame has one in
  // its first rows), so this costs next to nothing.
  bool any_valid = false;
  for (std::size_t i = 0; i < input.size () && !any_valid; ++i)
    any_valid = texlet::isValidDepthPoint (input[i]);
  if (!any_valid)
    throw pcl::ComputeFailedException ("pcl::TexletEstimation: the input cloud has no valid point (all depth is "
                                       "invalid: NaN, infinite or not in front of the camera)");

  float viewpoint[3];
  viewPoint (viewpoint);
  if (!std::isfinite (viewpoint[0]) || !std::isfinite (viewpoint[1]) || !std::isfinite (viewpoint[2]))
  {
    std::ostringstream msg;
    msg << "pcl::TexletEstimation: the input cloud's sensor_origin_ (" << viewpoint[0] << ", " << viewpoint[1] << ", "
        << viewpoint[2] << "), the viewpoint the normals face, is not finite; set one with setViewPoint";
    throw pcl::BadArgumentException (msg.str ());
  }

  texlet::CameraModel::ConstPtr camera = camera_;
  if (!camera)
    camera = std::make_shared<texlet::PinholeModel> (texlet::estimatePinholeModel (input));

  // Per-pixel depth SD, once per frame (pixels are shared by the overlapping discs), in the
  // same parallel region as the texlets: one fork and join per frame.
  const bool need_sigma = params_.uncertainty != texlet::UncertaintyMethod::None;
  if (need_sigma)
    sigma_image_.resize (input.size ());
  texlet::kernels::PolynomialCoefficients polynomial = {};
  const bool polynomial_sd = noise_.depthSdIsPolynomial (polynomial);
  const double min_sigma_mm = noise_.minSigmaMm ();
  // The paper's model needs each pixel's distance from the principal point: a virtual call and
  // a hypot per pixel, the same for every frame of one camera, so kept. The five probes catch
  // a camera object changed in place.
  bool fill_radius = false;
  if (polynomial_sd && need_sigma)
  {
    const double probe[5] = {camera->principalPointDistance (0, 0), camera->principalPointDistance (w - 1, 0),
                             camera->principalPointDistance (0, h - 1), camera->principalPointDistance (w - 1, h - 1),
                             camera->principalPointDistance (w / 2, h / 2)};
    // A pinhole's distances are hypot (u - cx, v - cy): the same principal point gives the same
    // image, also for a camera estimated anew from each frame.
    const auto *pinhole = dynamic_cast<const texlet::PinholeModel *> (camera.get ());
    const auto *kept = dynamic_cast<const texlet::PinholeModel *> (radius_camera_.get ());
    const bool same_camera = camera == radius_camera_ ||
                             (pinhole && kept && typeid (*pinhole) == typeid (texlet::PinholeModel) &&
                              typeid (*kept) == typeid (texlet::PinholeModel) && pinhole->cx () == kept->cx () &&
                              pinhole->cy () == kept->cy ());
    fill_radius = !same_camera || radius_width_ != input.width || radius_height_ != input.height ||
                  !std::equal (probe, probe + 5, radius_probe_);
    if (fill_radius)
    {
      radius_image_.resize (input.size ());
      radius_camera_ = camera;
      radius_width_ = input.width;
      radius_height_ = input.height;
      std::copy (probe, probe + 5, radius_probe_);
    }
  }
  // The model's bias (a warm-up drift, a distortion map) taken off each reading's depth along its
  // ray, once per pixel: P and N then estimate the surface, not the biased readings.
  const bool unbias = params_.remove_model_bias && noise_.movesMean ();
  if (unbias)
    unbiased_cloud_ = input;
  const pcl::PointCloud<PointInT> &cloud = unbias ? unbiased_cloud_ : input;
  texlet::PixelContext frame_context = noise_context_;
  frame_context.image_width_px = w;
  frame_context.image_height_px = h;
  const auto n = static_cast<std::ptrdiff_t> (indices_->size ());
  std::size_t made = 0;
#pragma omp parallel num_threads(threads) reduction(+ : made)
  {
    if (unbias)
    {
#pragma omp for schedule(static)
      for (int v = 0; v < h; ++v)
        texlet::detail::unbiasReadings (input, *camera, noise_, frame_context, v, 0, w, unbiased_cloud_);
    }
    if (fill_radius)
    {
#pragma omp for schedule(static)
      for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u)
          radius_image_[static_cast<std::size_t> (v) * w + u] = camera->principalPointDistance (u, v);
    }
    if (need_sigma)
    {
#pragma omp for schedule(static)
      for (int v = 0; v < h; ++v)
      {
        double *const row = sigma_image_.data () + static_cast<std::size_t> (v) * w;
        if (polynomial_sd)
          // The paper's model (the default), or one whose other terms leave the SD as it is: the
          // same bits as NoiseModel::sigmaMm without its virtual calls, a large part of an
          // analytic frame's cost (docs/benchmarks.md).
        {
          const double *const radius = radius_image_.data () + static_cast<std::size_t> (v) * w;
          const PointInT *const points = &cloud (0, v);
          for (int u = 0; u < w; ++u)
            row[u] = texlet::isValidDepthPoint (points[u])
                         ? texlet::kernels::polynomialSigmaMm (polynomial, radius[u], points[u].z * 1000.0,
                                                               min_sigma_mm) * 1e-3
                         : std::numeric_limits<double>::quiet_NaN ();
        }
        else
          for (int u = 0; u < w; ++u)
          {
            const PointInT &p = cloud (u, v);
            row[u] = texlet::isValidDepthPoint (p)
                         ? texlet::detail::depthSigmaMetres (noise_, *camera, u, v, p.z, noise_context_,
                                                             texlet::detail::CloudPoints<PointInT>::intensity (p))
                         : std::numeric_limits<double>::quiet_NaN ();
          }
      }
    }
    texlet::detail::TexletWorker<PointInT> worker (cloud, params_, *camera, noise_,
                                                   need_sigma ? sigma_image_.data () : nullptr, &noise_context_,
                                                   polynomial_sd && need_sigma ? radius_image_.data () : nullptr,
                                                   viewpoint);
#pragma omp for schedule(dynamic, 64)
    for (std::ptrdiff_t i = 0; i < n; ++i)
      made += worker.compute ((*indices_)[i], output[i]) ? 1 : 0;
  }
  output.is_dense = made == indices_->size ();
}

} // namespace pcl
