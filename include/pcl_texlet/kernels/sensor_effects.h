/*
 * pcl_texlet kernels: the physical effects of a structured-light depth sensor (DESIGN.md
 * section 5), each a switch with parameters, and the closed-form math the simulator applies.
 *
 * Everything acts in disparity (pixels), where the sensor measures: offsets shift the disparity,
 * noise terms scale its SD, and holes remove the reading. Depth effects follow through
 * z = f b / d, so a constant disparity offset becomes a depth offset growing with z^2.
 * All structs are plain aggregates so that they can be copied into device code unchanged.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/philox_rng.h>

#include <cmath>
#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief `axial_quadratic`: triangulation noise, a constant disparity SD.
  *
  * Physics: the correlation peak of the dot pattern is located with an error of roughly
  * constant size in pixels, whatever the depth. Through z = f b / d that gives a depth SD of
  * sigma_px z^2 / (f b): quadratic in depth, as Khoshelham and Oude Elberink 2012 derived and
  * measured for the Kinect v1 (random error growing to about 4 cm at its 5 m maximum range).
  * Added in quadrature to the base noise (the paper's polynomial converted to disparity).
  */
struct AxialQuadratic
{
  bool enabled = false;
  double sigma_px = 0.02; ///< disparity SD, pixels (>= 0)
};

/** \brief `radial`: noise grows away from the optical centre.
  *
  * Physics: lens vignetting (cos^4 fall-off) and the projector's own fall-off darken the dot
  * pattern toward the image border; a dimmer pattern localises worse. To second order in the
  * radius the disparity SD is multiplied by 1 + gain (r / reference_radius_px)^2, r being the
  * distance in pixels from the principal point.
  */
struct Radial
{
  bool enabled = false;
  double gain = 0.5;                  ///< relative SD increase at the reference radius (>= 0)
  double reference_radius_px = 400.0; ///< radius where the SD has grown by `gain`, pixels (> 0)
};

/** \brief `disparity_quantization`: the sensor reports disparity in sub-pixel steps.
  *
  * Physics: the Kinect v1 reports disparity as an integer count of 1/8 pixel, so depth comes in
  * steps of z^2 step_px / (f b) (about 2.9 mm at 1 m, 11.5 mm at 2 m for f = 580 px,
  * b = 7.5 cm). The paper (Fig. 7) notes that much of the measured noise is of this size.
  * The step is also written to the recording's camera.yaml as disparity_subpixel.
  */
struct DisparityQuantization
{
  bool enabled = false;
  double step_px = 0.125; ///< disparity step, pixels (> 0)
};

/** \brief `incidence_angle`: noise grows toward grazing angles.
  *
  * Physics: on a surface seen at angle theta from its normal the pattern is stretched by
  * 1 / cos(theta) across the correlation window, which blurs the correlation peak. The
  * disparity SD is multiplied by 1 + gain (1 / cos(theta) - 1); beyond max_angle_deg the
  * pattern is too stretched to match and the pixel has no reading.
  */
struct IncidenceAngle
{
  bool enabled = false;
  double gain = 0.5;           ///< SD increase per unit of 1/cos(theta) - 1 (>= 0)
  double max_angle_deg = 80.0; ///< no reading beyond this angle, degrees (0, 90]
};

/** \brief `vertical_stripes`: column bands with disparity offsets that change over time.
  *
  * Physics: the paper (Sect. 2.2, Fig. 4) sees the depth image cut into vertical slices with a
  * static offset of about one quantisation step between neighbours, at seemingly random places
  * that change over time; a plausible cause is the sensor's piecewise correlation of the
  * reference pattern. Model: `bands` bands separated by bands - 1 random columns, each band with
  * an offset drawn from N(0, offset_px^2); the layout is redrawn every period_frames frames.
  */
struct VerticalStripes
{
  bool enabled = false;
  int bands = 6;            ///< number of bands across the image (>= 1)
  double offset_px = 0.125; ///< SD of a band's disparity offset, pixels (>= 0)
  int period_frames = 10;   ///< frames one layout lasts (>= 1)
};

/** \brief `depth_distortion`: a static spatial bias that grows with depth.
  *
  * Physics: residual lens distortion of the IR camera and projector and an imperfect factory
  * reference pattern leave a fixed disparity error per pixel (Smisek et al. 2011, Herrera et al.
  * 2012); as a disparity offset delta it biases depth by -z^2 delta / (f b). Model: a radial
  * bowl bowl_px (r / r_corner)^2 (r_corner = the principal point's distance to the farthest
  * image corner) plus a smooth ripple of three plane waves of wavelength ripple_wavelength_px
  * and RMS ripple_px, with directions and phases fixed by the seed. Positive offsets pull the
  * surface toward the sensor.
  */
struct DepthDistortion
{
  bool enabled = false;
  double bowl_px = 0.1;                 ///< disparity offset at the image corner, pixels
  double ripple_px = 0.05;              ///< RMS of the ripple, pixels (>= 0)
  double ripple_wavelength_px = 160.0;  ///< ripple wavelength, pixels (> 0)
};

/** \brief `interference`: other sensors' projected patterns add noise and holes.
  *
  * Physics: where another active projector lights the surface, its dots overlay the sensor's
  * own pattern and confuse the correlation (the paper's Sect. 4, Fig. 12). The foreign load L
  * at a surface point is the sum over other active projectors of their irradiance relative to
  * the sensor's own projector, (cos theta_j / r_j^2) / (cos theta_own / r_own^2), capped at 4
  * per projector (theta: angle between surface normal and the projector direction, r: distance;
  * zero where the other projector does not see the point). The disparity SD is multiplied by
  * sqrt(1 + noise_gain L) and the reading is lost with probability 1 - exp(-dropout_rate L) per
  * frame, decided per blob_px x blob_px block of pixels since holes come in clumps.
  */
struct Interference
{
  bool enabled = false;
  double noise_gain = 1.0;   ///< variance added per unit of foreign load, relative (>= 0)
  double dropout_rate = 0.1; ///< hole rate per unit of foreign load (>= 0)
  int blob_px = 4;           ///< side of the blocks in which holes appear, pixels (>= 1)
};

/** \brief `temporal_drift`: depth changes while the sensor warms up.
  *
  * Physics: after power-on the projector laser and the housing heat up; thermal expansion of
  * the baseline and the laser's wavelength shift move the pattern, which shows as a disparity
  * offset that decays to zero: amplitude_px exp(-frame / time_constant_frames). At a steady
  * depth this is a trend in the frame means that settles after a few time constants.
  */
struct TemporalDrift
{
  bool enabled = false;
  double amplitude_px = 0.2;          ///< disparity offset at frame 0, pixels
  double time_constant_frames = 10.0; ///< decay time, frames (> 0)
};

/** \brief `lateral_noise`: depth edges jitter across discontinuities.
  *
  * Physics: the correlation window straddling a depth edge matches either side, so the edge's
  * position in the image jitters by a fraction of a pixel to a pixel (Nguyen et al. 2012 measured
  * about 0.8 px for the Kinect v1). Model: each pixel and frame draws an offset from
  * N(0, sigma_px^2) in both image directions, rounded to whole pixels; if the pixel it lands on
  * lies across a depth jump larger than min_jump_m (or on no surface) the reading comes from
  * there. Smooth surfaces are unaffected.
  */
struct LateralNoise
{
  bool enabled = false;
  double sigma_px = 0.8;    ///< SD of the edge position, pixels (>= 0)
  double min_jump_m = 0.02; ///< smallest depth difference that counts as an edge, metres (> 0)
};

/** \brief `intrinsics`: the recording is labelled with wrong intrinsics (the OpenNI flaws).
  *
  * Physics: the frames are rendered through the true pinhole, but camera.yaml carries focal
  * lengths scaled by focal_scale and a principal point shifted by (cx_offset_px, cy_offset_px),
  * as when OpenNI back-projects registered depth with the IR field of view (58.5 deg instead of
  * the RGB camera's 62.7 deg: focal_scale 1.088) and the principal point at the image centre.
  * Back-projected lengths across the view shrink by 1 / focal_scale; depths are unaffected.
  */
struct Intrinsics
{
  bool enabled = false;
  double focal_scale = 1.088; ///< labelled focal length over the true one (> 0)
  double cx_offset_px = 0.0;  ///< labelled cx minus the true cx, pixels
  double cy_offset_px = 0.0;  ///< labelled cy minus the true cy, pixels
};

// ---------------------------------------------------------------------------------------------
// Closed-form terms. Each returns the neutral value (factor 1, offset 0) when its effect is off.

/** \brief Factor on the disparity SD at distance \a r_px from the principal point. */
PCL_TEXLET_HD double
radialFactor (const Radial &p, double r_px)
{
  if (!p.enabled)
    return 1.0;
  const double x = r_px / p.reference_radius_px;
  return 1.0 + p.gain * x * x;
}

/** \brief Factor on the disparity SD for a surface seen at angle acos(\a cos_theta). */
PCL_TEXLET_HD double
incidenceFactor (const IncidenceAngle &p, double cos_theta)
{
  if (!p.enabled)
    return 1.0;
  return 1.0 + p.gain * (1.0 / cos_theta - 1.0);
}

/** \brief True when the surface is too oblique to give a reading. */
PCL_TEXLET_HD bool
incidenceTooOblique (const IncidenceAngle &p, double cos_theta)
{
  return p.enabled && cos_theta < std::cos (p.max_angle_deg * 0.017453292519943295);
}

/** \brief Factor on the disparity SD for a foreign projector load \a load. */
PCL_TEXLET_HD double
interferenceFactor (const Interference &p, double load)
{
  if (!p.enabled)
    return 1.0;
  return std::sqrt (1.0 + p.noise_gain * load);
}

/** \brief Probability per frame that a pixel under foreign load \a load has no reading. */
PCL_TEXLET_HD double
interferenceDropout (const Interference &p, double load)
{
  if (!p.enabled)
    return 0.0;
  return 1.0 - std::exp (-p.dropout_rate * load);
}

/** \brief Irradiance of a projector at a surface point relative to the sensor's own projector,
  * capped at \a cap: (cos_j / r_j^2) / (cos_own / r_own^2). Cosines are of the angle between
  * the surface normal and the direction to the projector; zero when cos_j <= 0.
  */
PCL_TEXLET_HD double
relativeIrradiance (double cos_j, double r_j, double cos_own, double r_own, double cap = 4.0)
{
  if (!(cos_j > 0))
    return 0.0;
  if (!(cos_own > 0))
    return cap;
  const double w = (cos_j / (r_j * r_j)) / (cos_own / (r_own * r_own));
  return w < cap ? w : cap;
}

/** \brief Disparity offset of warm-up drift at frame \a frame, pixels. */
PCL_TEXLET_HD double
driftOffset (const TemporalDrift &p, std::uint32_t frame)
{
  if (!p.enabled)
    return 0.0;
  return p.amplitude_px * std::exp (-static_cast<double> (frame) / p.time_constant_frames);
}

/** \brief Which layout of vertical stripes frame \a frame shows. */
PCL_TEXLET_HD std::uint32_t
stripeEpoch (const VerticalStripes &p, std::uint32_t frame)
{
  return frame / static_cast<std::uint32_t> (p.period_frames);
}

/** \brief Column where band boundary \a k (0 .. bands - 2) of \a epoch lies, in [1, width). */
PCL_TEXLET_HD int
stripeBoundary (std::uint32_t seed, std::uint32_t sensor, std::uint32_t epoch, int k, int width)
{
  const r123::Philox4x32::ctr_type w =
      philoxWords (seed, static_cast<std::uint32_t> (k), epoch, sensor, RandomStream::Stripes);
  return 1 + static_cast<int> (boundedIndex (w.v[0], static_cast<std::uint32_t> (width - 1)));
}

/** \brief Disparity offset of band \a band (0 .. bands - 1) in \a epoch, pixels. */
PCL_TEXLET_HD double
stripeBandOffset (const VerticalStripes &p, std::uint32_t seed, std::uint32_t sensor, std::uint32_t epoch, int band)
{
  const r123::Philox4x32::ctr_type w =
      philoxWords (seed, static_cast<std::uint32_t> (band), epoch, sensor, RandomStream::Stripes);
  return p.offset_px * r123::boxmuller (w.v[2], w.v[3]).x;
}

/** \brief Band of column \a u: the number of boundaries at or left of it (boundaries are drawn
  * independently, so they need no sorting; coinciding ones merely leave a band empty).
  */
PCL_TEXLET_HD int
stripeBand (const VerticalStripes &p, std::uint32_t seed, std::uint32_t sensor, std::uint32_t epoch, int u, int width)
{
  int band = 0;
  for (int k = 0; k + 1 < p.bands; ++k)
    band += stripeBoundary (seed, sensor, epoch, k, width) <= u ? 1 : 0;
  return band;
}

/** \brief Disparity offset of every column of frame \a frame into \a offsets (width values). */
PCL_TEXLET_HD void
stripeColumnOffsets (const VerticalStripes &p, std::uint32_t seed, std::uint32_t sensor, std::uint32_t frame,
                     int width, float *offsets)
{
  if (!p.enabled)
  {
    for (int u = 0; u < width; ++u)
      offsets[u] = 0.0f;
    return;
  }
  const std::uint32_t epoch = stripeEpoch (p, frame);
  for (int u = 0; u < width; ++u)
    offsets[u] = static_cast<float> (stripeBandOffset (p, seed, sensor, epoch, stripeBand (p, seed, sensor, epoch, u, width)));
}

/** \brief Static disparity offset of depth distortion at pixel (u, v), pixels.
  * \a cx, \a cy: principal point; \a r_corner: its distance to the farthest image corner.
  */
PCL_TEXLET_HD double
distortionOffset (const DepthDistortion &p, std::uint32_t seed, std::uint32_t sensor, double u, double v, double cx,
                  double cy, double r_corner)
{
  if (!p.enabled)
    return 0.0;
  const double du = u - cx, dv = v - cy;
  double offset = p.bowl_px * (du * du + dv * dv) / (r_corner * r_corner);
  if (p.ripple_px > 0)
  {
    // Three plane waves, each of amplitude ripple_px sqrt(2/3): their sum has RMS ripple_px.
    const double amplitude = p.ripple_px * 0.816496580927726, k = 6.283185307179586 / p.ripple_wavelength_px;
    for (std::uint32_t i = 0; i < 3; ++i)
    {
      const r123::Philox4x32::ctr_type w = philoxWords (seed, i, 0u, sensor, RandomStream::Distortion);
      const double direction = 6.283185307179586 * uniformFloat (w.v[0]);
      const double phase = 6.283185307179586 * uniformFloat (w.v[1]);
      offset += amplitude * std::cos (k * (std::cos (direction) * u + std::sin (direction) * v) + phase);
    }
  }
  return offset;
}

/** \brief Intrinsics written to camera.yaml for the true ones (fx, fy, cx, cy), in place. */
PCL_TEXLET_HD void
labelledIntrinsics (const Intrinsics &p, double &fx, double &fy, double &cx, double &cy)
{
  if (!p.enabled)
    return;
  fx *= p.focal_scale;
  fy *= p.focal_scale;
  cx += p.cx_offset_px;
  cy += p.cy_offset_px;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
