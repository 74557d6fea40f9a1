#include <pcl_texlet/noise/noise_terms.h>
#include <pcl_texlet/kernels/effect_terms.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{

namespace
{

/** The depth the terms work at: the noise-free one where known, else the measured one. */
double
depthOf (const PixelContext &ctx)
{
  return std::isfinite (ctx.true_depth_mm) && ctx.true_depth_mm > 0 ? ctx.true_depth_mm : ctx.depth_mm;
}

double
jacobian (const PixelContext &ctx)
{
  return kernels::depthPerDisparityMm (depthOf (ctx), ctx.fb_px_m);
}

void
unknownSetting (const std::string &term, const std::string &name)
{
  throw pcl::BadArgumentException ("noise term '" + term + "': unknown setting '" + name + "'");
}

} // namespace

EffectTerm::EffectTerm (std::string name, std::vector<std::string> parameter_names, std::vector<double> values)
  : name_ (std::move (name)), names_ (std::move (parameter_names)), values_ (std::move (values))
{
}

void
EffectTerm::setParameters (const std::vector<double> &values)
{
  if (values.size () != values_.size ())
  {
    std::ostringstream msg;
    msg << "noise term '" << name_ << "': expected " << values_.size () << " parameters, got " << values.size ();
    throw pcl::BadArgumentException (msg.str ());
  }
  for (std::size_t i = 0; i < values.size (); ++i)
    if (!std::isfinite (values[i]))
      throw pcl::BadArgumentException ("noise term '" + name_ + "': parameter " + names_[i] + " is not finite");
  values_ = values;
}

void
EffectTerm::setSetting (const std::string &name, double)
{
  unknownSetting (name_, name);
}

// --- axial_quadratic ---------------------------------------------------------------------------
double
AxialQuadraticTerm::variance (const PixelContext &ctx) const
{
  const double s = values_[0] * jacobian (ctx);
  return s * s;
}

std::string
AxialQuadraticTerm::physics () const
{
  return "triangulation: the correlation peak is found to a constant fraction of a pixel, so the depth SD grows "
         "with z^2 / (f b)";
}

// --- radial ------------------------------------------------------------------------------------
double
RadialTerm::varianceFactor (const PixelContext &ctx) const
{
  return kernels::radialVarianceFactor (values_[0], ctx.radius_px, r_ref_);
}

void
RadialTerm::setSetting (const std::string &name, double value)
{
  if (name != "reference_radius_px")
    unknownSetting (name_, name);
  if (!(value > 0) || !std::isfinite (value))
    throw pcl::BadArgumentException ("noise term 'radial': reference_radius_px must be positive");
  r_ref_ = value;
}

std::string
RadialTerm::physics () const
{
  return "vignetting and the projector's fall-off dim the dot pattern toward the border, where it localises worse";
}

// --- disparity_quantization --------------------------------------------------------------------
void
DisparityQuantizationTerm::transformMoments (const PixelContext &ctx, double &bias_mm, double &variance_mm2) const
{
  const double step = std::fabs (values_[0]);
  if (!(step > 0))
    return;
  const double J = jacobian (ctx);
  if (!(J > 0))
    return;
  if (!(std::isfinite (ctx.true_depth_mm) && ctx.true_depth_mm > 0))
  {
    // The phase of a measured (already quantised) depth says nothing: the phase average.
    variance_mm2 += J * J * step * step / 12.0;
    return;
  }
  // The disparity before rounding: the true one moved by the other terms' bias.
  const double d0 = ctx.fb_px_m * 1000.0 / ctx.true_depth_mm - bias_mm / J;
  double mean_offset = 0, var_px = 0;
  kernels::quantizedMoments (d0, std::sqrt (variance_mm2) / J, step, mean_offset, var_px);
  bias_mm -= J * mean_offset;
  variance_mm2 = J * J * var_px;
}

std::string
DisparityQuantizationTerm::physics () const
{
  return "the sensor reports disparity in sub-pixel steps (1/8 px on the Kinect v1): depth comes in steps of "
         "z^2 step / (f b), so SD and mean swing with the true disparity's sub-step phase";
}

// --- incidence_angle ---------------------------------------------------------------------------
double
IncidenceAngleTerm::varianceFactor (const PixelContext &ctx) const
{
  return kernels::incidenceVarianceFactor (values_[0], ctx.cos_incidence);
}

std::string
IncidenceAngleTerm::physics () const
{
  return "on an oblique surface the dot pattern is stretched by 1 / cos(theta) across the correlation window, "
         "blurring the correlation peak";
}

// --- vertical_stripes --------------------------------------------------------------------------
double
VerticalStripesTerm::columnVariance (const PixelContext &ctx) const
{
  const double s = values_[0] * jacobian (ctx);
  return s * s;
}

double
VerticalStripesTerm::frameVariance (const PixelContext &ctx) const
{
  const double bands = values_[1] > 1.0 ? values_[1] : 1.0;
  return columnVariance (ctx) / bands;
}

std::string
VerticalStripesTerm::physics () const
{
  return "the image is cut into column bands whose disparity offsets change over time (the paper's Fig. 4), "
         "so pixels of one column share an offset in each frame";
}

// --- depth_distortion --------------------------------------------------------------------------
DepthDistortionTerm::DepthDistortionTerm (int image_width, int image_height, int nodes_x, int nodes_y)
  : EffectTerm ("depth_distortion", {}, {}), width_ (image_width), height_ (image_height), nodes_x_ (nodes_x),
    nodes_y_ (nodes_y)
{
  resize ();
}

void
DepthDistortionTerm::resize ()
{
  if (width_ < 2 || height_ < 2 || nodes_x_ < 2 || nodes_y_ < 2 || nodes_x_ * nodes_y_ > 100000)
  {
    std::ostringstream msg;
    msg << "noise term 'depth_distortion': needs an image of at least 2x2 pixels and 2 to 100000 nodes with at "
           "least 2 a side (got image "
        << width_ << "x" << height_ << ", nodes " << nodes_x_ << "x" << nodes_y_ << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
  names_.clear ();
  for (int j = 0; j < nodes_y_; ++j)
    for (int i = 0; i < nodes_x_; ++i)
      names_.push_back ("offset_" + std::to_string (i) + "_" + std::to_string (j));
  values_.assign (names_.size (), 0.0);
}

double
DepthDistortionTerm::offsetPx (double u, double v) const
{
  return kernels::bilinearGrid (values_.data (), nodes_x_, nodes_y_, width_, height_, u, v);
}

double
DepthDistortionTerm::bias (const PixelContext &ctx) const
{
  return -jacobian (ctx) * offsetPx (ctx.u, ctx.v);
}

std::vector<std::pair<std::string, double>>
DepthDistortionTerm::settings () const
{
  return {{"image_width", double (width_)}, {"image_height", double (height_)}, {"nodes_x", double (nodes_x_)},
          {"nodes_y", double (nodes_y_)}};
}

void
DepthDistortionTerm::setSetting (const std::string &name, double value)
{
  if (!(value == std::floor (value)) || !(std::fabs (value) < 1e6))
    throw pcl::BadArgumentException ("noise term 'depth_distortion': setting " + name + " must be a whole number");
  const int n = static_cast<int> (value);
  if (name == "image_width")
    width_ = n;
  else if (name == "image_height")
    height_ = n;
  else if (name == "nodes_x")
    nodes_x_ = n;
  else if (name == "nodes_y")
    nodes_y_ = n;
  else
    unknownSetting (name_, name);
  resize ();
}

std::string
DepthDistortionTerm::physics () const
{
  return "residual lens distortion and an imperfect reference pattern leave a fixed disparity error per pixel, a "
         "static depth bias growing with z^2";
}

// --- interference ------------------------------------------------------------------------------
double
InterferenceTerm::varianceFactor (const PixelContext &ctx) const
{
  return kernels::interferenceVarianceFactor (values_[0], ctx.active_projectors);
}

std::string
InterferenceTerm::physics () const
{
  return "other sensors' projected dots overlay the sensor's own pattern and confuse the correlation: more noise "
         "(and holes) with every other active projector";
}

// --- temporal_drift ----------------------------------------------------------------------------
double
TemporalDriftTerm::bias (const PixelContext &ctx) const
{
  if (!std::isfinite (ctx.frame))
    return 0.0;
  return -jacobian (ctx) * kernels::driftDisparityOffset (values_[0], values_[1], ctx.frame);
}

std::string
TemporalDriftTerm::physics () const
{
  return "while the sensor warms up the projector and housing expand and the laser's wavelength shifts: a "
         "disparity offset that decays over the first frames";
}

// --- lateral_noise -----------------------------------------------------------------------------
double
LateralNoiseTerm::variance (const PixelContext &ctx) const
{
  if (!std::isfinite (ctx.edge_distance_px))
    return 0.0;
  return kernels::lateralVariance (values_[0], values_[1], ctx.edge_distance_px);
}

std::string
LateralNoiseTerm::physics () const
{
  return "the correlation window straddling a depth edge matches either side, so readings near edges jump "
         "between the two surfaces";
}

// --- catalogue ---------------------------------------------------------------------------------
const std::vector<std::string> &
noiseEffectNames ()
{
  static const std::vector<std::string> names = {"axial_quadratic",  "radial",           "disparity_quantization",
                                                 "incidence_angle",  "vertical_stripes", "depth_distortion",
                                                 "interference",     "temporal_drift",   "lateral_noise"};
  return names;
}

NoiseTerm::Ptr
makeNoiseTerm (const std::string &name)
{
  if (name == "polynomial")
    return std::make_shared<PolynomialSigmaTerm> ();
  if (name == "axial_quadratic")
    return std::make_shared<AxialQuadraticTerm> (0.0);
  if (name == "radial")
    return std::make_shared<RadialTerm> ();
  if (name == "disparity_quantization")
    return std::make_shared<DisparityQuantizationTerm> (0.0);
  if (name == "incidence_angle")
    return std::make_shared<IncidenceAngleTerm> ();
  if (name == "vertical_stripes")
    return std::make_shared<VerticalStripesTerm> ();
  if (name == "depth_distortion")
    return std::make_shared<DepthDistortionTerm> ();
  if (name == "interference")
    return std::make_shared<InterferenceTerm> ();
  if (name == "temporal_drift")
    return std::make_shared<TemporalDriftTerm> ();
  if (name == "lateral_noise")
    return std::make_shared<LateralNoiseTerm> ();
  std::string known = "polynomial";
  for (const auto &n : noiseEffectNames ())
    known += ", " + n;
  throw pcl::BadArgumentException ("unknown noise term '" + name + "' (known: " + known + ")");
}

} // namespace texlet
} // namespace pcl
