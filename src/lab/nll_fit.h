/*
 * pcl_texlet model lab (internal): fitting a model's non-linear parameters. Ceres (L-BFGS on the
 * temporal NLL, central differences) alternates with the linear static fit; a term just added is
 * first fitted alone, and a fit never ends worse than the nested model without the term.
 */
#pragma once

#include "static_fit.h"

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** NLL per sample of \a model on \a d with the surfaces (and a grid, as \a grid_fit says) fitted
  * to it; the fitted grid is written into \a model.
  */
double
fitObjective (NoiseModel &model, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
              StaticState &s, GridFit grid_fit = GridFit::nodes);

/** Refits \a start on \a d: alternating linear (surfaces, grid) and Ceres (the rest) fits.
  * \a new_term: index of a term just added to a fitted model, or -1. A new term is first fitted
  * alone (from the best of a few starting scales), then everything together; since the model
  * without it is nested (the term at neutral values), the result is never worse on \a d than
  * that model, whose objective is \a nested_objective. A grid's shape along depth is chosen when
  * the grid is the new term and kept after that (docs/model_lab.md section 9).
  */
NoiseModel
fitOn (const NoiseModel &start, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
       const LabSettings &settings, int new_term = -1, double nested_objective = kNaN);

/** Fits the effect \a name on top of \a fitted (\a given refitted on \a d, objective
  * \a nested_objective) with fitOn. For disparity_quantization it also fits from \a given (the
  * model before that refit) plus the term, and keeps the better on \a d: the refit polynomial
  * has already absorbed the phase-averaged step^2/12 variance, and from there adding the step
  * at its camera.yaml value doubles that variance while the joint fit stalls in the valley
  * between them (docs/model_lab.md section 7).
  * \a fits: -1 both fits and the better; 0 only the fit from \a fitted; 1 only the one from
  * \a given (so that the two can run in parallel; the caller then keeps the better).
  */
NoiseModel
fitWithEffect (const NoiseModel &fitted, const NoiseModel &given, const std::string &name, const ModelLab::Data &d,
               const std::vector<RecordingMeasurement::ConstPtr> &recs, const LabSettings &settings,
               double nested_objective, int fits = -1);

/** NLL per sample of a fitted model on held-out data (surfaces refitted, nothing else). */
double
scoreOn (const NoiseModel &model, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
