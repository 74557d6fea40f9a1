/*
 * pcl_texlet effect `intrinsics`: the recording is labelled with wrong intrinsics.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `intrinsics`: the recording is labelled with wrong intrinsics (the OpenNI flaws).
  *
  * Physics: the frames are rendered through the true pinhole, but camera.yaml carries focal
  * lengths scaled by focal_scale and a principal point shifted by (cx_offset_px, cy_offset_px),
  * as when OpenNI back-projects registered depth with the IR field of view (58.5 deg instead of
  * the RGB camera's 62.7 deg: focal_scale 1.088) and the principal point at the image centre.
  * Back-projected lengths across the view shrink by 1 / focal_scale; depths are unaffected.
  * A camera-model effect: it has no term in the noise model.
  */
struct Intrinsics
{
  static constexpr const char *kName = "intrinsics";
  static constexpr EffectText kText = {"lateral scale",
                                       "camera.yaml labelled with other intrinsics than rendered",
                                       "the recording's intrinsics are not the ones its frames were taken with"};

  struct SimParameters
  {
    double focal_scale = 1.088; ///< labelled focal length over the true one
    double cx_offset_px = 0.0;  ///< labelled cx minus the true cx, pixels
    double cy_offset_px = 0.0;  ///< labelled cy minus the true cy, pixels
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"focal_scale", "1", "labelled focal length over the true one", ParameterRange::Positive,
             &SimParameters::focal_scale},
            {"cx_offset_px", "px", "labelled cx minus the true cx", ParameterRange::Any, &SimParameters::cx_offset_px},
            {"cy_offset_px", "px", "labelled cy minus the true cy", ParameterRange::Any, &SimParameters::cy_offset_px}};
  }

  /** \brief Intrinsics written to camera.yaml for the true ones (fx, fy, cx, cy), in place. */
  static PCL_TEXLET_HD void
  label (const SimParameters &p, double &fx, double &fy, double &cx, double &cy)
  {
    fx *= p.focal_scale;
    fy *= p.focal_scale;
    cx += p.cx_offset_px;
    cy += p.cy_offset_px;
  }

  static void
  labelCamera (const SimParameters &p, bool enabled, CameraLabel &c)
  {
    if (enabled)
      label (p, c.fx, c.fy, c.cx, c.cy);
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
