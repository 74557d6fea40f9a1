/*
 * pcl_texlet simulator: what the simulator adds to the geometry, and its seed.
 */
#pragma once

#include <pcl_texlet/noise/noise_model.h>
#include <pcl_texlet/simulation/effects.h>

#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief Noise, effects and randomness of a simulation. */
struct SimulationSettings
{
  /** \brief Whether the base noise is added: noise_model's depth SD (mm) converted to a
    * disparity SD, sigma_d = sigma_z f b / z^2. Off: no noise but the effects' own.
    */
  bool base_noise = true;

  /** \brief The base noise; by default the paper's polynomial f(r, d) (Eq. 4), fitted for
    * 0.7-1.75 m and extrapolated beyond.
    */
  NoiseModel noise_model = NoiseModel::paper ();

  /** \brief The switchable physical effects (all off by default). */
  SensorEffects effects;

  /** \brief Pixels the sensor's own projector cannot light (behind an occluder, or on a
    * surface facing away from it) have no reading: the shadows beside objects that every
    * structured-light sensor shows. Geometry rather than an effect, so on by default.
    */
  bool projector_shadows = true;

  /** \brief Seed of every random draw; the same seed gives the same frames, byte for byte,
    * whatever the number of threads.
    */
  std::uint32_t seed = 0;
};

} // namespace sim
} // namespace texlet
} // namespace pcl
