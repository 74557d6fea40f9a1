/*
 * pcl_texlet noise: the effect registry, every physical effect of the sensor model by name.
 *
 * Each effect is defined once, in its file noise/effects/<name>.h; the registry holds one entry
 * per effect, in the order of the vocabulary (src/noise/effect_registry.cpp, one line each).
 * From an entry come the catalogue (names, texts, the simulator's parameters with units,
 * defaults and ranges: what the YAML files, the apps' --list-effects and --set and the lab
 * read), the effect's noise term (makeNoiseTerm) and the simulator's generative hooks.
 */
#pragma once

#include <pcl_texlet/noise/effect.h>
#include <pcl_texlet/noise/noise_model.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief One parameter of an effect in the simulator. */
struct EffectParameterInfo
{
  std::string name;        ///< e.g. "offset_px"
  std::string unit;        ///< e.g. "px", "m", "deg", "frames", "1" (dimensionless)
  std::string description; ///< one line
  ParameterRange range = ParameterRange::Any;
  double default_value = 0.0;
};

/** \brief One effect: its name, texts, simulator parameters and what the model lab needs. */
struct EffectInfo
{
  std::string name;
  std::string summary;   ///< one line, with the simulator's law
  std::string physics;   ///< one line: why the sensor shows it
  std::string signature; ///< the covariate where it shows
  std::vector<EffectParameterInfo> parameters; ///< the simulator's
  bool simulated = false; ///< the simulator can draw it
  bool has_term = false;  ///< the noise model has a term for it
  bool quantises = false; ///< its term rounds the disparity (NoiseTerm::quantises)
  /** \brief Its term moves the mean: a bias (), a linear bias map or a rounding. A term of
    * variance only moves the bias through the surface fit's weights alone. */
  bool moves_mean = false;
  unsigned lab_needs = effects::kNeedsNothing; ///< effects::LabNeeds flags
};

/** \brief The simulator's hooks of one effect at given parameter values (the effect's
  * generative form; neutral where the effect has no hook: factor 1, offsets and variances 0).
  */
class GenerativeEffect
{
public:
  using ConstPtr = std::shared_ptr<const GenerativeEffect>;

  virtual ~GenerativeEffect () = default;

  /** \brief Whether the simulator must compute SimPixel::foreign_load for this effect. */
  virtual bool
  needsForeignLoad () const = 0;

  /** \brief False where the effect leaves the pixel without a reading (static). */
  virtual bool
  readable (const effects::SimPixel &px) const = 0;

  /** \brief Disparity variance added to the base noise's, px^2 (first phase of the SD). */
  virtual double
  disparityVariance (const effects::SimPixel &px) const = 0;

  /** \brief Factor on the disparity SD (second phase, in registry order). */
  virtual double
  sdFactor (const effects::SimPixel &px) const = 0;

  /** \brief Whether the effect makes holes (dropout ()). */
  virtual bool
  hasDropout () const = 0;

  /** \brief Probability per frame that the pixel has no reading. */
  virtual double
  dropout (const effects::SimPixel &px) const = 0;

  /** \brief Static disparity offset of the pixel, px. */
  virtual double
  disparityOffset (const effects::SimSensor &sensor, const effects::SimPixel &px) const = 0;

  /** \brief Disparity offset of the whole frame \a frame, px. */
  virtual double
  frameOffset (std::uint32_t frame) const = 0;

  /** \brief Whether the effect offsets columns (addColumnOffsets ()). */
  virtual bool
  hasColumnOffsets () const = 0;

  /** \brief Adds the disparity offset of each column of frame \a frame to \a columns. */
  virtual void
  addColumnOffsets (const effects::SimSensor &sensor, std::uint32_t frame, float *columns) const = 0;

  /** \brief Sets what the per-pixel kernel needs of the effect for a frame (quantisation step,
    * edge jitter, hole block size).
    */
  virtual void
  frameSettings (kernels::SensorFrameSettings &settings) const = 0;

  /** \brief What camera.yaml says of the sensor; called for every effect, \a enabled or not. */
  virtual void
  labelCamera (bool enabled, effects::CameraLabel &label) const = 0;
};

/** \brief The effects, in order, each defined by its effect file. */
class EffectRegistry
{
public:
  /** \brief The project's vocabulary of effects (docs/sensor_model.md), in its order. */
  static const EffectRegistry &
  vocabulary ();

  /** \brief Registers the effect of effect file \a Effect (noise/effect_adapter.h defines it).
    * \throws pcl::BadArgumentException if an effect of that name is registered already.
    */
  template <typename Effect>
  EffectRegistry &
  add ();

  std::size_t
  size () const { return entries_.size (); }

  const EffectInfo &
  info (std::size_t index) const { return entries_.at (index).info; }

  /** \brief Index of effect \a name, or -1. */
  int
  find (const std::string &name) const;

  /** \brief Index of effect \a name. \throws pcl::BadArgumentException for an unknown name
    * (the message lists the known ones).
    */
  std::size_t
  index (const std::string &name) const;

  /** \brief Names of all effects, ", "-separated (for messages). */
  std::string
  knownNames () const;

  /** \brief A new term of effect \a index with neutral parameters; null for an effect without
    * a term.
    */
  NoiseTerm::Ptr
  makeTerm (std::size_t index) const;

  /** \brief The simulator's hooks of effect \a index with parameter \a values (in the order of
    * info ().parameters); null for an effect the simulator cannot draw.
    */
  GenerativeEffect::ConstPtr
  generative (std::size_t index, const std::vector<double> &values) const;

private:
  struct Entry
  {
    EffectInfo info;
    std::function<NoiseTerm::Ptr ()> term;
    std::function<GenerativeEffect::ConstPtr (const std::vector<double> &)> generative;
  };

  void
  addEntry (Entry entry);

  std::vector<Entry> entries_;
};

/** \brief All effects of the vocabulary, in order. */
const std::vector<EffectInfo> &
effectCatalogue ();

/** \brief The entry of effect \a name. \throws pcl::BadArgumentException for an unknown name
  *        (the message lists the known ones).
  */
const EffectInfo &
effectInfo (const std::string &name);

} // namespace texlet
} // namespace pcl
