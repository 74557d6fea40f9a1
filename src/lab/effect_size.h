/*
 * pcl_texlet model lab (internal): a candidate's practical effect, the fall of the per-pixel
 * error where its signature shows. A gain of 1e-5 nats per sample can be statistically certain
 * on millions of samples and still change nothing a user would see (docs/model_lab.md section 4).
 */
#pragma once

#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** Per-pixel predictions and measurements of one model on one half (ModelLab::evaluate). */
struct PixelErrors
{
  std::vector<float> sd_pred, sd_meas;     ///< temporal SD, mm
  std::vector<float> mean_pred, mean_meas; ///< mean depth (surface plus the model's bias), mm
  std::vector<float> line_pred, line_meas; ///< SD of each column's and row's offsets about its frame's, mm
};

/** The practical effect of replacing \a base's predictions by \a candidate's (same pixels). */
struct EffectSize
{
  double sd_fall = 0, bias_fall = 0, line_fall = 0;    ///< 1 - mse(candidate) / mse(base) where each shows
  double sd_share = 0, bias_share = 0, line_share = 0; ///< share of the pixels (lines) where each shows
  double sd_before_mm = 0, sd_after_mm = 0, bias_before_mm = 0, bias_after_mm = 0, line_before_mm = 0, line_after_mm = 0;
};

/** Where a candidate shows: the pixels where it moves the prediction (SD, or the mean) by at
  * least half the 95th percentile of its moves over all pixels; there, the share of the mean
  * squared error of the SD and of the bias that it removes (as R^2 is the share of a variance a
  * model explains: the measured SD's own sampling noise stays in both, so the share of the
  * error a model can remove is what is measured, not the noise). Zero where it moves nothing.
  * The same for the SD of the columns' and rows' offsets, where a term of shared offsets shows
  * first: its per-pixel SD also depends on how many layouts a pixel's frames saw.
  */
EffectSize
effectSize (const PixelErrors &base, const PixelErrors &candidate);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
