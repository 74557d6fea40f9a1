/*
 * pcl_texlet model lab (internal): the recordings' own resolution. The lab reads depth in whole
 * millimetres (16-bit images; every reader's frames are stored so), and a sample's moments are
 * the model's moments rounded to whole millimetres, with the rounded Gaussian's moments of
 * disparity_quantization (docs/model_lab.md section 6).
 */
#pragma once

#include <pcl_texlet/noise/noise_model.h>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** The moments of one recorded sample. */
struct RecordedMoments
{
  double variance_mm2 = 0;   ///< of the recorded, whole-mm value
  double mean_offset_mm = 0; ///< recorded mean minus the mean before the rounding
};

/** Moments of a sample of \a model recorded in whole millimetres, where the model gives the
  * variance \a variance_mm2 (never taken below the model's floor) and the mean \a mean_mm before
  * the rounding. Where the noise is below a millimetre the SD and the mean swing with
  * \a mean_mm's sub-millimetre phase. A model that rounds the disparity (\a quantised) gives
  * levels, not a Gaussian: each level's own rounding to whole millimetres is then taken as the
  * phase average, 1/12 mm^2 and no offset.
  */
RecordedMoments
recordedMoments (const NoiseModel &model, bool quantised, double variance_mm2, double mean_mm);

/** recordedMoments ()'s variance averaged over a uniform sub-millimetre phase of the mean: what a
  * covariate bin, whose pixels sit at every phase, sees within its pixels.
  */
double
recordedVarianceOverPhases (const NoiseModel &model, bool quantised, double variance_mm2);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
