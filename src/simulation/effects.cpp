#include <pcl_texlet/simulation/effects.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <functional>
#include <sstream>
#include <type_traits>

namespace pcl
{
namespace texlet
{
namespace sim
{

namespace
{

/** A parameter bound to its member: reads and writes it as a double. */
struct ParameterBinding
{
  EffectParameterInfo info;
  std::function<double (const SensorEffects &)> get;
  std::function<void (SensorEffects &, double)> set;
};

/** An effect bound to its struct in SensorEffects. */
struct EffectBinding
{
  EffectInfo info;
  std::function<bool (const SensorEffects &)> enabled;
  std::function<void (SensorEffects &, bool)> enable;
  std::vector<ParameterBinding> parameters;
};

template <typename Effect>
struct EffectBuilder
{
  Effect SensorEffects::*effect;
  EffectBinding binding;

  EffectBuilder (Effect SensorEffects::*e, const std::string &name, const std::string &summary) : effect (e)
  {
    binding.info.name = name;
    binding.info.summary = summary;
    binding.enabled = [e] (const SensorEffects &s) { return (s.*e).enabled; };
    binding.enable = [e] (SensorEffects &s, bool on) { (s.*e).enabled = on; };
  }

  /** Adds a parameter; its default is read from a default-constructed Effect. */
  template <typename T> EffectBuilder &
  param (T Effect::*member, const std::string &name, const std::string &unit, ParameterRange range,
         const std::string &description)
  {
    Effect SensorEffects::*e = effect;
    ParameterBinding p;
    p.info = {name, unit, description, range, static_cast<double> (Effect ().*member)};
    p.get = [e, member] (const SensorEffects &s) { return static_cast<double> ((s.*e).*member); };
    p.set = [e, member] (SensorEffects &s, double v) {
      if constexpr (std::is_integral_v<T>)
        (s.*e).*member = static_cast<T> (std::llround (v));
      else
        (s.*e).*member = static_cast<T> (v);
    };
    binding.info.parameters.push_back (p.info);
    binding.parameters.push_back (std::move (p));
    return *this;
  }
};

const std::vector<EffectBinding> &
bindings ()
{
  using P = ParameterRange;
  static const std::vector<EffectBinding> table = [] {
    std::vector<EffectBinding> t;
    t.push_back (EffectBuilder<kernels::AxialQuadratic> (&SensorEffects::axial_quadratic, "axial_quadratic",
                                                         "triangulation noise: constant disparity SD, depth SD ~ z^2")
                     .param (&kernels::AxialQuadratic::sigma_px, "sigma_px", "px", P::NonNegative, "disparity SD")
                     .binding);
    t.push_back (EffectBuilder<kernels::Radial> (&SensorEffects::radial, "radial",
                                                 "noise grows away from the optical centre: SD x (1 + gain (r/r_ref)^2)")
                     .param (&kernels::Radial::gain, "gain", "1", P::NonNegative, "relative SD increase at r_ref")
                     .param (&kernels::Radial::reference_radius_px, "reference_radius_px", "px", P::Positive,
                             "reference radius r_ref from the principal point")
                     .binding);
    t.push_back (EffectBuilder<kernels::DisparityQuantization> (
                     &SensorEffects::disparity_quantization, "disparity_quantization",
                     "disparity in sub-pixel steps: depth steps of z^2 step / (f b)")
                     .param (&kernels::DisparityQuantization::step_px, "step_px", "px", P::Positive,
                             "disparity step (camera.yaml disparity_subpixel)")
                     .binding);
    t.push_back (EffectBuilder<kernels::IncidenceAngle> (&SensorEffects::incidence_angle, "incidence_angle",
                                                         "noise grows toward grazing angles: SD x (1 + gain (1/cos - 1))")
                     .param (&kernels::IncidenceAngle::gain, "gain", "1", P::NonNegative,
                             "SD increase per unit of 1/cos(theta) - 1")
                     .param (&kernels::IncidenceAngle::max_angle_deg, "max_angle_deg", "deg", P::AngleDegrees,
                             "no reading beyond this angle")
                     .binding);
    t.push_back (EffectBuilder<kernels::VerticalStripes> (&SensorEffects::vertical_stripes, "vertical_stripes",
                                                          "column bands with disparity offsets that change over time")
                     .param (&kernels::VerticalStripes::bands, "bands", "1", P::PositiveInteger, "bands across the image")
                     .param (&kernels::VerticalStripes::offset_px, "offset_px", "px", P::NonNegative,
                             "SD of a band's disparity offset")
                     .param (&kernels::VerticalStripes::period_frames, "period_frames", "frames", P::PositiveInteger,
                             "frames one layout lasts")
                     .binding);
    t.push_back (EffectBuilder<kernels::DepthDistortion> (&SensorEffects::depth_distortion, "depth_distortion",
                                                          "static disparity bias map: depth bias grows with z^2")
                     .param (&kernels::DepthDistortion::bowl_px, "bowl_px", "px", P::Any,
                             "disparity offset at the farthest image corner (radial bowl)")
                     .param (&kernels::DepthDistortion::ripple_px, "ripple_px", "px", P::NonNegative,
                             "RMS of the smooth ripple")
                     .param (&kernels::DepthDistortion::ripple_wavelength_px, "ripple_wavelength_px", "px", P::Positive,
                             "wavelength of the ripple")
                     .binding);
    t.push_back (EffectBuilder<kernels::Interference> (&SensorEffects::interference, "interference",
                                                       "other active projectors add noise and holes where they overlap")
                     .param (&kernels::Interference::noise_gain, "noise_gain", "1", P::NonNegative,
                             "variance added per unit of foreign load, relative")
                     .param (&kernels::Interference::dropout_rate, "dropout_rate", "1", P::NonNegative,
                             "hole rate per unit of foreign load: p = 1 - exp(-rate L)")
                     .param (&kernels::Interference::blob_px, "blob_px", "px", P::PositiveInteger,
                             "side of the blocks in which holes appear")
                     .binding);
    t.push_back (EffectBuilder<kernels::TemporalDrift> (&SensorEffects::temporal_drift, "temporal_drift",
                                                        "warm-up: disparity offset decaying over the first frames")
                     .param (&kernels::TemporalDrift::amplitude_px, "amplitude_px", "px", P::Any,
                             "disparity offset at frame 0")
                     .param (&kernels::TemporalDrift::time_constant_frames, "time_constant_frames", "frames",
                             P::Positive, "decay time")
                     .binding);
    t.push_back (EffectBuilder<kernels::LateralNoise> (&SensorEffects::lateral_noise, "lateral_noise",
                                                       "depth edges jitter across discontinuities")
                     .param (&kernels::LateralNoise::sigma_px, "sigma_px", "px", P::NonNegative,
                             "SD of the edge position")
                     .param (&kernels::LateralNoise::min_jump_m, "min_jump_m", "m", P::Positive,
                             "smallest depth difference that counts as an edge")
                     .binding);
    t.push_back (EffectBuilder<kernels::Intrinsics> (&SensorEffects::intrinsics, "intrinsics",
                                                     "camera.yaml labelled with other intrinsics than rendered")
                     .param (&kernels::Intrinsics::focal_scale, "focal_scale", "1", P::Positive,
                             "labelled focal length over the true one")
                     .param (&kernels::Intrinsics::cx_offset_px, "cx_offset_px", "px", P::Any,
                             "labelled cx minus the true cx")
                     .param (&kernels::Intrinsics::cy_offset_px, "cy_offset_px", "px", P::Any,
                             "labelled cy minus the true cy")
                     .binding);
    return t;
  }();
  return table;
}

std::string
knownEffectNames ()
{
  std::string names;
  for (const auto &b : bindings ())
    names += (names.empty () ? "" : ", ") + b.info.name;
  return names;
}

const EffectBinding &
binding (const std::string &name)
{
  for (const auto &b : bindings ())
    if (b.info.name == name)
      return b;
  throw pcl::BadArgumentException ("unknown effect '" + name + "' (known: " + knownEffectNames () + ")");
}

const ParameterBinding &
parameterBinding (const std::string &effect, const std::string &parameter)
{
  const EffectBinding &b = binding (effect);
  std::string names;
  for (const auto &p : b.parameters)
  {
    if (p.info.name == parameter)
      return p;
    names += (names.empty () ? "" : ", ") + p.info.name;
  }
  throw pcl::BadArgumentException ("effect '" + effect + "' has no parameter '" + parameter + "' (its parameters: " +
                                   names + ")");
}

bool
inRange (ParameterRange range, double v)
{
  if (!std::isfinite (v))
    return false;
  switch (range)
  {
    case ParameterRange::Any: return true;
    case ParameterRange::NonNegative: return v >= 0;
    case ParameterRange::Positive: return v > 0;
    case ParameterRange::PositiveInteger: return v >= 1 && v == std::floor (v) && v <= 1e9;
    case ParameterRange::AngleDegrees: return v > 0 && v <= 90;
  }
  return false;
}

} // namespace

std::string
toString (ParameterRange range)
{
  switch (range)
  {
    case ParameterRange::Any: return "any finite number";
    case ParameterRange::NonNegative: return ">= 0";
    case ParameterRange::Positive: return "> 0";
    case ParameterRange::PositiveInteger: return "a whole number >= 1";
    case ParameterRange::AngleDegrees: return "in (0, 90]";
  }
  return "?";
}

const std::vector<EffectInfo> &
effectCatalogue ()
{
  static const std::vector<EffectInfo> catalogue = [] {
    std::vector<EffectInfo> c;
    for (const auto &b : bindings ())
      c.push_back (b.info);
    return c;
  }();
  return catalogue;
}

const EffectInfo &
effectInfo (const std::string &name)
{
  return binding (name).info;
}

bool
isEffectEnabled (const SensorEffects &effects, const std::string &name)
{
  return binding (name).enabled (effects);
}

void
setEffectEnabled (SensorEffects &effects, const std::string &name, bool enabled)
{
  binding (name).enable (effects, enabled);
}

double
effectParameter (const SensorEffects &effects, const std::string &effect, const std::string &parameter)
{
  return parameterBinding (effect, parameter).get (effects);
}

void
setEffectParameter (SensorEffects &effects, const std::string &effect, const std::string &parameter, double value)
{
  const ParameterBinding &p = parameterBinding (effect, parameter);
  if (!inRange (p.info.range, value))
  {
    std::ostringstream msg;
    msg << "effect '" << effect << "': parameter " << parameter << " must be " << toString (p.info.range) << " (got "
        << value << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
  p.set (effects, value);
}

std::vector<std::string>
enabledEffects (const SensorEffects &effects)
{
  std::vector<std::string> names;
  for (const auto &b : bindings ())
    if (b.enabled (effects))
      names.push_back (b.info.name);
  return names;
}

void
validate (const SensorEffects &effects)
{
  for (const auto &b : bindings ())
    for (const auto &p : b.parameters)
    {
      const double v = p.get (effects);
      if (!inRange (p.info.range, v))
      {
        std::ostringstream msg;
        msg << "effect '" << b.info.name << "': parameter " << p.info.name << " must be " << toString (p.info.range)
            << " (got " << v << ")";
        throw pcl::BadArgumentException (msg.str ());
      }
    }
}

} // namespace sim
} // namespace texlet
} // namespace pcl
