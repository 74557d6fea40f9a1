/*
 * pcl_texlet: the depth noise model, a sum of composable terms.
 *
 * Each term contributes a variance (and optionally a bias) of the depth in millimetres at a
 * pixel; the model's sigma is the root of their sum. The default model is the paper's
 * polynomial f(r, d) (Eq. 4). Terms expose their parameters by name so that the model lab can
 * fit them, and the properties the lab needs to fit them (which are linear, which round, which
 * depend on the frame); one NoiseModel object is passed down from the sensor model to the
 * texlets. The physical effects' terms are made by the effect registry (noise/noise_terms.h).
 */
#pragma once

#include <pcl_texlet/kernels/noise_terms.h>
#include <pcl_texlet/noise/effect.h>
#include <pcl_texlet/noise/pixel_context.h>

#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief What a model predicts for one depth sample: bias and the parts of its variance. */
struct NoiseMoments
{
  double bias_mm = 0.0;               ///< expected measured minus true depth, mm
  double variance_mm2 = 0.0;          ///< variance independent from pixel to pixel, mm^2
  double column_variance_mm2 = 0.0;   ///< variance shared by a column of pixels within a frame, mm^2
  double row_variance_mm2 = 0.0;      ///< variance shared by a row of pixels within a frame, mm^2
  double frame_variance_mm2 = 0.0;    ///< the part of both shared by all pixels of a frame, mm^2
  double row_frame_variance_mm2 = 0.0; ///< the rows' part of frame_variance_mm2, mm^2
  /** Columns over which the correlation of two columns' shared offsets falls by a factor e
    * (columnCorrelationPx () of the terms with a column variance, their rates weighted by it);
    * infinite: every column of a frame shares them. */
  double column_correlation_px = std::numeric_limits<double>::infinity ();
  /** Rows over which the correlation of two rows' shared offsets falls by a factor e (as
    * column_correlation_px, for the terms with a row variance). */
  double row_correlation_px = std::numeric_limits<double>::infinity ();
  double sigma_mm = 0.0;              ///< total SD, sqrt of the three variances, never below the floor
  /** The share of variance_mm2 that neighbours share over a window (spatial_correlation): two
    * pixels du, dv apart correlate by window_share tri(du) tri(dv), tri(d) = max(0, 1 - |d| / window_px). */
  double window_share = 0.0;
  double window_px = 1.0; ///< that window's width, pixels

  /** \brief The column offsets' variance about their frame's offset, mm^2. */
  double
  columnWithinFrameMm2 () const { return column_variance_mm2 - (frame_variance_mm2 - row_frame_variance_mm2); }

  /** \brief The row offsets' variance about their frame's offset, mm^2. */
  double
  rowWithinFrameMm2 () const { return row_variance_mm2 - row_frame_variance_mm2; }

  /** \brief The variance a pixel shares with its column and its row (their frame's part included), mm^2. */
  double
  sharedVarianceMm2 () const { return column_variance_mm2 + row_variance_mm2; }
};

/** \brief One physical contribution to the depth noise. */
class NoiseTerm
{
public:
  using Ptr = std::shared_ptr<NoiseTerm>;
  using ConstPtr = std::shared_ptr<const NoiseTerm>;

  virtual ~NoiseTerm () = default;

  /** \brief Name of the effect (the registry's vocabulary where one applies). */
  virtual std::string
  name () const = 0;

  /** \brief Variance contribution, mm^2 (>= 0). */
  virtual double
  variance (const PixelContext &ctx) const = 0;

  /** \brief Bias contribution (measured minus true depth), mm. */
  virtual double
  bias (const PixelContext &) const { return 0.0; }

  /** \brief Factor on the variance of the terms that are scaled (effects that multiply the
    * disparity SD: radial, incidence angle, interference). 1 for additive terms.
    */
  virtual double
  varianceFactor (const PixelContext &) const { return 1.0; }

  /** \brief Whether variance() is multiplied by the other terms' factors (true for noise of the
    * correlation itself; false for offsets added after it, such as stripes).
    */
  virtual bool
  scaledByFactors () const { return true; }

  /** \brief Variance shared by all pixels of a column within one frame (vertical stripes), mm^2. */
  virtual double
  columnVariance (const PixelContext &) const { return 0.0; }

  /** \brief Variance shared by all pixels of a row within one frame (horizontal bands), mm^2. A
    * term shares its offsets along columns or along rows, not both.
    */
  virtual double
  rowVariance (const PixelContext &) const { return 0.0; }

  /** \brief The part of columnVariance () (or rowVariance ()) shared by every pixel of a frame, mm^2. */
  virtual double
  frameVariance (const PixelContext &) const { return 0.0; }

  /** \brief Columns over which the correlation of two columns' offsets (columnVariance ()) falls
    * by a factor e: exp(-|du| / L) for columns du apart. Infinite (the default): all share them.
    */
  virtual double
  columnCorrelationPx (const PixelContext &) const { return std::numeric_limits<double>::infinity (); }

  /** \brief Rows over which the correlation of two rows' offsets (rowVariance ()) falls by a
    * factor e. Infinite (the default): all share them.
    */
  virtual double
  rowCorrelationPx (const PixelContext &) const { return std::numeric_limits<double>::infinity (); }

  /** \brief The share of the pixel's own variance (NoiseMoments::variance_mm2) that neighbours
    * share over a window (NoiseMoments::window_share); 0 by default.
    */
  virtual double
  windowShare (const PixelContext &) const { return 0.0; }

  /** \brief That window's width, pixels (NoiseMoments::window_px); 1 by default. */
  virtual double
  windowPx (const PixelContext &) const { return 1.0; }

  /** \brief Applied last, to the bias and the independent variance of the depth before the
    * sensor reports it (disparity quantisation). Identity by default.
    */
  virtual void
  transformMoments (const PixelContext &, double & /*bias_mm*/, double & /*variance_mm2*/) const {}

  virtual std::vector<std::string>
  parameterNames () const = 0;

  virtual std::vector<double>
  parameters () const = 0;

  /** \throws pcl::BadArgumentException on a wrong count or a non-finite value. */
  virtual void
  setParameters (const std::vector<double> &values) = 0;

  virtual Ptr
  clone () const = 0;

  /** \brief Fixed settings (not fitted), name and value; none by default. */
  virtual std::vector<std::pair<std::string, double>>
  settings () const { return {}; }

  /** \brief Sets one setting. \throws pcl::BadArgumentException for an unknown name or a bad value. */
  virtual void
  setSetting (const std::string &name, double value);

  // --- What the model lab reads of a term (properties, so that it needs no effect's name).

  /** \brief A typical magnitude of parameter \a k: the lab's fit scales the parameter by
    * max (|value|, typical) so that every scaled parameter is of order one.
    */
  virtual double
  typicalScale (std::size_t /*k*/) const { return 1.0; }

  /** \brief The least meaningful value of parameter \a k (effects::TermParameter::lowest): the
    * term reads a value below it as this one. Unbounded by default.
    */
  virtual double
  lowestValue (std::size_t /*k*/) const { return -std::numeric_limits<double>::infinity (); }

  /** \brief Whether parameter \a k moves only the steady mean (effects::TermParameter::
    * fitted_to_means): the lab fits it to the pixels' means with the surfaces. None by default.
    */
  virtual bool
  fittedToMeans (std::size_t /*k*/) const { return false; }

  /** \brief Whether bias () depends on PixelContext::frame (then the lab predicts the frames'
    * mean offsets from it).
    */
  virtual bool
  frameDependent () const { return false; }

  /** \brief Whether transformMoments () rounds the disparity; roundingMoments () then gives the
    * rounding's moments at one pixel's own sub-step phase.
    */
  virtual bool
  quantises () const { return false; }

  /** \brief Whether the term can move the mean depth (a bias (), a linear bias map, a rounding):
    * false for a term of variance only; a term that does not say is taken to move it.
    */
  virtual bool
  movesMean () const { return true; }

  /** \brief Whether the term can change a pixel's depth SD (NoiseModel::sigmaMm ()): a variance,
    * a factor, a line's variance or a transform of the moments. False for a term that only says
    * how the others' variance is shared (spatial_correlation) or only moves the mean; a term
    * that does not say is taken to change it.
    */
  virtual bool
  changesDepthSd () const { return true; }

  /** \brief Mean offset and variance (px) of a disparity N(\a d0_px, \a sigma_px^2) after the
    * term's rounding; no rounding by default.
    */
  virtual void
  roundingMoments (double /*d0_px*/, double sigma_px, double &mean_offset_px, double &variance_px2) const
  {
    mean_offset_px = 0.0;
    variance_px2 = sigma_px * sigma_px;
  }

  /** \brief For a term whose bias is linear in its parameters (a disparity offset map,
    * offset(u, v) = sum_k parameter_k basis_k(u, v), bias = -J offset): the most basis functions
    * that are non-zero at one pixel. 0 (the default): the bias is not linear, or there is none.
    * The lab fits such a term by least squares with the surfaces.
    */
  virtual int
  linearBiasSupport () const { return 0; }

  /** \brief The linearBiasSupport () basis functions at pixel (\a u, \a v): their parameter
    * indices and values (disparity px per unit of parameter).
    */
  virtual void
  linearBiasBasis (double /*u*/, double /*v*/, int * /*index*/, double * /*weight*/) const {}

  /** \brief The factor by which the linear bias basis scales at depth \a depth_mm (f b \a fb_px_m),
    * from the term's settings: 1 (the default) for a disparity offset map the same at every
    * depth.
    */
  virtual double
  linearBiasShape (double /*depth_mm*/, double /*fb_px_m*/) const { return 1.0; }

  /** \brief The settings that shape a linear bias along depth and the values the lab tries for
    * each (it keeps the combination whose least-squares fit is best); empty (the default): none.
    */
  virtual std::vector<std::pair<std::string, std::vector<double>>>
  linearBiasShapeSearch () const { return {}; }

  /** \brief The settings that choose between the forms the term's physics allows, and the values
    * the lab tries for each when it adds the term (it keeps the form whose first fit is best);
    * empty (the default): one form.
    */
  virtual std::vector<std::pair<std::string, std::vector<double>>>
  formSearch () const { return {}; }

  /** \brief Sets the values the lab starts a fit from (a neutral value is a saddle), some of
    * them from what it knows of the recordings.
    */
  virtual void
  setLabStart (const effects::LabStart & /*facts*/) {}
};

/** \brief Sigma as a second-order polynomial in r (px) and d (mm): the paper's Eq. 4.
  * Contributes max(f, 0)^2 as variance.
  */
class PolynomialSigmaTerm : public NoiseTerm
{
public:
  explicit PolynomialSigmaTerm (const kernels::PolynomialCoefficients &c = kernels::paperPolynomial ())
    : c_ (c) {}

  std::string
  name () const override { return "polynomial"; }

  double
  sigmaMm (const PixelContext &ctx) const;

  double
  variance (const PixelContext &ctx) const override;

  std::vector<std::string>
  parameterNames () const override;

  std::vector<double>
  parameters () const override;

  void
  setParameters (const std::vector<double> &values) override;

  NoiseTerm::Ptr
  clone () const override { return std::make_shared<PolynomialSigmaTerm> (*this); }

  bool
  movesMean () const override { return false; }

  /** \brief The coefficients span many orders of magnitude: each is its own scale. */
  double
  typicalScale (std::size_t) const override { return 1e-12; }

  const kernels::PolynomialCoefficients &
  coefficients () const { return c_; }

private:
  kernels::PolynomialCoefficients c_;
};

/** \brief Depth noise model: sigma = sqrt(sum of the terms' variances), never below a floor. */
class NoiseModel
{
public:
  /** \brief An empty model (sigma is the floor everywhere until terms are added). */
  NoiseModel () = default;
  NoiseModel (const NoiseModel &other);
  NoiseModel &
  operator= (const NoiseModel &other);
  NoiseModel (NoiseModel &&) = default;
  NoiseModel &
  operator= (NoiseModel &&) = default;

  /** \brief The paper's model: one PolynomialSigmaTerm with the coefficients of Eq. 4. */
  static NoiseModel
  paper ();

  /** \brief Adds a term (the model keeps its own copy). */
  NoiseModel &
  add (const NoiseTerm &term);

  const std::vector<NoiseTerm::Ptr> &
  terms () const { return terms_; }

  /** \brief The term named \a name, or null. */
  NoiseTerm::Ptr
  find (const std::string &name) const;

  /** \brief Depth SD in mm at \a ctx; NaN if the depth is not positive and finite. */
  double
  sigmaMm (const PixelContext &ctx) const;

  /** \brief Sum of the terms' biases in mm at \a ctx (after transformMoments). */
  double
  biasMm (const PixelContext &ctx) const;

  /** \brief Whether a term can move the mean depth (NoiseTerm::movesMean ()): where none does,
    * biasMm () is 0 everywhere.
    */
  bool
  movesMean () const;

  /** \brief Bias and variance parts at \a ctx: variance = (sum of scaled terms' variances) x
    * (product of factors) + (unscaled terms' variances), then transformMoments of each term;
    * sigma = sqrt(variance + column variance), never below the floor. NaN sigma for a depth that
    * is not positive and finite.
    */
  NoiseMoments
  moments (const PixelContext &ctx) const;

  /** \brief Removes the term named \a name; true if there was one. */
  bool
  remove (const std::string &name);

  /** \brief Smallest sigma the model reports (default 0.1 mm): keeps every point's weight
    * finite where a fitted polynomial dips toward zero outside its range.
    * \throws pcl::BadArgumentException unless positive and finite.
    */
  void
  setMinSigmaMm (double sigma);

  double
  minSigmaMm () const { return min_sigma_mm_; }

  /** \brief Whether the model is one PolynomialSigmaTerm and nothing else (the paper's model,
    * the default); then \a c gets its coefficients and sigmaMm () equals
    * kernels::polynomialSigmaMm (c, radius_px, depth_mm, minSigmaMm ()) bit for bit, which
    * per-pixel loops can evaluate without the terms' virtual calls.
    */
  bool
  isPolynomialOnly (kernels::PolynomialCoefficients &c) const;

  /** \brief Whether the model's depth SD is one PolynomialSigmaTerm's, every other term leaving
    * it as it is (NoiseTerm::changesDepthSd ()); then \a c gets its coefficients and sigmaMm ()
    * equals kernels::polynomialSigmaMm (c, radius_px, depth_mm, minSigmaMm ()) bit for bit.
    */
  bool
  depthSdIsPolynomial (kernels::PolynomialCoefficients &c) const;

private:
  std::vector<NoiseTerm::Ptr> terms_;
  double min_sigma_mm_ = 0.1;
};

} // namespace texlet
} // namespace pcl
