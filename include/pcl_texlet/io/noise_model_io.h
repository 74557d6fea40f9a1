/*
 * pcl_texlet: a NoiseModel as a YAML file (what the model lab writes as model.yaml and what
 * TexletEstimation users and pcl_texlet_extract --noise-model load).
 *
 *   min_sigma_mm: 0.1
 *   terms:
 *     - name: polynomial
 *       parameters: {p00: 2.344, p10: -0.01202, p01: -0.002734, p20: 1.818e-05, p11: 6.516e-06, p02: 1.233e-06}
 *     - name: incidence_angle
 *       parameters: {gain: 0.48}
 *     - name: depth_distortion
 *       settings: {image_width: 640, image_height: 480, nodes_x: 17, nodes_y: 13}
 *       parameters: {offset_0_0: 0.01, ...}
 *
 * Term names are those of the effect registry (noise/effect_registry.h) plus `polynomial` (the
 * paper's Eq. 4). A term lists every parameter; settings it does not list keep their defaults.
 */
#pragma once

#include <pcl_texlet/noise/noise_model.h>

#include <string>

namespace pcl
{
namespace texlet
{

/** \brief The model as YAML text (parameters written with 17 significant digits). */
std::string
noiseModelToYaml (const NoiseModel &model);

/** \brief The model of YAML text; \a source names it in error messages.
  * \throws pcl::IOException naming the source and the problem: not YAML, no terms, an unknown
  *         term, setting or parameter, a missing parameter, a value that is not a finite number.
  */
NoiseModel
parseNoiseModelYaml (const std::string &yaml, const std::string &source = "noise model");

/** \brief The model of YAML file \a path. \throws pcl::IOException (missing file, as above). */
NoiseModel
loadNoiseModelYaml (const std::string &path);

/** \brief Writes the model to \a path through a temporary file in the same folder, renamed when
  * complete. \throws pcl::IOException if it cannot be written.
  */
void
saveNoiseModelYaml (const std::string &path, const NoiseModel &model);

} // namespace texlet
} // namespace pcl
