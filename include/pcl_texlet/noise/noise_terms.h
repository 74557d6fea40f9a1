/*
 * pcl_texlet: the physical effects of DESIGN.md section 5 as terms of the NoiseModel.
 *
 * Each term is named after its effect, has fittable parameters (the model lab refits them) and
 * fixed settings (image size of a grid, a reference radius). The math is in
 * kernels/effect_terms.h. Terms read the covariates of PixelContext; where one is not known
 * (a single frame in TexletEstimation) they fall back to the steady, phase-averaged form.
 */
#pragma once

#include <pcl_texlet/noise/noise_model.h>

#include <string>
#include <utility>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief A term with named parameters and settings stored as plain vectors. */
class EffectTerm : public NoiseTerm
{
public:
  EffectTerm (std::string name, std::vector<std::string> parameter_names, std::vector<double> values);

  std::string
  name () const override { return name_; }

  std::vector<std::string>
  parameterNames () const override { return names_; }

  std::vector<double>
  parameters () const override { return values_; }

  /** \throws pcl::BadArgumentException on a wrong count or a non-finite value. */
  void
  setParameters (const std::vector<double> &values) override;

  /** \brief Fixed settings (not fitted), name and value. */
  virtual std::vector<std::pair<std::string, double>>
  settings () const { return {}; }

  /** \brief Sets one setting. \throws pcl::BadArgumentException for an unknown name or a bad value. */
  virtual void
  setSetting (const std::string &name, double value);

  /** \brief One line: the physics of the effect. */
  virtual std::string
  physics () const = 0;

  /** \brief The covariate where the effect's signature shows. */
  virtual std::string
  signature () const = 0;

protected:
  std::string name_;
  std::vector<std::string> names_;
  std::vector<double> values_;
};

/** \brief `axial_quadratic`: a constant disparity SD sigma_px; depth variance (J sigma_px)^2. */
class AxialQuadraticTerm : public EffectTerm
{
public:
  explicit AxialQuadraticTerm (double sigma_px = 0.02) : EffectTerm ("axial_quadratic", {"sigma_px"}, {sigma_px}) {}
  double variance (const PixelContext &ctx) const override;
  NoiseTerm::Ptr clone () const override { return std::make_shared<AxialQuadraticTerm> (*this); }
  std::string physics () const override;
  std::string signature () const override { return "depth"; }
};

/** \brief `radial`: the variance of the correlation noise times (1 + gain (r / r_ref)^2)^2. */
class RadialTerm : public EffectTerm
{
public:
  explicit RadialTerm (double gain = 0.0) : EffectTerm ("radial", {"gain"}, {gain}) {}
  double variance (const PixelContext &) const override { return 0.0; }
  double varianceFactor (const PixelContext &ctx) const override;
  NoiseTerm::Ptr clone () const override { return std::make_shared<RadialTerm> (*this); }
  std::vector<std::pair<std::string, double>> settings () const override { return {{"reference_radius_px", r_ref_}}; }
  void setSetting (const std::string &name, double value) override;
  std::string physics () const override;
  std::string signature () const override { return "radius"; }

private:
  double r_ref_ = 400.0;
};

/** \brief `disparity_quantization`: disparity reported in steps of step_px (moments of the
  * rounded disparity at the true depth's sub-step phase; step^2/12 where the phase is unknown).
  */
class DisparityQuantizationTerm : public EffectTerm
{
public:
  explicit DisparityQuantizationTerm (double step_px = 0.125)
    : EffectTerm ("disparity_quantization", {"step_px"}, {step_px}) {}
  double variance (const PixelContext &) const override { return 0.0; }
  void transformMoments (const PixelContext &ctx, double &bias_mm, double &variance_mm2) const override;
  NoiseTerm::Ptr clone () const override { return std::make_shared<DisparityQuantizationTerm> (*this); }
  std::string physics () const override;
  std::string signature () const override { return "phase"; }
};

/** \brief `incidence_angle`: variance times (1 + gain (1/cos(theta) - 1))^2. */
class IncidenceAngleTerm : public EffectTerm
{
public:
  explicit IncidenceAngleTerm (double gain = 0.0) : EffectTerm ("incidence_angle", {"gain"}, {gain}) {}
  double variance (const PixelContext &) const override { return 0.0; }
  double varianceFactor (const PixelContext &ctx) const override;
  NoiseTerm::Ptr clone () const override { return std::make_shared<IncidenceAngleTerm> (*this); }
  std::string physics () const override;
  std::string signature () const override { return "incidence"; }
};

/** \brief `vertical_stripes`: a disparity offset of SD offset_px shared by a column in a frame;
  * `bands` independent bands across the image, so a frame's mean offset has variance offset^2 / bands.
  */
class VerticalStripesTerm : public EffectTerm
{
public:
  explicit VerticalStripesTerm (double offset_px = 0.0, double bands = 6.0)
    : EffectTerm ("vertical_stripes", {"offset_px", "bands"}, {offset_px, bands}) {}
  double variance (const PixelContext &) const override { return 0.0; }
  bool scaledByFactors () const override { return false; }
  double columnVariance (const PixelContext &ctx) const override;
  double frameVariance (const PixelContext &ctx) const override;
  NoiseTerm::Ptr clone () const override { return std::make_shared<VerticalStripesTerm> (*this); }
  std::string physics () const override;
  std::string signature () const override { return "column"; }
};

/** \brief `depth_distortion`: a static disparity offset map (bilinear grid over the image),
  * depth bias -J offset(u, v).
  */
class DepthDistortionTerm : public EffectTerm
{
public:
  /** \throws pcl::BadArgumentException for a size < 2 pixels or fewer than 2 nodes a side. */
  DepthDistortionTerm (int image_width = 640, int image_height = 480, int nodes_x = 17, int nodes_y = 13);
  double variance (const PixelContext &) const override { return 0.0; }
  double bias (const PixelContext &ctx) const override;
  /** \brief Disparity offset at (u, v), px. */
  double offsetPx (double u, double v) const;
  NoiseTerm::Ptr clone () const override { return std::make_shared<DepthDistortionTerm> (*this); }
  std::vector<std::pair<std::string, double>> settings () const override;
  void setSetting (const std::string &name, double value) override;
  std::string physics () const override;
  std::string signature () const override { return "position (bias map)"; }
  int nodesX () const { return nodes_x_; }
  int nodesY () const { return nodes_y_; }
  int imageWidth () const { return width_; }
  int imageHeight () const { return height_; }

private:
  void resize ();
  int width_, height_, nodes_x_, nodes_y_;
};

/** \brief `interference`: variance times 1 + noise_gain (P - 1) for P active projectors. */
class InterferenceTerm : public EffectTerm
{
public:
  explicit InterferenceTerm (double noise_gain = 0.0) : EffectTerm ("interference", {"noise_gain"}, {noise_gain}) {}
  double variance (const PixelContext &) const override { return 0.0; }
  double varianceFactor (const PixelContext &ctx) const override;
  NoiseTerm::Ptr clone () const override { return std::make_shared<InterferenceTerm> (*this); }
  std::string physics () const override;
  std::string signature () const override { return "projectors"; }
};

/** \brief `temporal_drift`: disparity offset A exp(-frame / tau); no bias in the steady state. */
class TemporalDriftTerm : public EffectTerm
{
public:
  explicit TemporalDriftTerm (double amplitude_px = 0.0, double time_constant_frames = 10.0)
    : EffectTerm ("temporal_drift", {"amplitude_px", "time_constant_frames"}, {amplitude_px, time_constant_frames}) {}
  double variance (const PixelContext &) const override { return 0.0; }
  double bias (const PixelContext &ctx) const override;
  NoiseTerm::Ptr clone () const override { return std::make_shared<TemporalDriftTerm> (*this); }
  std::string physics () const override;
  std::string signature () const override { return "frame"; }
};

/** \brief `lateral_noise`: extra variance sigma_edge^2 exp(-dist^2 / (2 width^2)) near edges. */
class LateralNoiseTerm : public EffectTerm
{
public:
  explicit LateralNoiseTerm (double sigma_edge_mm = 0.0, double width_px = 1.5)
    : EffectTerm ("lateral_noise", {"sigma_edge_mm", "width_px"}, {sigma_edge_mm, width_px}) {}
  double variance (const PixelContext &ctx) const override;
  bool scaledByFactors () const override { return false; }
  NoiseTerm::Ptr clone () const override { return std::make_shared<LateralNoiseTerm> (*this); }
  std::string physics () const override;
  std::string signature () const override { return "edge distance"; }
};

/** \brief Names of the effects that can be terms of a NoiseModel, in DESIGN.md order
  * (`intrinsics` is a camera-model effect, not a noise term).
  */
const std::vector<std::string> &
noiseEffectNames ();

/** \brief A new term for effect \a name with neutral parameters (adds nothing until fitted).
  * \throws pcl::BadArgumentException for an unknown name (the message lists the known ones).
  */
NoiseTerm::Ptr
makeNoiseTerm (const std::string &name);

} // namespace texlet
} // namespace pcl
