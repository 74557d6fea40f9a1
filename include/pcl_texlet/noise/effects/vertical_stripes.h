/*
 * pcl_texlet effect `vertical_stripes`: column bands with disparity offsets that change over time.
 */
#pragma once

#include <pcl_texlet/kernels/philox_rng.h>
#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `vertical_stripes`: column bands with disparity offsets that change over time.
  *
  * Physics: the paper (Sect. 2.2, Fig. 4) sees the depth image cut into vertical slices with a
  * static offset of about one quantisation step between neighbours, at seemingly random places
  * that change over time; a plausible cause is the sensor's piecewise correlation of the
  * reference pattern. Model: `bands` bands separated by bands - 1 random columns, each band with
  * an offset drawn from N(0, offset_px^2); the layout is redrawn every period_frames frames.
  * The term: pixels of one column share an offset of SD offset_px in each frame, and with
  * `bands` independent bands a frame's mean offset has variance offset_px^2 / bands.
  */
struct VerticalStripes
{
  static constexpr const char *kName = "vertical_stripes";
  static constexpr EffectText kText = {"column",
                                       "column bands with disparity offsets that change over time",
                                       "the image is cut into column bands whose disparity offsets change over time (the paper's Fig. 4), so pixels of one column share an offset in each frame"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    int bands = 6;            ///< number of bands across the image
    double offset_px = 0.125; ///< SD of a band's disparity offset, pixels
    int period_frames = 10;   ///< frames one layout lasts
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"bands", "1", "bands across the image", ParameterRange::PositiveInteger, &SimParameters::bands},
            {"offset_px", "px", "SD of a band's disparity offset", ParameterRange::NonNegative,
             &SimParameters::offset_px},
            {"period_frames", "frames", "frames one layout lasts", ParameterRange::PositiveInteger,
             &SimParameters::period_frames}};
  }

  /** \brief Which layout of stripes frame \a frame shows. */
  static PCL_TEXLET_HD std::uint32_t
  epoch (const SimParameters &p, std::uint32_t frame)
  {
    return frame / static_cast<std::uint32_t> (p.period_frames);
  }

  /** \brief Column where band boundary \a k (0 .. bands - 2) of \a epoch lies, in [1, width). */
  static PCL_TEXLET_HD int
  boundary (std::uint32_t seed, std::uint32_t sensor, std::uint32_t epoch, int k, int width)
  {
    const r123::Philox4x32::ctr_type w = kernels::philoxWords (seed, static_cast<std::uint32_t> (k), epoch, sensor,
                                                               kernels::RandomStream::Stripes);
    return 1 + static_cast<int> (kernels::boundedIndex (w.v[0], static_cast<std::uint32_t> (width - 1)));
  }

  /** \brief Disparity offset of band \a band (0 .. bands - 1) in \a epoch, pixels. */
  static PCL_TEXLET_HD double
  bandOffset (const SimParameters &p, std::uint32_t seed, std::uint32_t sensor, std::uint32_t epoch, int band)
  {
    const r123::Philox4x32::ctr_type w = kernels::philoxWords (seed, static_cast<std::uint32_t> (band), epoch, sensor,
                                                               kernels::RandomStream::Stripes);
    return p.offset_px * r123::boxmuller (w.v[2], w.v[3]).x;
  }

  /** \brief Band of column \a u: the number of boundaries at or left of it (boundaries are drawn
    * independently, so they need no sorting; coinciding ones merely leave a band empty).
    */
  static PCL_TEXLET_HD int
  band (const SimParameters &p, std::uint32_t seed, std::uint32_t sensor, std::uint32_t epoch, int u, int width)
  {
    int b = 0;
    for (int k = 0; k + 1 < p.bands; ++k)
      b += boundary (seed, sensor, epoch, k, width) <= u ? 1 : 0;
    return b;
  }

  /** \brief Adds the disparity offset of every column of frame \a frame to \a columns (width values). */
  static PCL_TEXLET_HD void
  addColumnOffsets (const SimParameters &p, const SimSensor &s, std::uint32_t frame, float *columns)
  {
    const std::uint32_t e = epoch (p, frame);
    for (int u = 0; u < s.width; ++u)
      columns[u] += static_cast<float> (bandOffset (p, s.seed, s.sensor, e, band (p, s.seed, s.sensor, e, u, s.width)));
  }

  // --- the noise model's term ----------------------------------------------------------------

  static constexpr bool kScaledByFactors = false; // an offset added after the correlation
  static constexpr unsigned kLabNeeds = kNeedsFrameSplit | kNeedsRepeatedFrames;

  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"offset_px", 0.0, 0.05, 0.02},
            {"bands", double (SimParameters ().bands), double (SimParameters ().bands), 1.0, 1.0}};
  }

  static PCL_TEXLET_HD double
  columnVariance (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    const double s = p[0] * depthPerDisparity (ctx);
    return s * s;
  }

  static PCL_TEXLET_HD double
  frameVariance (const double *p, const NoSettings &s, const PixelContext &ctx)
  {
    const double bands = p[1] > 1.0 ? p[1] : 1.0;
    return columnVariance (p, s, ctx) / bands;
  }

  /** \brief Two columns du apart share a band unless one of the bands - 1 boundaries, each at a
    * random column, falls between them: probability (1 - du / width)^(bands - 1), about
    * exp(-du (bands - 1) / width).
    */
  static PCL_TEXLET_HD double
  columnCorrelationPx (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    return bandCorrelationPx (p[1], ctx.image_width_px);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
