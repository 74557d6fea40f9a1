/*
 * pcl_texlet model lab: the structure a noise model leaves in the recordings' residuals, found
 * without a model of it: offsets that the pixels of a frame, a row or a column share, correlation
 * along rows, along columns and over time, and the SD and bias against each covariate. Each is
 * measured on the data and on replicas of the model's own noise on the same pixels, and ranked
 * by how much more the data hold than the model expects (docs/model_lab.md, "What no effect
 * explains").
 */
#pragma once

#include <pcl_texlet/lab/model_lab.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{

/** \brief One structure of the residuals and how much of it the model does not explain. */
struct UnexplainedStructure
{
  /** rows, columns, frames, spatial_correlation, temporal_correlation, or covariate:NAME (NAME:
    * radius, depth, incidence_angle, column, row, disparity_phase, edge_distance, intensity). */
  std::string structure;
  /** Effect size: the structure's statistic on the data minus its mean over the model's
    * replicas, in units of the residual variance (a share of it for offsets, an excess
    * correlation for correlations, a mean square over covariate bins for covariates). Rows and
    * columns are significant by their part beyond the frame offset, and then include it. */
  double strength = 0;
  double z = 0;              ///< strength over the replicas' SD of the statistic
  bool significant = false;  ///< z and strength both at least the settings' thresholds
  std::string words;         ///< one sentence saying what it is, for people
};

/** \brief Settings of diagnoseResiduals(). */
struct ResidualDiagnosticsSettings
{
  int replicas = 8;            ///< draws of the model's own noise on the recordings' pixels
  double min_z = 5.0;          ///< statistical threshold, in replica SDs
  double min_strength = 0.02;  ///< practical threshold on the strength (docs/model_lab.md)
  int max_lag = 10;            ///< autocorrelation lags 1 .. max_lag (pixels, frames)
  int covariate_bins = 10;     ///< quantile bins of each covariate
  std::uint64_t seed = 1;      ///< of the replicas
};

/** \brief An autocorrelation of the residuals (after the frame, row and column offsets) at lags
  * 1, 2, ...: measured, and the mean of the model's replicas. */
struct ResidualCorrelation
{
  std::string along;               ///< "rows", "columns" or "time"
  std::vector<double> measured, model;
};

/** \brief Sums over pairs of residuals (after the frame, row and column offsets) one lag apart
  * along rows (direction 0) and columns (1), lags 1 .. max_lag, in even (half 0) and odd (1)
  * frames: what the lab fits the term spatial_correlation to and scores it on
  * (spatial_correlation_fit.h). Indices [half][direction][lag - 1].
  */
struct NeighbourPairs
{
  std::vector<double> products[2][2]; ///< sum of x y
  std::vector<double> squares[2][2];  ///< sum of x^2 + y^2
  std::vector<double> count[2][2];    ///< pairs
  double samples[2] = {0, 0};         ///< residuals in each half
  double variance = 1;                ///< the residuals' variance (x / sqrt(variance) has unit variance)
};

/** \brief What diagnoseResiduals() found. */
struct ResidualDiagnostics
{
  std::vector<UnexplainedStructure> structures; ///< every structure tested, strongest first
  std::vector<ResidualCorrelation> correlations; ///< along rows, columns, time
  double seconds = 0;                           ///< wall time it took
  /** The neighbour pairs of the data (0) and of each of the model's replicas (1 ..). */
  std::vector<NeighbourPairs> neighbour_pairs;

  /** \brief The strongest significant structure, or null when none is. */
  const UnexplainedStructure *
  firstSignificant () const;
};

/** \brief The structure \a model leaves in \a lab's recordings (all frames).
  * \throws pcl::BadArgumentException for settings out of range (replicas < 2, max_lag < 1, bins < 2)
  */
ResidualDiagnostics
diagnoseResiduals (const ModelLab &lab, const NoiseModel &model,
                   const ResidualDiagnosticsSettings &settings = ResidualDiagnosticsSettings ());

} // namespace lab
} // namespace texlet
} // namespace pcl
