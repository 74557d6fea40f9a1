/*
 * pcl_texlet model lab (internal): the linear part of a fit. The model as the fits see it
 * (ModelView), and the least-squares fit of the surfaces and a distortion grid to the pixels'
 * means with the model's other biases removed (staticFit), which every objective needs first.
 */
#pragma once

#include "lab_data.h"

#include <pcl_texlet/noise/noise_model.h>

#include <pcl/exceptions.h>

#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** The most basis functions a linear bias term may have at one pixel. */
constexpr int kMaxBiasBasis = 16;
/** The most parameters of the steady mean a model may have besides its grid's. */
constexpr int kMaxMeanParameters = 16;

/** The model as the fits see it: the term whose bias is linear (a distortion grid, fitted by
  * least squares with the surfaces), the parameters of the steady mean (fitted with them) and the
  * term that rounds apart from the rest.
  */
struct ModelView
{
  const NoiseModel &model;
  bool quantised = false;
  NoiseModel without_grid;   // the model less the linear bias term (its bias is per pixel)
  NoiseModel pre_quantised;  // ... and less the rounding term (its bias is per pixel too)
  NoiseTerm::ConstPtr quantiser;
  NoiseTerm::ConstPtr grid;
  /** The parameters of the steady mean besides the grid's (NoiseTerm::fittedToMeans): term name
    * and parameter index. The term's bias must be linear in them. */
  std::vector<std::pair<std::string, std::size_t>> means;
  explicit ModelView (const NoiseModel &m) : model (m), without_grid (m), pre_quantised (m)
  {
    for (const auto &t : m.terms ())
    {
      if (!grid && t->linearBiasSupport () > 0)
        grid = t;
      if (!quantiser && t->quantises ())
        quantiser = t;
    }
    for (const auto &t : m.terms ())
      if (t != grid)
        for (std::size_t k = 0, n = t->parameters ().size (); k < n; ++k)
          if (t->fittedToMeans (k))
            means.emplace_back (t->name (), k);
    if (means.size () > static_cast<std::size_t> (kMaxMeanParameters))
      throw pcl::BadArgumentException ("model lab: the model has more than " + std::to_string (kMaxMeanParameters) +
                                       " parameters of the steady mean");
    quantised = quantiser != nullptr;
    if (grid)
    {
      if (grid->linearBiasSupport () > kMaxBiasBasis)
        throw pcl::BadArgumentException ("model lab: the term '" + grid->name () + "' has more than " +
                                         std::to_string (kMaxBiasBasis) + " bias basis functions at a pixel");
      without_grid.remove (grid->name ());
      pre_quantised.remove (grid->name ());
    }
    if (quantiser)
      pre_quantised.remove (quantiser->name ());
  }

  /** Whether the static fit changes with the other parameters (a rounding, a grid or a steady
    * mean's parameter): the fits then alternate it with the variances' fit more often. */
  bool
  hasStaticFit () const { return quantised || grid || !means.empty (); }
};

/** The disparity offset (px) of linear bias term \a grid with node values \a nodes at (u, v),
  * at depth \a depth_mm of a recording of f b \a fb_px_m (the term's shape along depth).
  */
double
linearBiasPx (const NoiseTerm &grid, const std::vector<double> &nodes, double u, double v, double depth_mm,
              double fb_px_m);

/** The predicted mean depth (mm) of a pixel whose fitted surface has disparity \a surface_px
  * (f b 1000 = \a fb1000) under a model bias of \a bias_mm (J = \a J_mm_per_px there). The fits
  * take every bias as the disparity offset -bias / J (staticFit), so this converts it back in
  * disparity rather than adding it in depth: the two differ by J offset^2 / d, tens of mm where
  * a distortion of a good part of a pixel meets a small disparity.
  */
inline double
predictedMeanMm (double surface_px, double fb1000, double bias_mm, double J_mm_per_px)
{
  return fb1000 / (surface_px - bias_mm / J_mm_per_px);
}

/** Result of the linear fit of surfaces (and a distortion grid) for one model on one half. */
struct StaticState
{
  std::vector<Eigen::Vector3d> planes;   // per recording (plane scenes)
  std::vector<double> grid;              // fitted grid node offsets, px (empty: the model's own)
  std::vector<double> means;             // fitted ModelView::means (empty: the model's own)
  std::vector<std::pair<std::string, double>> grid_settings; // the grid's shape settings the fit chose
  std::vector<double> ss_static;         // per bin of the set in use: sum of n e^2
  std::vector<double> bin_var, bin_shared; // per bin of the set in use
  std::vector<double> bin_bias;          // per bin: the steady bias (mm) of the terms besides the grid (used where nothing rounds; a rounding's is per pixel)
  std::vector<float> pixel_bias;         // quantised models: per-pixel bias (mm) of the other terms
};

/** Bin moments of the model (without the distortion grid, whose bias is per pixel). */
void
binMoments (const ModelView &mv, const std::vector<Bin> &bins, StaticState &s);

/** What staticFit fits of the distortion grid besides the surfaces. */
enum class GridFit
{
  none,          ///< the grid as the model has it
  nodes,         ///< its node values, in the shape along depth the model has
  nodes_and_shape ///< its node values in each shape it can take (linearBiasShapeSearch); the best
};

/** Linear fit of the surfaces (plane scenes) and, as \a grid_fit says, of the distortion grid
  * and the parameters of the steady mean (unless GridFit::none), to the pixels' mean disparities
  * with the model's other biases removed; then the static sums.
  * With GridFit::nodes_and_shape every combination of the grid's shape settings is fitted and
  * the one with the smallest static NLL kept (grid_settings).
  */
void
staticFit (const ModelView &mv, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
           GridFit grid_fit, StaticState &s);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
