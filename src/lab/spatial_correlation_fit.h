/*
 * pcl_texlet model lab (internal): the term spatial_correlation, fitted to and scored on the
 * residuals' correlation between neighbouring pixels (the diagnostics' NeighbourPairs), since it
 * changes no pixel's own moments and so no per-pixel likelihood (docs/model_lab.md, "Terms built
 * from the data").
 */
#pragma once

#include <pcl_texlet/lab/residual_diagnostics.h>

#include <string>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** Whether the registered effect \a name is fitted to the neighbour pairs rather than to the
  * per-pixel likelihood (effects::kNeedsNeighbourCorrelation); false for a name not registered. */
bool
fittedToNeighbourPairs (const std::string &name);

/** A window's share of the residual variance and its width (whole pixels). */
struct WindowFit
{
  double share = 0;
  int window_px = 1;
};

/** The model's own correlation at each direction and lag: the mean over the diagnostics'
  * replicas (1 ..), pooled over both halves. [direction][lag - 1] */
struct ModelCorrelation
{
  std::vector<double> r[2];
};

/** \param leave_out a replica (1 ..) left out of the mean, so that a replica scored as the null
  * is not part of the model it is scored against; 0: none */
ModelCorrelation
modelCorrelation (const ResidualDiagnostics &d, std::size_t leave_out = 0);

/** The window (share, width 2 .. kernels::kMaxWindowPx) whose correlation share tri(k) adds to
  * the model's best in least squares over both directions and every lag, on half \a half (0, 1;
  * -1: both) of \a p.
  */
WindowFit
fitWindow (const NeighbourPairs &p, const ModelCorrelation &model, int half);

/** \a fit with its share scaled so that the replicas of the model with it (\a with: their
  * correlation) match the data's excess over the model without it (\a without) in least squares,
  * at most 1: the replicas' correlation per unit of share is below the window's overlap (the
  * offsets the diagnostics remove, the whole-millimetre rounding, the model's floor), as is the
  * data's, so the share fitted to the overlap alone comes out low.
  */
WindowFit
calibrateWindow (const NeighbourPairs &data, const ModelCorrelation &without, const ModelCorrelation &with,
                 WindowFit fit);

/** Held-out score of \a fit on half \a half of \a p: the fall, from the model's correlation to
  * the model's plus the window's, of the Gaussian pair likelihood of the neighbour pairs summed
  * over both directions and averaged over the lags, nats per residual of that half.
  */
double
windowGain (const NeighbourPairs &p, const ModelCorrelation &model, const WindowFit &fit, int half);

/** Practical effect on half \a half: the share of the squared error of the correlation (measured
  * less predicted, over both directions and every lag) that adding \a fit removes; and the RMS
  * errors before and after. */
double
windowEffect (const NeighbourPairs &p, const ModelCorrelation &model, const WindowFit &fit, int half,
              double &rms_before, double &rms_after);

/** \brief \a model with the term \a effect (a registered term of the neighbours' correlation) set
  * to \a fit's share and width. */
NoiseModel
withWindow (const NoiseModel &model, const std::string &effect, const WindowFit &fit);

/** \brief \a base with the term \a effect fitted to half \a half (0, 1; -1: every frame) of the data's
  * neighbour pairs in \a pairs (diagnoseResiduals() of \a lab under \a base), its share calibrated
  * by the replicas of the model with it (calibrateWindow(): one more diagnoseResiduals()).
  */
NoiseModel
withFittedWindow (const ModelLab &lab, const NoiseModel &base, const std::string &effect,
                  const ResidualDiagnostics &pairs, int half);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
