/*
 * pcl_texlet noise: where a depth sample was taken, as the noise model's terms read it, and the
 * one place that makes it for a pixel of a camera.
 *
 * PCL-free and usable in device code, like the effect terms that read it.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/structured_light.h>

#include <cmath>
#include <limits>

namespace pcl
{
namespace texlet
{

/** \brief Where a depth sample was taken: pixel, distance from the principal point, depth. */
struct PixelContext
{
  double u = 0.0;         ///< column, pixels
  double v = 0.0;         ///< row, pixels
  double radius_px = 0.0; ///< distance from the principal point, pixels
  double depth_mm = 0.0;  ///< measured depth, millimetres
  // Covariates of the effect terms (docs/sensor_model.md). The defaults describe what is known
  // from a single frame, where terms fall back to their steady, phase-averaged form.
  double cos_incidence = 1.0;      ///< cosine of the angle between surface normal and viewing ray
  double active_projectors = 1.0;  ///< projectors lighting the scene, the sensor's own included
  double frame = std::numeric_limits<double>::quiet_NaN ();         ///< frame index since power-on; NaN: steady state
  double true_depth_mm = std::numeric_limits<double>::quiet_NaN (); ///< noise-free depth where known (the lab); NaN: unknown
  double edge_distance_px = std::numeric_limits<double>::infinity (); ///< distance to the nearest depth edge, pixels
  double image_width_px = std::numeric_limits<double>::quiet_NaN ();  ///< the image's width, pixels; NaN: unknown
  double image_height_px = std::numeric_limits<double>::quiet_NaN (); ///< the image's height, pixels; NaN: unknown
  /// grey level of the surface in the colour image, 0 (black) to 1 (white); NaN: unknown
  double intensity = std::numeric_limits<double>::quiet_NaN ();
  /// focal length (px) times baseline (m): disparity = fb / z; by default a Kinect v1 at VGA
  double fb_px_m = kernels::focalBaseline (580.0, 0.075);
};

/** \brief Grey level, 0 (black) to 1 (white), of an 8-bit colour (ITU-R BT.601 luma): what
  * PixelContext::intensity holds, from a recording's colour frames or a cloud's points.
  */
PCL_TEXLET_HD double
greyLevel (double r, double g, double b)
{
  return (0.299 * r + 0.587 * g + 0.114 * b) / 255.0;
}

/** \brief Makes the PixelContext of each pixel of one camera.
  *
  * What every pixel of a frame shares (f b, active projectors, frame index) is set once; each
  * call then fills in the pixel, its distance from the principal point and its depth. The
  * simulator, the texlet extractor and the model lab all make their contexts here, so that a
  * term sees the same f b and covariates wherever it is evaluated.
  */
class PixelContextBuilder
{
public:
  /** \brief A builder whose shared covariates are those of \a shared (its pixel fields are
    * overwritten per call); radii must then be given to at ().
    */
  explicit PixelContextBuilder (const PixelContext &shared = PixelContext ()) : shared_ (shared) {}

  /** \brief A pinhole camera with principal point (\a cx, \a cy) and f b = \a fb_px_m
    * (kernels::focalBaseline); the other shared covariates at their defaults.
    */
  PixelContextBuilder (double cx, double cy, double fb_px_m) : cx_ (cx), cy_ (cy) { shared_.fb_px_m = fb_px_m; }

  /** \brief Projectors lighting the scene, the sensor's own included. */
  PixelContextBuilder &
  setActiveProjectors (double projectors)
  {
    shared_.active_projectors = projectors;
    return *this;
  }

  /** \brief The image's size, pixels (the scale of terms whose offsets are shared by bands). */
  PixelContextBuilder &
  setImageSize (double width_px, double height_px)
  {
    shared_.image_width_px = width_px;
    shared_.image_height_px = height_px;
    return *this;
  }

  /** \brief Frame index since power-on (NaN: steady state). */
  PixelContextBuilder &
  setFrame (double frame)
  {
    shared_.frame = frame;
    return *this;
  }

  /** \brief The covariates every pixel shares (pixel fields at their defaults). */
  const PixelContext &
  shared () const { return shared_; }

  /** \brief The context of pixel (\a u, \a v) at \a radius_px from the principal point (as the
    * camera model measures it) and measured depth \a depth_mm.
    */
  PCL_TEXLET_HD PixelContext
  at (double u, double v, double radius_px, double depth_mm) const
  {
    PixelContext ctx = shared_;
    ctx.u = u;
    ctx.v = v;
    ctx.radius_px = radius_px;
    ctx.depth_mm = depth_mm;
    return ctx;
  }

  /** \brief As above with the pinhole's radius, hypot (u - cx, v - cy). */
  PCL_TEXLET_HD PixelContext
  at (double u, double v, double depth_mm) const
  {
    return at (u, v, std::hypot (u - cx_, v - cy_), depth_mm);
  }

private:
  PixelContext shared_;
  double cx_ = std::numeric_limits<double>::quiet_NaN ();
  double cy_ = std::numeric_limits<double>::quiet_NaN ();
};

} // namespace texlet
} // namespace pcl
