/*
 * pcl_texlet: the physical effects as terms of the NoiseModel.
 *
 * Each term is named after its effect, has fittable parameters (the model lab refits them) and
 * fixed settings (image size of a grid, a reference radius). Its closed forms are those of the
 * effect's file (noise/effects/<name>.h), made into a term by EffectTermOf (noise/effect_adapter.h).
 * Terms read the covariates of PixelContext; where one is not known (a single frame in
 * TexletEstimation) they fall back to the steady, phase-averaged form.
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

/** \brief A term with named parameters stored as a plain vector, and the texts of its effect. */
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

/** \brief Names of the effects that can be terms of a NoiseModel, in the registry's order
  * (`intrinsics` is a camera-model effect, not a noise term).
  */
const std::vector<std::string> &
noiseEffectNames ();

/** \brief A new term for effect \a name (or `polynomial`) with neutral parameters (adds nothing
  * until fitted).
  * \throws pcl::BadArgumentException for an unknown name (the message lists the known ones).
  */
NoiseTerm::Ptr
makeNoiseTerm (const std::string &name);

} // namespace texlet
} // namespace pcl
