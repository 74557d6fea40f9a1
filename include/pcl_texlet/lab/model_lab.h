/*
 * pcl_texlet model lab, steps 2, 4 and 5: compare a NoiseModel with measured recordings, rank
 * the effects it lacks by the held-out fall of the error they bring, add them and refit.
 *
 * The data are split into two halves (even and odd frames; for recordings of fewer than four
 * frames, a checkerboard of 32 px blocks). A model is fitted on the first half and scored on the
 * second. Recordings of one frame (single-frame sets, e.g. calibration walls) have one sample a
 * pixel: their within, column and frame parts are empty and only the static part is left, so the
 * variance parameters keep the model's values (no temporal contrast to fit them on) and effects
 * that add variance only are not testable (docs/model_lab.md, "Few frames"). The score is the Gaussian negative log-likelihood per depth sample, decomposed into
 * parts the effects show in:
 *   - within: each sample's deviation from its pixel's mean, its frame's mean and its column's
 *     mean in that frame, against the model's independent variance;
 *   - static: each pixel's mean minus the surface and the model's bias, against variance / n;
 *   - column: the mean offset of each column in each frame (disparity), against the model's
 *     column-shared variance plus the noise of a mean;
 *   - frame: the mean offset of each frame (disparity), against the model's frame-dependent bias.
 * For independent noise with no bias this is the plain per-sample NLL; the other parts let
 * stripes and drift, which add the same per-pixel variance as axial noise, be told apart.
 *
 * Fits: the surface planes and a depth_distortion grid are linear (Eigen least squares); the
 * other parameters are fitted by Ceres (L-BFGS on the NLL, central differences) on covariate
 * bins (recording, radius, depth, incidence, edge distance and, where a model quantises,
 * sub-step phase). Significance: a candidate's held-out gain is compared with the gains the
 * same fit brings on data drawn from the current model (parametric bootstrap): significant
 * when it exceeds their mean by more than 4 of their SDs, removes enough of the error where it
 * shows, and does not leave the texlets' covariances less honest on the score half (LabSettings).
 */
#pragma once

#include <pcl_texlet/lab/recording_measurement.h>
#include <pcl_texlet/lab/texlet_consistency.h>
#include <pcl_texlet/noise/noise_model.h>

#include <functional>
#include <limits>
#include <memory>
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
struct PixelErrors;
} // namespace detail

/** \brief Which samples a computation uses. */
enum class Half
{
  all,    ///< every frame and pixel
  fit,    ///< even frames (or even 32 px blocks for recordings of fewer than 4 frames)
  score   ///< odd frames (or odd blocks)
};

/** \brief How well a model describes the samples of one half. */
struct LabMetrics
{
  /** \brief RMS over pixels of predicted minus measured temporal SD, over the pixels with at
    * least two samples; NaN when none has (single-frame sets: not measurable).
    */
  double sd_rmse_mm = 0;
  /** \brief The part of sd_rmse_mm that no model removes: the RMS over pixels of how far an SD
    * measured from the pixel's samples falls from its true SD by chance, estimated from the SDs
    * of the pixel's alternate samples (a model-free measure; pixels with at least four samples).
    * Compare sqrt (sd_rmse_mm^2 - sd_floor_mm^2), the model's own SD error. NaN where no pixel
    * has four samples.
    */
  double sd_floor_mm = 0;
  double bias_rmse_mm = 0;  ///< RMS over pixels of measured minus predicted bias (mean - surface)
  /** \brief The spatial SD of the bias residual after removing its smooth part: each pixel's
    * residual (measured minus predicted mean) minus the mean of its neighbours' within 3 px,
    * RMS, scaled by k / (k + 1) for k neighbours so that white noise gives its own SD. What a
    * single frame shows of the noise (the SD of a pixel's mean where pixels have several
    * samples); compare with bias_spatial_sd_pred_mm.
    */
  double bias_spatial_sd_mm = 0;
  /** \brief The model's prediction of bias_spatial_sd_mm: the RMS over the same pixels of the
    * predicted SD of a pixel's mean, sqrt (variance / n), counting of the column and row offsets
    * only the part that does not cancel against the neighbours' (none of a frame's offset).
    */
  double bias_spatial_sd_pred_mm = 0;
  double nll = 0;           ///< Gaussian NLL per depth sample (see the file comment)
  double within_1sigma = 0; ///< share of samples within 1 sigma of the model's mean
  double within_2sigma = 0; ///< share of samples within 2 sigma
  double pixels = 0;        ///< pixels compared
  double samples = 0;       ///< depth samples compared
  /** \brief Texlet NEES of P and N across frames (texletConsistency); filled by runLabSession
    * for the starting model and each step (samples == 0: not computed, e.g. for candidates).
    */
  TexletConsistency texlets;
};

/** \brief One effect tried on top of the current model. */
struct Candidate
{
  std::string effect;       ///< effect name (noiseEffectNames (); docs/sensor_model.md section 6)
  std::string physics;      ///< one line
  std::string signature;    ///< the covariate where it shows
  LabMetrics metrics;       ///< held-out metrics (score half) after adding it
  double gain = 0;          ///< held-out fall of the NLL per sample against the current model refitted
  double null_mean = 0;     ///< mean gain of the same fit on data drawn from the current model
  double null_sd = 0;       ///< SD of those gains
  double threshold = 0;     ///< gain needed to be significant (also: gain * score samples >= LabSettings::min_total_gain_nats)
  double total_gain = 0;    ///< gain times the score half's samples: the held-out log-likelihood ratio, nats
  /** \brief The practical effect where its signature shows, on the score half: the share of
    * the mean squared error of the predicted SD, or of the bias (the larger), that it removes
    * over the pixels where adding it moves that prediction by at least half its 95th-percentile
    * move.
    */
  double effect_size = 0;
  /** \brief Which error effect_size is of: "sd", "bias", "offsets" (of columns and rows) or
    * "correlation" (of neighbours' residuals). */
  std::string effect_shows_in;
  double effect_share = 0;      ///< share of the score half's pixels where it shows
  double error_before = 0;      ///< the RMS error there under the current model refitted, in error_unit
  double error_after = 0;       ///< ... and with the candidate
  std::string error_unit = "mm"; ///< "mm", or "correlation" (dimensionless) for terms of the neighbours' correlation
  bool statistically_significant = false; ///< gain > threshold and total_gain >= LabSettings::min_total_gain_nats
  /** \brief statistically_significant and effect_size >= LabSettings::min_effect_size (detectable
    * and large enough to matter), and its texlets no less honest than the current model's by more
    * than LabSettings::max_texlet_worsening.
    */
  bool significant = false;
  /** \brief The texlets' distance from honest covariances (TexletConsistency::logRatioError) on
    * the score half's frames: under the current model refitted on the fit half, and with this
    * candidate (whose texlets are metrics.texlets). Computed for the statistically significant
    * candidates; NaN for the others.
    */
  double texlet_error_before = std::numeric_limits<double>::quiet_NaN ();
  double texlet_error_after = std::numeric_limits<double>::quiet_NaN (); ///< see texlet_error_before
  /** \brief Passed both tests, but its texlets are further from honest than the current model's
    * by more than LabSettings::max_texlet_worsening, so not significant. */
  bool texlets_less_honest = false;
  bool applicable = true;   ///< false when the data cannot show it (reason in note)
  std::string note;         ///< why not applicable, or remarks
  NoiseModel model;         ///< the model with it, fitted on the fit half
};

/** \brief In words, for reports: "significant", "detectable, too small", "detectable, makes the
  * texlets less honest", "not significant" or "not testable".
  */
std::string
candidateVerdict (const Candidate &c);

/** \brief Options of the lab. */
struct LabSettings
{
  int null_replicates = 5;       ///< bootstrap data sets for the significance test
  double null_sigmas = 4.0;      ///< significance: gain > null mean + null_sigmas * null SD
  /** \brief Significance also needs the held-out gain summed over the score half's samples to
    * reach this many nats (a likelihood ratio of e^3 = 20 on data the fit did not see): five
    * bootstrap gains of a term that often fits to its neutral value can have an SD near zero, and
    * then a gain no likelihood-ratio test would call evidence passes mean + 4 SDs
    * (docs/model_lab.md section 4).
    */
  double min_total_gain_nats = 3.0;
  /** \brief Significance also needs the candidate's effect size (Candidate::effect_size) to reach
    * this fraction: with millions of samples a gain of 1e-5 nats per sample is detectable, yet
    * brings the error where the effect shows down by a fraction of a percent (docs/model_lab.md
    * section 4).
    */
  double min_effect_size = 0.05;
  /** \brief Significance also needs a candidate not to make the texlets' covariances less
    * honest: on the score half's frames its texlets' distance from honest
    * (Candidate::texlet_error_after, the larger |ln| of the median NEES ratios of P and N) may
    * exceed the current model's by at most this; ln 1.25: 25 % further from honest. A rounding
    * is exempt (the texlets take the model's bias off their readings, but a rounding's phase at a
    * reading is unknown; docs/model_lab.md section 4).
    */
  double max_texlet_worsening = 0.22314355131420976;
  int outer_iterations = 3;      ///< alternations of the linear (bias) and Ceres (variance) fits
  int max_lbfgs_iterations = 60; ///< per Ceres run
  unsigned seed = 1;             ///< bootstrap seed
  int threads = 0;               ///< OpenMP threads (0: default)
  std::function<void (const std::string &)> progress; ///< progress lines, or empty
};

/** \brief The lab: recordings, a model to compare, candidates to add. */
class ModelLab
{
public:
  explicit ModelLab (const LabSettings &settings = LabSettings ());
  ~ModelLab ();
  ModelLab (const ModelLab &) = delete;
  ModelLab &
  operator= (const ModelLab &) = delete;

  /** \brief Adds a measured recording. \throws pcl::BadArgumentException for null. */
  void
  addRecording (const RecordingMeasurement::ConstPtr &recording);

  const std::vector<RecordingMeasurement::ConstPtr> &
  recordings () const { return recordings_; }

  /** \brief Whether the halves are frame halves (true) or pixel blocks (recordings < 4 frames). */
  bool
  splitsFrames () const;

  /** \brief Per-pixel metrics of \a model on \a half (the surfaces are refitted to the model's
    * bias; the model's parameters are not).
    * \throws pcl::BadArgumentException when no recording was added.
    */
  LabMetrics
  evaluate (const NoiseModel &model, Half half = Half::all) const;

  /** \brief Texlet NEES of \a model on \a half's frames (Analytic, TexletEstimation's defaults,
    * the lab's threads): Half::all every frame; Half::fit or Half::score that half's frames where
    * the halves are frame halves, every frame where they are pixel blocks (a texlet spans blocks).
    */
  TexletConsistency
  texlets (const NoiseModel &model, Half half = Half::all) const;

  /** \brief \a model with every parameter refitted on \a half. */
  NoiseModel
  fit (const NoiseModel &model, Half half = Half::all) const;

  /** \brief Every effect of noiseEffectNames () not in \a current, fitted with it on the fit
    * half and scored on the score half, best (largest gain) first.
    */
  std::vector<Candidate>
  rankCandidates (const NoiseModel &current) const;

  /** \brief Why the recordings cannot show the registered effect \a effect (single frames, no
    * plane scene, one projector count, too few frames to split, no depth edges, no colour), or
    * empty when they can.
    * \throws pcl::BadArgumentException for an effect that is not registered
    */
  std::string
  whyNotApplicable (const std::string &effect) const;

  /** \brief \a current with effect \a effect added and every parameter refitted on all data.
    * \throws pcl::BadArgumentException for an unknown effect, one already in the model, or one
    * the recordings cannot show (whyNotApplicable()).
    */
  NoiseModel
  addEffect (const NoiseModel &current, const std::string &effect) const;

  /** \brief The context of pixel \a i of recording \a r (covariates from the measurement). */
  PixelContext
  context (std::size_t r, std::size_t i) const;

  /** \brief Per-pixel predicted temporal SD and mean depth (surface refitted to the model's
    * bias, plus the bias) of \a model over all frames, for maps and curves: one vector per
    * recording, NaN where the pixel is not used. One fit of the static bias serves every
    * recording.
    */
  void
  predict (const NoiseModel &model, std::vector<std::vector<float>> &sd_mm,
           std::vector<std::vector<float>> &mean_mm) const;

  /** \brief Predicted frame-dependent bias (mm, relative to the steady state) of \a model at the
    * central pixel of recording \a r for each of its frames, and the measured mean offset of
    * each frame (mm at that pixel's depth): the drift curve.
    */
  void
  frameCurve (const NoiseModel &model, std::size_t r, std::vector<double> &predicted_mm, std::vector<double> &measured_mm) const;

  const LabSettings &
  settings () const { return settings_; }

  struct Data; ///< aggregates of one half (internal)

private:
  /** \brief The aggregates of \a half, their sub-step phases on the disparity that
    * \a reference's static distortion (its linear bias term, if any) gives before rounding.
    * Built on first use and kept while the reference's distortion stays the same.
    */
  std::shared_ptr<const Data>
  data (Half half, const NoiseModel &reference) const;

  /** \brief evaluate () on aggregates \a d, also giving each pixel's predicted and measured SD
    * and mean when \a pixels is not null.
    */
  LabMetrics
  evaluate (const NoiseModel &model, const Data &d, detail::PixelErrors *pixels) const;

  /** The aggregates of one half and the distortion their phases were built on. */
  struct CachedData
  {
    std::vector<double> distortion;
    std::shared_ptr<const Data> data;
  };

  /** What the recordings can show (whyNotApplicable()), measured once as each is added. */
  struct RecordingFacts
  {
    bool any_plane = false, any_edges = false, any_repeated = false, any_intensity = false;
    bool all_split = true; ///< every recording has at least 4 frames (splitsFrames())
    double min_projectors = 0, max_projectors = 0;
  };

  LabSettings settings_;
  std::vector<RecordingMeasurement::ConstPtr> recordings_;
  RecordingFacts facts_;
  mutable CachedData data_[3];
};

} // namespace lab
} // namespace texlet
} // namespace pcl
