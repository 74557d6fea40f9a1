/*
 * pcl_texlet model lab, texlet-level comparison (issue 4, "Compare"): are the texlets' own
 * covariances, propagated from a noise model, the spread of texlet P and N across frames?
 *
 * Per recording, texlets are extracted (pcl::TexletEstimation with the model under test as its
 * noise model and the recording's camera) at the same hexagonal-grid centres in each of a
 * subsample of frames. Per centre, over the frames where its texlet is valid, the mean P and the
 * mean N (normalised) are taken; then per frame the normalised estimation error squared (NEES)
 *   P:  (P - mean P)^T Sigma_P^+ (P - mean P)        (rank(Sigma_P) degrees of freedom: 1 for P
 *       on the centre ray, whose Sigma_P lies along it; 3 for the inliers' mean)
 *   N:  d^T Sigma_N^-1 d,  d = T^T (N - mean N), T = that texlet's tangentFrame ()  (2)
 * For a centre valid in n frames with equal covariances, the deviations from the estimated mean
 * have covariance Sigma (n - 1) / n, so the expected NEES is rank (n - 1) / n for P and
 * 2 (n - 1) / n for N; the ideal of the mean over all (centre, frame) pairs is the same sum over centres
 * divided by the pairs. A ratio above 1 means the texlets are more certain than they should be.
 */
#pragma once

#include <pcl_texlet/lab/recording_measurement.h>
#include <pcl_texlet/noise/noise_model.h>
#include <pcl_texlet/features/texlet_parameters.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{

/** \brief How the texlet comparison samples the recordings. */
struct TexletConsistencySettings
{
  int max_frames = 15;   ///< frames per recording, evenly spaced over it (at least 3)
  int spacing_px = 0;    ///< hexagonal grid spacing of the centres; 0: width / 32 (20 px at 640)
  int radius_px = 6;     ///< texlet disc radius, pixels (the paper's)
  int min_frames = 3;    ///< fewest frames in which a centre's texlet must be valid to be used
  UncertaintyMethod uncertainty = UncertaintyMethod::Analytic; ///< how Sigma_P, Sigma_N are propagated
  unsigned threads = 0;  ///< OpenMP threads of TexletEstimation (0: all)
  /** \brief RANSAC inlier distance, metres; 0 (default): TexletEstimation's automatic one (3 depth
    * SDs of the model, widened by the patch's own residual scale), as a user extracts them. With
    * P on the centre ray, points that drop out in a frame move P only with the plane; 1 m makes
    * every disc point an inlier (the check before the centre ray, docs/model_lab.md).
    */
  double ransac_threshold_m = 0.0;
  TexletCentre centre = TexletCentre::CentreRay; ///< the texlets' P (TexletEstimation's default)
  /** \brief -1: every frame; 0 or 1: only the frames whose index has that parity (the lab's fit
    * and score halves), evenly spaced over them.
    */
  int frame_parity = -1;
};

/** \brief Mean NEES of texlet P and N across frames against their own covariances. */
struct TexletConsistency
{
  double nees_p = std::numeric_limits<double>::quiet_NaN ();  ///< mean NEES of P over (centre, frame) pairs
  double nees_n = std::numeric_limits<double>::quiet_NaN ();  ///< mean NEES of N
  double nees_p_normal = std::numeric_limits<double>::quiet_NaN (); ///< mean NEES of P along the mean normal (1 dof)
  double ideal_p_normal = std::numeric_limits<double>::quiet_NaN (); ///< sum(n-1) / sum(n)
  double ideal_p = std::numeric_limits<double>::quiet_NaN (); ///< its expectation when calibrated: sum over pairs of rank (n-1)/n, over the pairs
  double ideal_n = std::numeric_limits<double>::quiet_NaN (); ///< 2 sum(n-1) / sum(n)
  /** \brief Medians over the pairs, robust to a few texlets that jump (edges in real scenes).
    * Each pair's NEES is (n - 1) / n times a chi-square variable (rank(Sigma_P) or 2 dof) when
    * calibrated, so the ideal median is the median of (n - 1) / n over the pairs times 2.366 (P,
    * each pair's NEES first scaled from its rank's chi-square median to 3 dof's) or 1.386 (N).
    */
  double median_p = std::numeric_limits<double>::quiet_NaN ();
  double median_n = std::numeric_limits<double>::quiet_NaN ();
  double ideal_median_p = std::numeric_limits<double>::quiet_NaN ();
  double ideal_median_n = std::numeric_limits<double>::quiet_NaN ();
  double texlets = 0;    ///< centres used (valid in at least min_frames frames)
  double samples = 0;    ///< (centre, frame) pairs used
  double frames = 0;     ///< frames used over all recordings

  double ratioP () const { return nees_p / ideal_p; } ///< 1 when calibrated
  double ratioN () const { return nees_n / ideal_n; } ///< 1 when calibrated
  double medianRatioP () const { return median_p / ideal_median_p; } ///< 1 when calibrated
  double medianRatioN () const { return median_n / ideal_median_n; } ///< 1 when calibrated
  double ratioPNormal () const { return nees_p_normal / ideal_p_normal; } ///< 1 when calibrated
  /** \brief How far from honest: the larger of |ln (median ratio)| of P and of N; 0 when both
    * are calibrated, ln 10 = 2.3 when one is 10 times over- or under-confident; NaN when nothing
    * was compared.
    */
  double logRatioError () const
  {
    return samples > 0 ? std::max (std::fabs (std::log (medianRatioP ())), std::fabs (std::log (medianRatioN ())))
                       : std::numeric_limits<double>::quiet_NaN ();
  }
};

/** \brief Texlet NEES of \a model on \a recordings (see the file comment).
  * \throws pcl::BadArgumentException for no recording, a null one or bad settings.
  */
TexletConsistency
texletConsistency (const std::vector<RecordingMeasurement::ConstPtr> &recordings, const NoiseModel &model,
                   const TexletConsistencySettings &settings = TexletConsistencySettings ());

} // namespace lab
} // namespace texlet
} // namespace pcl
