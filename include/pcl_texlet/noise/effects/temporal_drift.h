/*
 * pcl_texlet effect `temporal_drift`: depth changes while the sensor warms up.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `temporal_drift`: depth changes while the sensor warms up.
  *
  * Physics: after power-on the projector laser and the housing heat up; thermal expansion of
  * the baseline and the laser's wavelength shift move the pattern, which shows as a disparity
  * offset that decays to zero: amplitude_px exp(-frame / time_constant_frames). At a steady
  * depth this is a trend in the frame means that settles after a few time constants. The term's
  * bias depends on the frame index; without one (a single frame) it is the steady state, zero.
  *
  * The term has a second form beside the disparity offset (the simulator draws only the first):
  * when warming changes the focal length of the IR camera rather than the pattern's position,
  * depth scales, Delta z = scale z exp(-frame / tau), growing with z where the disparity offset's
  * Delta z = -J amplitude_px grows with z^2. The lab fits both and the data choose (a fit with one
  * of them at zero is the other form).
  */
struct TemporalDrift
{
  static constexpr const char *kName = "temporal_drift";
  static constexpr EffectText kText = {"frame",
                                       "warm-up: disparity offset decaying over the first frames",
                                       "while the sensor warms up the projector and housing expand and the laser's wavelength shifts: a disparity offset that decays over the first frames"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    double amplitude_px = 0.2;          ///< disparity offset at frame 0, pixels
    double time_constant_frames = 10.0; ///< decay time, frames
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"amplitude_px", "px", "disparity offset at frame 0", ParameterRange::Any, &SimParameters::amplitude_px},
            {"time_constant_frames", "frames", "decay time", ParameterRange::Positive,
             &SimParameters::time_constant_frames}};
  }

  /** \brief Disparity offset of the whole frame \a frame, pixels. */
  static PCL_TEXLET_HD double
  frameOffset (const SimParameters &p, std::uint32_t frame)
  {
    return p.amplitude_px * std::exp (-static_cast<double> (frame) / p.time_constant_frames);
  }

  // --- the noise model's term ----------------------------------------------------------------

  static constexpr bool kFrameDependent = true;
  static constexpr unsigned kLabNeeds = kNeedsFrameSplit | kNeedsRepeatedFrames;

  static std::vector<TermParameter>
  termParameters ()
  {
    const double tau = SimParameters ().time_constant_frames;
    return {{"amplitude_px", 0.0, 0.05, 0.02}, {"time_constant_frames", tau, tau, 5.0}, {"scale", 0.0, 0.0, 0.002}};
  }

  /** \brief Disparity offset at frame \a frame, px: A exp(-frame / tau) (tau at least 1e-3). */
  static PCL_TEXLET_HD double
  offsetAt (double amplitude_px, double time_constant_frames, double frame)
  {
    const double tau = time_constant_frames > 1e-3 ? time_constant_frames : 1e-3;
    return amplitude_px * std::exp (-frame / tau);
  }

  static PCL_TEXLET_HD double
  bias (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    if (!std::isfinite (ctx.frame))
      return 0.0;
    return -depthPerDisparity (ctx) * offsetAt (p[0], p[1], ctx.frame) + termDepthMm (ctx) * offsetAt (p[2], p[1], ctx.frame);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
