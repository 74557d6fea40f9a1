/*
 * pcl_texlet model lab (internal): the parametric bootstrap of the significance test. Data in the
 * shape of a half drawn from the current model, on which a candidate's gain shows what the same
 * fit brings where no effect is missing.
 */
#pragma once

#include "lab_data.h"

#include <pcl_texlet/noise/noise_model.h>

#include <memory>
#include <random>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** Data drawn from \a model in the shape of \a d (parametric bootstrap): no effect beyond it. */
std::unique_ptr<ModelLab::Data>
synthesise (const ModelLab::Data &d, const NoiseModel &model,
            const std::vector<RecordingMeasurement::ConstPtr> &recs, std::mt19937_64 &rng);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
