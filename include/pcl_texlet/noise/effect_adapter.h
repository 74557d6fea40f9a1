/*
 * pcl_texlet noise: the adapters that make an effect file (noise/effects/<name>.h) into a noise
 * term, the simulator's hooks and a catalogue entry, and EffectRegistry::add.
 *
 * An effect defines only the hooks it has (noise/effect.h lists them); for the others the
 * adapters give the neutral value (no variance or bias, factor 1, readable, no offset), so that
 * a contribution that is absent adds exactly 0 or multiplies by exactly 1.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>
#include <pcl_texlet/noise/effect_registry.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace detail
{

/** \brief Throws pcl::BadArgumentException with \a message (kept out of the templates, so that
  * this header needs no PCL).
  */
[[noreturn]] void
throwBadArgument (const std::string &message);

/** \brief Whether Op<E> is a valid type: which hooks an effect has. */
template <typename E, template <typename> class Op, typename = void>
struct Has : std::false_type
{
};

template <typename E, template <typename> class Op>
struct Has<E, Op, std::void_t<Op<E>>> : std::true_type
{
};

/** \brief An effect's term settings, effects::NoSettings if it has none. */
template <typename E, typename = void>
struct SettingsOfImpl
{
  using type = effects::NoSettings;
};

template <typename E>
struct SettingsOfImpl<E, std::void_t<typename E::TermSettings>>
{
  using type = typename E::TermSettings;
};

template <typename E> using SettingsOf = typename SettingsOfImpl<E>::type;

// Flags.
template <typename E> using ScaledOp = decltype (E::kScaledByFactors);
template <typename E> using FrameDependentOp = decltype (E::kFrameDependent);
template <typename E> using LabNeedsOp = decltype (E::kLabNeeds);
template <typename E> using ForeignLoadOp = decltype (E::kNeedsForeignLoad);

// The simulator's hooks.
template <typename E> using SimParametersOp = typename E::SimParameters;
template <typename E> using SimPar = const typename E::SimParameters &;
template <typename E> using ReadableOp = decltype (E::readable (std::declval<SimPar<E>> (), effects::SimPixel ()));
template <typename E>
using DisparityVarianceOp = decltype (E::disparityVariance (std::declval<SimPar<E>> (), effects::SimPixel ()));
template <typename E> using SdFactorOp = decltype (E::sdFactor (std::declval<SimPar<E>> (), effects::SimPixel ()));
template <typename E> using DropoutOp = decltype (E::dropout (std::declval<SimPar<E>> (), effects::SimPixel ()));
template <typename E>
using DisparityOffsetOp =
    decltype (E::disparityOffset (std::declval<SimPar<E>> (), effects::SimSensor (), effects::SimPixel ()));
template <typename E> using FrameOffsetOp = decltype (E::frameOffset (std::declval<SimPar<E>> (), 0u));
template <typename E>
using ColumnOffsetsOp = decltype (E::addColumnOffsets (std::declval<SimPar<E>> (), effects::SimSensor (), 0u,
                                                       std::declval<float *> ()));
template <typename E>
using FrameSettingsOp =
    decltype (E::frameSettings (std::declval<SimPar<E>> (), std::declval<kernels::SensorFrameSettings &> ()));
template <typename E>
using LabelCameraOp =
    decltype (E::labelCamera (std::declval<SimPar<E>> (), true, std::declval<effects::CameraLabel &> ()));

// The term's closed forms.
template <typename E> using TermParametersOp = decltype (E::termParameters ());
template <typename E>
using TermParameterNamesOp = decltype (E::termParameterNames (std::declval<const SettingsOf<E> &> ()));
template <typename E> using TermSettingsFieldsOp = decltype (E::termSettings ());
template <typename E>
using SettingsProblemOp = decltype (E::settingsProblem (std::declval<const SettingsOf<E> &> ()));
template <typename E>
using LabStartOp = decltype (E::labStart (effects::LabStart (), std::declval<double *> (),
                                          std::declval<SettingsOf<E> &> ()));
template <typename E> using Args = const SettingsOf<E> &;
template <typename E>
using VarianceOp = decltype (E::variance (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using BiasOp = decltype (E::bias (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using VarianceFactorOp =
    decltype (E::varianceFactor (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using ColumnVarianceOp =
    decltype (E::columnVariance (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using RowVarianceOp =
    decltype (E::rowVariance (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using RowCorrelationOp =
    decltype (E::rowCorrelationPx (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using FrameVarianceOp =
    decltype (E::frameVariance (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using ColumnCorrelationOp =
    decltype (E::columnCorrelationPx (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using WindowShareOp =
    decltype (E::windowShare (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using WindowPxOp =
    decltype (E::windowPx (std::declval<const double *> (), std::declval<Args<E>> (), PixelContext ()));
template <typename E>
using TransformOp = decltype (E::transformMoments (std::declval<const double *> (), std::declval<Args<E>> (),
                                                   PixelContext (), std::declval<double &> (),
                                                   std::declval<double &> ()));
template <typename E>
using RoundingOp = decltype (E::roundingMoments (std::declval<const double *> (), std::declval<Args<E>> (), 0.0, 0.0,
                                                 std::declval<double &> (), std::declval<double &> ()));
template <typename E>
using BiasBasisOp = decltype (E::biasBasis (std::declval<Args<E>> (), 0.0, 0.0, std::declval<int *> (),
                                            std::declval<double *> ()));
template <typename E>
using BiasShapeOp = decltype (E::biasShape (std::declval<Args<E>> (), 0.0, 0.0));
template <typename E> using BiasShapeSearchOp = decltype (E::biasShapeSearch ());
template <typename E> using FormSearchOp = decltype (E::formSearch ());

template <typename E>
constexpr bool
isSimulated ()
{
  return Has<E, SimParametersOp>::value;
}

template <typename E>
constexpr bool
hasTerm ()
{
  return Has<E, TermParametersOp>::value || Has<E, TermParameterNamesOp>::value;
}

template <typename E>
std::vector<effects::Field<SettingsOf<E>>>
settingFields ()
{
  if constexpr (Has<E, TermSettingsFieldsOp>::value)
    return E::termSettings ();
  else
    return {};
}

} // namespace detail

/** \brief The noise term of effect file \a Effect: its parameters and settings by name, its
  * closed forms, and the properties the model lab reads.
  */
template <typename Effect>
class EffectTermOf : public EffectTerm
{
public:
  using Settings = detail::SettingsOf<Effect>;

  /** \brief A term with parameter \a values (empty: the neutral ones) and \a settings.
    * \throws pcl::BadArgumentException for settings out of range or a wrong count of values.
    */
  explicit EffectTermOf (const std::vector<double> &values = {}, const Settings &settings = Settings ())
    : EffectTerm (Effect::kName, {}, {})
  {
    applySettings (settings);
    if (!values.empty ())
      setParameters (values);
  }

  double
  variance (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::VarianceOp>::value)
      return Effect::variance (values_.data (), settings_, ctx);
    else
      return 0.0;
  }

  double
  bias (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::BiasOp>::value)
      return Effect::bias (values_.data (), settings_, ctx);
    else
      return 0.0;
  }

  double
  varianceFactor (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::VarianceFactorOp>::value)
      return Effect::varianceFactor (values_.data (), settings_, ctx);
    else
      return 1.0;
  }

  bool
  scaledByFactors () const override
  {
    if constexpr (detail::Has<Effect, detail::ScaledOp>::value)
      return Effect::kScaledByFactors;
    else
      return true;
  }

  double
  columnVariance (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::ColumnVarianceOp>::value)
      return Effect::columnVariance (values_.data (), settings_, ctx);
    else
      return 0.0;
  }

  double
  rowVariance (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::RowVarianceOp>::value)
      return Effect::rowVariance (values_.data (), settings_, ctx);
    else
      return 0.0;
  }

  double
  rowCorrelationPx (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::RowCorrelationOp>::value)
      return Effect::rowCorrelationPx (values_.data (), settings_, ctx);
    else
      return std::numeric_limits<double>::infinity ();
  }

  double
  frameVariance (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::FrameVarianceOp>::value)
      return Effect::frameVariance (values_.data (), settings_, ctx);
    else
      return 0.0;
  }

  double
  columnCorrelationPx (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::ColumnCorrelationOp>::value)
      return Effect::columnCorrelationPx (values_.data (), settings_, ctx);
    else
      return std::numeric_limits<double>::infinity ();
  }

  double
  windowShare (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::WindowShareOp>::value)
      return Effect::windowShare (values_.data (), settings_, ctx);
    else
      return 0.0;
  }

  double
  windowPx (const PixelContext &ctx) const override
  {
    if constexpr (detail::Has<Effect, detail::WindowPxOp>::value)
      return Effect::windowPx (values_.data (), settings_, ctx);
    else
      return 1.0;
  }

  void
  transformMoments (const PixelContext &ctx, double &bias_mm, double &variance_mm2) const override
  {
    if constexpr (detail::Has<Effect, detail::TransformOp>::value)
      Effect::transformMoments (values_.data (), settings_, ctx, bias_mm, variance_mm2);
  }

  NoiseTerm::Ptr
  clone () const override { return std::make_shared<EffectTermOf> (*this); }

  std::vector<std::pair<std::string, double>>
  settings () const override
  {
    std::vector<std::pair<std::string, double>> out;
    for (const auto &f : detail::settingFields<Effect> ())
      out.emplace_back (f.name, f.get (settings_));
    return out;
  }

  void
  setSetting (const std::string &name, double value) override
  {
    for (const auto &f : detail::settingFields<Effect> ())
      if (name == f.name)
      {
        if (!inRange (f.range, value))
        {
          std::ostringstream msg;
          msg << "noise term '" << name_ << "': setting " << name << " must be " << toString (f.range) << " (got "
              << value << ")";
          detail::throwBadArgument (msg.str ());
        }
        Settings s = settings_;
        f.set (s, value);
        applySettings (s);
        return;
      }
    NoiseTerm::setSetting (name, value);
  }

  double
  typicalScale (std::size_t k) const override
  {
    const effects::TermParameter *p = declaredParameter (k);
    return p ? p->typical : 1.0;
  }

  double
  lowestValue (std::size_t k) const override
  {
    const effects::TermParameter *p = declaredParameter (k);
    return p ? p->lowest : NoiseTerm::lowestValue (k);
  }

  bool
  fittedToMeans (std::size_t k) const override
  {
    const effects::TermParameter *p = declaredParameter (k);
    return p && p->fitted_to_means;
  }

  bool
  frameDependent () const override
  {
    if constexpr (detail::Has<Effect, detail::FrameDependentOp>::value)
      return Effect::kFrameDependent;
    else
      return false;
  }

  bool
  quantises () const override { return detail::Has<Effect, detail::RoundingOp>::value; }

  /** \brief Whether the effect's term can move the mean depth: a bias, a linear bias map, a
    * transform of the moments or a rounding (NoiseTerm::movesMean ()).
    */
  static constexpr bool kMovesMean = detail::Has<Effect, detail::BiasOp>::value ||
                                     detail::Has<Effect, detail::BiasBasisOp>::value ||
                                     detail::Has<Effect, detail::TransformOp>::value ||
                                     detail::Has<Effect, detail::RoundingOp>::value;

  bool
  movesMean () const override { return kMovesMean; }

  /** \brief Whether the effect's term can change a pixel's depth SD: a variance, a factor, a
    * line's variance, a transform of the moments or a rounding (NoiseTerm::changesDepthSd ()).
    */
  static constexpr bool kChangesDepthSd = detail::Has<Effect, detail::VarianceOp>::value ||
                                          detail::Has<Effect, detail::VarianceFactorOp>::value ||
                                          detail::Has<Effect, detail::ColumnVarianceOp>::value ||
                                          detail::Has<Effect, detail::RowVarianceOp>::value ||
                                          detail::Has<Effect, detail::TransformOp>::value ||
                                          detail::Has<Effect, detail::RoundingOp>::value;

  bool
  changesDepthSd () const override { return kChangesDepthSd; }

  void
  roundingMoments (double d0_px, double sigma_px, double &mean_offset_px, double &variance_px2) const override
  {
    if constexpr (detail::Has<Effect, detail::RoundingOp>::value)
      Effect::roundingMoments (values_.data (), settings_, d0_px, sigma_px, mean_offset_px, variance_px2);
    else
      NoiseTerm::roundingMoments (d0_px, sigma_px, mean_offset_px, variance_px2);
  }

  int
  linearBiasSupport () const override
  {
    if constexpr (detail::Has<Effect, detail::BiasBasisOp>::value)
      return Effect::kBiasSupport;
    else
      return 0;
  }

  void
  linearBiasBasis (double u, double v, int *index, double *weight) const override
  {
    if constexpr (detail::Has<Effect, detail::BiasBasisOp>::value)
      Effect::biasBasis (settings_, u, v, index, weight);
  }

  double
  linearBiasShape (double depth_mm, double fb_px_m) const override
  {
    if constexpr (detail::Has<Effect, detail::BiasShapeOp>::value)
      return Effect::biasShape (settings_, depth_mm, fb_px_m);
    else
      return 1.0;
  }

  std::vector<std::pair<std::string, std::vector<double>>>
  linearBiasShapeSearch () const override
  {
    if constexpr (detail::Has<Effect, detail::BiasShapeSearchOp>::value)
      return Effect::biasShapeSearch ();
    else
      return {};
  }

  std::vector<std::pair<std::string, std::vector<double>>>
  formSearch () const override
  {
    if constexpr (detail::Has<Effect, detail::FormSearchOp>::value)
      return Effect::formSearch ();
    else
      return {};
  }

  void
  setLabStart (const effects::LabStart &facts) override
  {
    std::vector<double> start = values_;
    if constexpr (detail::Has<Effect, detail::TermParametersOp>::value)
    {
      start.clear ();
      for (const auto &p : Effect::termParameters ())
        start.push_back (p.start);
    }
    Settings s = settings_;
    if constexpr (detail::Has<Effect, detail::LabStartOp>::value)
      Effect::labStart (facts, start.data (), s);
    applySettings (s);
    if constexpr (detail::Has<Effect, detail::TermParametersOp>::value)
      values_ = start;
  }

  std::string
  physics () const override { return Effect::kText.physics; }

  std::string
  signature () const override { return Effect::kText.signature; }

  /** \brief The settings as the effect's struct. */
  const Settings &
  termSettings () const { return settings_; }

private:
  /** The effect's declaration of its k-th parameter; null where it declares none (a grid's
    * nodes are named by its settings). Built once: the lab's fit asks per evaluation. */
  static const effects::TermParameter *
  declaredParameter (std::size_t k)
  {
    if constexpr (detail::Has<Effect, detail::TermParametersOp>::value)
    {
      static const std::vector<effects::TermParameter> specs = Effect::termParameters ();
      if (k < specs.size ())
        return &specs[k];
    }
    return nullptr;
  }

  /** Checks \a s and makes it the term's; an effect whose parameters depend on its settings
    * (a grid's nodes) gets new names and neutral values.
    */
  void
  applySettings (const Settings &s)
  {
    for (const auto &f : detail::settingFields<Effect> ())
      if (!inRange (f.range, f.get (s)))
      {
        std::ostringstream msg;
        msg << "noise term '" << name_ << "': setting " << f.name << " must be " << toString (f.range) << " (got "
            << f.get (s) << ")";
        detail::throwBadArgument (msg.str ());
      }
    if constexpr (detail::Has<Effect, detail::SettingsProblemOp>::value)
    {
      const std::string problem = Effect::settingsProblem (s);
      if (!problem.empty ())
        detail::throwBadArgument ("noise term '" + name_ + "': " + problem);
    }
    const bool first = names_.empty ();
    settings_ = s;
    if constexpr (detail::Has<Effect, detail::TermParameterNamesOp>::value)
    {
      names_ = Effect::termParameterNames (settings_);
      values_.assign (names_.size (), 0.0);
    }
    else if (first)
    {
      for (const auto &p : Effect::termParameters ())
      {
        names_.push_back (p.name);
        values_.push_back (p.neutral);
      }
    }
  }

  Settings settings_;
};

/** \brief The simulator's hooks of effect file \a Effect at parameter values \a p. */
template <typename Effect>
class GenerativeEffectOf : public GenerativeEffect
{
public:
  using Parameters = typename Effect::SimParameters;

  explicit GenerativeEffectOf (const Parameters &p) : p_ (p) {}

  bool
  needsForeignLoad () const override
  {
    if constexpr (detail::Has<Effect, detail::ForeignLoadOp>::value)
      return Effect::kNeedsForeignLoad;
    else
      return false;
  }

  bool
  readable (const effects::SimPixel &px) const override
  {
    if constexpr (detail::Has<Effect, detail::ReadableOp>::value)
      return Effect::readable (p_, px);
    else
      return true;
  }

  double
  disparityVariance (const effects::SimPixel &px) const override
  {
    if constexpr (detail::Has<Effect, detail::DisparityVarianceOp>::value)
      return Effect::disparityVariance (p_, px);
    else
      return 0.0;
  }

  double
  sdFactor (const effects::SimPixel &px) const override
  {
    if constexpr (detail::Has<Effect, detail::SdFactorOp>::value)
      return Effect::sdFactor (p_, px);
    else
      return 1.0;
  }

  bool
  hasDropout () const override { return detail::Has<Effect, detail::DropoutOp>::value; }

  double
  dropout (const effects::SimPixel &px) const override
  {
    if constexpr (detail::Has<Effect, detail::DropoutOp>::value)
      return Effect::dropout (p_, px);
    else
      return 0.0;
  }

  double
  disparityOffset (const effects::SimSensor &sensor, const effects::SimPixel &px) const override
  {
    if constexpr (detail::Has<Effect, detail::DisparityOffsetOp>::value)
      return Effect::disparityOffset (p_, sensor, px);
    else
      return 0.0;
  }

  double
  frameOffset (std::uint32_t frame) const override
  {
    if constexpr (detail::Has<Effect, detail::FrameOffsetOp>::value)
      return Effect::frameOffset (p_, frame);
    else
      return 0.0;
  }

  bool
  hasColumnOffsets () const override { return detail::Has<Effect, detail::ColumnOffsetsOp>::value; }

  void
  addColumnOffsets (const effects::SimSensor &sensor, std::uint32_t frame, float *columns) const override
  {
    if constexpr (detail::Has<Effect, detail::ColumnOffsetsOp>::value)
      Effect::addColumnOffsets (p_, sensor, frame, columns);
  }

  void
  frameSettings (kernels::SensorFrameSettings &settings) const override
  {
    if constexpr (detail::Has<Effect, detail::FrameSettingsOp>::value)
      Effect::frameSettings (p_, settings);
  }

  void
  labelCamera (bool enabled, effects::CameraLabel &label) const override
  {
    if constexpr (detail::Has<Effect, detail::LabelCameraOp>::value)
      Effect::labelCamera (p_, enabled, label);
  }

  const Parameters &
  parameters () const { return p_; }

private:
  Parameters p_;
};

template <typename Effect>
EffectRegistry &
EffectRegistry::add ()
{
  Entry e;
  e.info.name = Effect::kName;
  e.info.summary = Effect::kText.summary;
  e.info.physics = Effect::kText.physics;
  e.info.signature = Effect::kText.signature;
  if constexpr (detail::isSimulated<Effect> ())
  {
    const typename Effect::SimParameters defaults{};
    for (const auto &f : Effect::simParameters ())
      e.info.parameters.push_back ({f.name, f.unit, f.description, f.range, f.get (defaults)});
    e.info.simulated = true;
    e.generative = [] (const std::vector<double> &values) -> GenerativeEffect::ConstPtr {
      return std::make_shared<const GenerativeEffectOf<Effect>> (effects::withFieldValues (Effect::simParameters (), values));
    };
  }
  if constexpr (detail::hasTerm<Effect> ())
  {
    e.info.has_term = true;
    e.info.quantises = detail::Has<Effect, detail::RoundingOp>::value;
    e.info.moves_mean = EffectTermOf<Effect>::kMovesMean;
    e.term = [] () -> NoiseTerm::Ptr { return std::make_shared<EffectTermOf<Effect>> (); };
  }
  if constexpr (detail::Has<Effect, detail::LabNeedsOp>::value)
    e.info.lab_needs = Effect::kLabNeeds;
  addEntry (std::move (e));
  return *this;
}

} // namespace texlet
} // namespace pcl
