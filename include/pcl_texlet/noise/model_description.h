/*
 * pcl_texlet noise: a NoiseModel as plain names and numbers, the one description that every
 * serialiser writes (model.yaml through io/noise_model_io.h, the base model in a simulated
 * recording's meta.yaml, the terms in the lab's report.json).
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

/** \brief One term: its name, settings and parameters, each in the term's order. */
struct TermDescription
{
  std::string name;
  std::vector<std::pair<std::string, double>> settings;
  std::vector<std::pair<std::string, double>> parameters;
};

/** \brief A model: its sigma floor and its terms in order. */
struct ModelDescription
{
  double min_sigma_mm = 0.0;
  std::vector<TermDescription> terms;
};

/** \brief The description of \a model. */
ModelDescription
describeModel (const NoiseModel &model);

} // namespace texlet
} // namespace pcl
