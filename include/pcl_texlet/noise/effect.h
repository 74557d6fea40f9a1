/*
 * pcl_texlet noise: what an effect file (noise/effects/<name>.h) is made of.
 *
 * A physical effect of the sensor is one struct of static members in one header: its name and
 * texts, the simulator's parameters with the generative hooks that draw it, and the noise
 * model's parameters with the closed-form moments that the extractor and the model lab
 * evaluate. Every hook is optional; the adapters of noise/effect_adapter.h call the ones an
 * effect has and use neutral values for the rest (docs/architecture.md, "Adding an effect").
 *
 * Everything here is PCL-free; the hooks are PCL_TEXLET_HD so that the device can run them.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/depth_sensor.h>
#include <pcl_texlet/kernels/structured_light.h>
#include <pcl_texlet/noise/pixel_context.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Which values a parameter accepts. */
enum class ParameterRange
{
  Any,             ///< any finite number
  NonNegative,     ///< >= 0
  Positive,        ///< > 0
  PositiveInteger, ///< a whole number >= 1
  AngleDegrees     ///< in (0, 90]
};

/** \brief Text for a range, e.g. "> 0". */
inline std::string
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

/** \brief Whether \a value lies in \a range (never for a value that is not finite). */
inline bool
inRange (ParameterRange range, double value)
{
  if (!std::isfinite (value))
    return false;
  switch (range)
  {
    case ParameterRange::Any: return true;
    case ParameterRange::NonNegative: return value >= 0;
    case ParameterRange::Positive: return value > 0;
    case ParameterRange::PositiveInteger: return value >= 1 && value == std::floor (value) && value <= 1e9;
    case ParameterRange::AngleDegrees: return value > 0 && value <= 90;
  }
  return false;
}

namespace effects
{

/** \brief A named number of an effect bound to its member of the struct \a S that holds it
  * (the simulator's parameters, or a term's settings). Its default is the member's initialiser.
  */
template <typename S>
struct Field
{
  const char *name;        ///< e.g. "offset_px"
  const char *unit;        ///< e.g. "px", "m", "deg", "frames", "1" (dimensionless)
  const char *description; ///< one line
  ParameterRange range;

  /** \brief Binds member \a member (a double or an int) of S. */
  template <typename T>
  Field (const char *n, const char *u, const char *d, ParameterRange r, T S::*member)
    : name (n), unit (u), description (d), range (r)
  {
    static_assert (std::is_same<T, double>::value || std::is_same<T, int>::value, "a Field is a double or an int");
    get_ = [member] (const S &s) { return static_cast<double> (s.*member); };
    set_ = [member] (S &s, double value) {
      if constexpr (std::is_same<T, int>::value)
        s.*member = static_cast<int> (std::llround (value));
      else
        s.*member = value;
    };
  }

  /** \brief The member's value in \a s. */
  double
  get (const S &s) const { return get_ (s); }

  /** \brief Sets the member in \a s (an int member to the nearest whole number). */
  void
  set (S &s, double value) const { set_ (s, value); }

private:
  std::function<double (const S &)> get_;
  std::function<void (S &, double)> set_;
};

/** \brief The values of \a fields in \a s, in their order. */
template <typename S>
std::vector<double>
fieldValues (const std::vector<Field<S>> &fields, const S &s)
{
  std::vector<double> values;
  for (const auto &f : fields)
    values.push_back (f.get (s));
  return values;
}

/** \brief A struct with \a values (in the order of \a fields) set on \a s's. */
template <typename S>
S
withFieldValues (const std::vector<Field<S>> &fields, const std::vector<double> &values, S s = S ())
{
  for (std::size_t k = 0; k < fields.size () && k < values.size (); ++k)
    fields[k].set (s, values[k]);
  return s;
}

/** \brief What an effect says of itself, for people: the covariate where it shows, its law in
  * one line (the simulator's), and its physics in one line (why the sensor shows it).
  */
struct EffectText
{
  const char *signature;
  const char *summary;
  const char *physics;
};

/** \brief One fitted parameter of an effect's noise term. */
struct TermParameter
{
  const char *name; ///< as in model.yaml, e.g. "sigma_px"
  double neutral;   ///< value at which the term adds nothing (what makeNoiseTerm gives)
  double start;     ///< where the model lab starts its fit (the neutral value is a saddle)
  double typical;   ///< the lab's scale for the fit: a typical magnitude of the parameter
  /** \brief The least meaningful value: the term reads any value below it as this one (a count
    * of bands below 1 as 1), so the lab's fit keeps to it and a model file may not go below. */
  double lowest = -INFINITY;
  /** \brief Whether the parameter moves only the steady mean depth: the lab fits it with the
    * surfaces to the pixels' means, not to the temporal contrasts as a variance. */
  bool fitted_to_means = false;
};

/** \brief Settings of a term without any. */
struct NoSettings
{
};

/** \brief What the model lab knows of the recordings when it adds a term: its start values may
  * come from them (the quantisation step from camera.yaml, a grid's image size).
  */
struct LabStart
{
  int image_width = 0;
  int image_height = 0;
  double disparity_step_px = 0.0; ///< camera.yaml's disparity_subpixel, 0 if unknown
  /** \brief The step of the disparity lattice the recordings' depths sit on (z_k = C / (k +
    * phase), step = 1000 f b / C), 0 when they sit on none or on camera.yaml's own.
    */
  double lattice_step_px = 0.0;
  double lattice_phase = 0.0; ///< that lattice's phase, in steps
};

/** \brief What the model lab needs in its recordings to test an effect (flags). */
enum LabNeeds : unsigned
{
  kNeedsNothing = 0,
  kNeedsPlaneScene = 1u,       ///< a plane scene, to tell a static bias from the surface
  kNeedsVariedProjectors = 2u, ///< recordings with different numbers of active projectors
  kNeedsFrameSplit = 4u,       ///< enough frames to fit on some and score on others
  kNeedsDepthEdges = 8u,       ///< depth edges in the image
  /** \brief Two or more frames of a pixel: the effect adds variance only, which one frame of a
    * pixel cannot tell from an unmodelled bias.
    */
  kNeedsRepeatedFrames = 16u,
  kNeedsIntensity = 32u, ///< colour frames (rgb/*.png): each pixel's grey level
  /** \brief The term changes no pixel's own moments, only how neighbours' noise correlates: the
    * lab fits and scores it on the residuals' correlation between neighbouring pixels.
    */
  kNeedsNeighbourCorrelation = 64u
};

/** \brief One pixel as the simulator's generative hooks see it (the static maps' phase). */
struct SimPixel
{
  double u = 0, v = 0;        ///< pixel
  double radius_px = 0;       ///< distance from the principal point, pixels
  double depth_m = 0;         ///< true depth along the optical axis, metres
  double cos_incidence = 1;   ///< cosine of the angle between surface normal and viewing ray
  double foreign_load = 0;    ///< other projectors' relative irradiance (kernels::relativeIrradiance)
};

/** \brief One sensor as the simulator's generative hooks see it. */
struct SimSensor
{
  std::uint32_t seed = 0;
  std::uint32_t sensor = 0;  ///< index in the setup
  int width = 0, height = 0; ///< image size, pixels
  double cx = 0, cy = 0;     ///< principal point, pixels
  double r_corner = 1;       ///< distance from the principal point to the farthest image corner, pixels
  double fb = 0;             ///< focal length (px) times baseline (m)
};

/** \brief What a simulated recording's camera.yaml says about its sensor. */
struct CameraLabel
{
  double fx = 0, fy = 0, cx = 0, cy = 0; ///< labelled intrinsics, pixels
  double disparity_step_px = 0.125;      ///< disparity_subpixel
};

// ---------------------------------------------------------------------------------------------
// Helpers of the closed forms.

/** \brief The depth the terms work at: the noise-free one where known, else the measured one. */
PCL_TEXLET_HD double
termDepthMm (const PixelContext &ctx)
{
  return std::isfinite (ctx.true_depth_mm) && ctx.true_depth_mm > 0 ? ctx.true_depth_mm : ctx.depth_mm;
}

/** \brief Depth per pixel of disparity at the context's depth, mm/px (J = z^2 / (f b)). */
PCL_TEXLET_HD double
depthPerDisparity (const PixelContext &ctx)
{
  return kernels::depthPerDisparityMm (termDepthMm (ctx), ctx.fb_px_m);
}

/** \brief Correlation length, pixels, of offsets shared by `bands` bands whose bands - 1
  * boundaries fall at random over \a extent_px lines: two lines dv apart share a band with
  * probability about exp(-dv (bands - 1) / extent). Infinite for one band or an unknown extent.
  */
PCL_TEXLET_HD double
bandCorrelationPx (double bands, double extent_px)
{
  const double boundaries = bands - 1.0;
  return boundaries > 0.0 && extent_px > 0.0 ? extent_px / boundaries : INFINITY;
}

} // namespace effects
} // namespace texlet
} // namespace pcl
