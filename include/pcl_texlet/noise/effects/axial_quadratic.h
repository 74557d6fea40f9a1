/*
 * pcl_texlet effect `axial_quadratic`: triangulation noise, a constant disparity SD.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `axial_quadratic`: triangulation noise, a constant disparity SD.
  *
  * Physics: the correlation peak of the dot pattern is located with an error of roughly
  * constant size in pixels, whatever the depth. Through z = f b / d that gives a depth SD of
  * sigma_px z^2 / (f b): quadratic in depth, as Khoshelham and Oude Elberink 2012 derived and
  * measured for the Kinect v1 (random error growing to about 4 cm at its 5 m maximum range).
  * The simulator adds it in quadrature to the base noise (the paper's polynomial converted to
  * disparity); the term's depth variance is (J sigma_px)^2, J = z^2 / (f b).
  */
struct AxialQuadratic
{
  static constexpr const char *kName = "axial_quadratic";
  static constexpr EffectText kText = {"depth",
                                       "triangulation noise: constant disparity SD, depth SD ~ z^2",
                                       "triangulation: the correlation peak is found to a constant fraction of a pixel, so the depth SD grows with z^2 / (f b)"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    double sigma_px = 0.02; ///< disparity SD, pixels
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"sigma_px", "px", "disparity SD", ParameterRange::NonNegative, &SimParameters::sigma_px}};
  }

  /** \brief Disparity variance added to the base noise's, px^2. */
  static PCL_TEXLET_HD double
  disparityVariance (const SimParameters &p, const SimPixel &)
  {
    return p.sigma_px * p.sigma_px;
  }

  // --- the noise model's term ----------------------------------------------------------------

  static constexpr unsigned kLabNeeds = kNeedsRepeatedFrames;

  /** \brief The lab starts from the simulator's nominal SD. */
  static std::vector<TermParameter>
  termParameters ()
  {
    return {{"sigma_px", 0.0, SimParameters ().sigma_px, 0.02}};
  }

  static PCL_TEXLET_HD double
  variance (const double *p, const NoSettings &, const PixelContext &ctx)
  {
    const double s = p[0] * depthPerDisparity (ctx);
    return s * s;
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
