/*
 * pcl_texlet effect `depth_distortion`: a static spatial bias that grows with depth.
 */
#pragma once

#include <pcl_texlet/kernels/philox_rng.h>
#include <pcl_texlet/noise/effect.h>

#include <sstream>

namespace pcl
{
namespace texlet
{
namespace effects
{

/** \brief `depth_distortion`: a static spatial bias that grows with depth.
  *
  * Physics: residual lens distortion of the IR camera and projector and an imperfect factory
  * reference pattern leave a fixed disparity error per pixel (Smisek et al. 2011, Herrera et al.
  * 2012); as a disparity offset delta it biases depth by -z^2 delta / (f b). The simulator draws
  * a radial bowl bowl_px (r / r_corner)^2 (r_corner = the principal point's distance to the
  * farthest image corner) plus a smooth ripple of three plane waves of wavelength
  * ripple_wavelength_px and RMS ripple_px, with directions and phases fixed by the seed.
  * Positive offsets pull the surface toward the sensor. The term is a disparity offset map, a
  * bilinear grid of nodes_x x nodes_y nodes over the image, linear in its nodes: the model lab
  * fits it by least squares (its bias basis) rather than with the non-linear parameters.
  *
  * The map's shape along depth covers the forms the physics allows (the simulator draws only
  * the first): a disparity offset the same at every depth (depth_power 0, decay_per_px 0);
  * Herrera et al.'s disparity distortion, the map times exp(alpha0 - alpha1 d), which fades with
  * disparity d (decay_per_px = alpha1 per px of disparity at 640 px width, the map's values
  * those at 1.5 m); and a depth scale map, a bias growing with z rather than z^2
  * (depth_power 1: the offset times 1500 mm / z). The lab tries each and keeps what fits.
  */
struct DepthDistortion
{
  static constexpr const char *kName = "depth_distortion";
  static constexpr EffectText kText = {"position (bias map)",
                                       "static disparity bias map: depth bias grows with z^2",
                                       "residual lens distortion and an imperfect reference pattern leave a fixed disparity error per pixel, a static depth bias growing with z^2"};

  // --- the simulator -------------------------------------------------------------------------

  struct SimParameters
  {
    double bowl_px = 0.1;                ///< disparity offset at the image corner, pixels
    double ripple_px = 0.05;             ///< RMS of the ripple, pixels
    double ripple_wavelength_px = 160.0; ///< ripple wavelength, pixels
  };

  static std::vector<Field<SimParameters>>
  simParameters ()
  {
    return {{"bowl_px", "px", "disparity offset at the farthest image corner (radial bowl)", ParameterRange::Any,
             &SimParameters::bowl_px},
            {"ripple_px", "px", "RMS of the smooth ripple", ParameterRange::NonNegative, &SimParameters::ripple_px},
            {"ripple_wavelength_px", "px", "wavelength of the ripple", ParameterRange::Positive,
             &SimParameters::ripple_wavelength_px}};
  }

  /** \brief Static disparity offset at pixel (u, v), pixels. \a cx, \a cy: principal point;
    * \a r_corner: its distance to the farthest image corner.
    */
  static PCL_TEXLET_HD double
  offset (const SimParameters &p, std::uint32_t seed, std::uint32_t sensor, double u, double v, double cx, double cy,
          double r_corner)
  {
    const double du = u - cx, dv = v - cy;
    double offset = p.bowl_px * (du * du + dv * dv) / (r_corner * r_corner);
    if (p.ripple_px > 0)
    {
      // Three plane waves, each of amplitude ripple_px sqrt(2/3): their sum has RMS ripple_px.
      const double amplitude = p.ripple_px * 0.816496580927726, k = 6.283185307179586 / p.ripple_wavelength_px;
      for (std::uint32_t i = 0; i < 3; ++i)
      {
        const r123::Philox4x32::ctr_type w = kernels::philoxWords (seed, i, 0u, sensor, kernels::RandomStream::Distortion);
        const double direction = 6.283185307179586 * kernels::uniformFloat (w.v[0]);
        const double phase = 6.283185307179586 * kernels::uniformFloat (w.v[1]);
        offset += amplitude * std::cos (k * (std::cos (direction) * u + std::sin (direction) * v) + phase);
      }
    }
    return offset;
  }

  static PCL_TEXLET_HD double
  disparityOffset (const SimParameters &p, const SimSensor &s, const SimPixel &px)
  {
    return offset (p, s.seed, s.sensor, px.u, px.v, s.cx, s.cy, s.r_corner);
  }

  // --- the noise model's term ----------------------------------------------------------------

  struct TermSettings
  {
    int image_width = 640;  ///< the image the grid spans, pixels
    int image_height = 480;
    int nodes_x = 17;       ///< grid nodes across
    int nodes_y = 13;       ///< grid nodes down
    int depth_power = 0;    ///< 0: a disparity offset map (bias ~ z^2); 1: a depth scale map (bias ~ z)
    double decay_per_px = 0.0; ///< Herrera's alpha1: exp(-decay (d - d(1.5 m))), d in px at 640 px width
  };

  /** \brief The factor of the map at depth \a depth_mm: 1 at 1.5 m (the map's own values). */
  static PCL_TEXLET_HD double
  biasShape (const TermSettings &s, double depth_mm, double fb_px_m)
  {
    const double reference_mm = 1500.0;
    double f = s.depth_power == 1 ? reference_mm / depth_mm : 1.0;
    if (s.decay_per_px != 0.0)
      f *= std::exp (-s.decay_per_px * 1000.0 * fb_px_m * (1.0 / depth_mm - 1.0 / reference_mm) * 640.0 / s.image_width);
    return f;
  }

  /** \brief What the lab tries: both depth laws, and decays about Herrera's (0.0165 per px). */
  static std::vector<std::pair<std::string, std::vector<double>>>
  biasShapeSearch ()
  {
    return {{"depth_power", {0, 1}}, {"decay_per_px", {-0.04, -0.02, -0.01, 0.0, 0.01, 0.02, 0.04}}};
  }

  static std::vector<Field<TermSettings>>
  termSettings ()
  {
    using R = ParameterRange;
    return {{"image_width", "px", "width of the image the grid spans", R::PositiveInteger, &TermSettings::image_width},
            {"image_height", "px", "height of the image the grid spans", R::PositiveInteger, &TermSettings::image_height},
            {"nodes_x", "1", "grid nodes across", R::PositiveInteger, &TermSettings::nodes_x},
            {"nodes_y", "1", "grid nodes down", R::PositiveInteger, &TermSettings::nodes_y},
            {"depth_power", "1", "0: a disparity offset map (depth bias ~ z^2); 1: a depth scale map (~ z)",
             R::NonNegative, &TermSettings::depth_power},
            {"decay_per_px", "1/px", "Herrera's alpha1: the map fades as exp(-decay (d - d(1.5 m))), d at 640 px width",
             R::Any, &TermSettings::decay_per_px}};
  }

  /** \brief What is wrong with \a s, or "" when nothing. */
  static std::string
  settingsProblem (const TermSettings &s)
  {
    if (s.depth_power != 0 && s.depth_power != 1)
      return "depth_power must be 0 (a disparity offset map) or 1 (a depth scale map), got " +
             std::to_string (s.depth_power);
    if (!(std::fabs (s.decay_per_px) <= 1.0))
      return "decay_per_px must be within [-1, 1] per px of disparity";
    if (s.image_width >= 2 && s.image_height >= 2 && s.nodes_x >= 2 && s.nodes_y >= 2 && s.nodes_x * s.nodes_y <= 100000)
      return "";
    std::ostringstream msg;
    msg << "needs an image of at least 2x2 pixels and 2 to 100000 nodes with at least 2 a side (got image "
        << s.image_width << "x" << s.image_height << ", nodes " << s.nodes_x << "x" << s.nodes_y << ")";
    return msg.str ();
  }

  /** \brief One parameter per node, offset_I_J (column I, row J; row-major), all neutral at 0. */
  static std::vector<std::string>
  termParameterNames (const TermSettings &s)
  {
    std::vector<std::string> names;
    for (int j = 0; j < s.nodes_y; ++j)
      for (int i = 0; i < s.nodes_x; ++i)
        names.push_back ("offset_" + std::to_string (i) + "_" + std::to_string (j));
    return names;
  }

  static constexpr unsigned kLabNeeds = kNeedsPlaneScene;

  /** \brief The grid spans the recordings' image. */
  static void
  labStart (const LabStart &facts, double *, TermSettings &s)
  {
    s.image_width = facts.image_width;
    s.image_height = facts.image_height;
  }

  /** \brief Nodes whose weights are non-zero at a pixel, at most. */
  static constexpr int kBiasSupport = 4;

  /** \brief The bias basis: the nodes bilinear interpolation at (u, v) uses and their weights
    * (disparity px per px of node offset).
    */
  static PCL_TEXLET_HD void
  biasBasis (const TermSettings &s, double u, double v, int *index, double *weight)
  {
    bilinearWeights (s.nodes_x, s.nodes_y, s.image_width, s.image_height, u, v, index, weight);
  }

  static PCL_TEXLET_HD double
  bias (const double *p, const TermSettings &s, const PixelContext &ctx)
  {
    return -depthPerDisparity (ctx) * biasShape (s, termDepthMm (ctx), ctx.fb_px_m) *
           bilinear (p, s.nodes_x, s.nodes_y, s.image_width, s.image_height, ctx.u, ctx.v);
  }

  /** \brief Weights of the four nodes of a nodes_x x nodes_y grid (row-major) spanning the image
    * [0, width - 1] x [0, height - 1] that bilinear interpolation at pixel (u, v) uses: their
    * indices and weights; outside the image, those of the border.
    */
  static PCL_TEXLET_HD void
  bilinearWeights (int nodes_x, int nodes_y, double width, double height, double u, double v, int index[4],
                   double weight[4])
  {
    double gx = (nodes_x - 1) * u / (width - 1.0), gy = (nodes_y - 1) * v / (height - 1.0);
    gx = gx < 0 ? 0 : (gx > nodes_x - 1 ? nodes_x - 1 : gx);
    gy = gy < 0 ? 0 : (gy > nodes_y - 1 ? nodes_y - 1 : gy);
    int ix = static_cast<int> (gx), iy = static_cast<int> (gy);
    ix = ix > nodes_x - 2 ? nodes_x - 2 : ix;
    iy = iy > nodes_y - 2 ? nodes_y - 2 : iy;
    const double fx = gx - ix, fy = gy - iy;
    index[0] = iy * nodes_x + ix;
    index[1] = index[0] + 1;
    index[2] = index[0] + nodes_x;
    index[3] = index[2] + 1;
    weight[0] = (1 - fy) * (1 - fx);
    weight[1] = (1 - fy) * fx;
    weight[2] = fy * (1 - fx);
    weight[3] = fy * fx;
  }

  /** \brief Bilinear interpolation of a nodes_x x nodes_y grid (row-major) spanning the image
    * [0, width - 1] x [0, height - 1] at pixel (u, v); outside, the border value.
    */
  static PCL_TEXLET_HD double
  bilinear (const double *nodes, int nodes_x, int nodes_y, double width, double height, double u, double v)
  {
    int index[4];
    double weight[4];
    bilinearWeights (nodes_x, nodes_y, width, height, u, v, index, weight);
    return weight[0] * nodes[index[0]] + weight[1] * nodes[index[1]] + weight[2] * nodes[index[2]] +
           weight[3] * nodes[index[3]];
  }
};

} // namespace effects
} // namespace texlet
} // namespace pcl
