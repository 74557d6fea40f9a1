/*
 * pcl_texlet simulator: depth frames of Kinect-class structured-light sensors looking at a
 * static scene, with the paper's noise and any of the physical effects of the effect registry
 * (noise/effect_registry.h).
 *
 * Per pixel: the true depth z along the optical axis comes from ray casting; the sensor
 * measures disparity d = f b / z, to which the effects' static offsets (depth_distortion),
 * frame and column offsets (temporal_drift, vertical_stripes) and Gaussian noise are added; the
 * noise SD is the base noise (the noise model, converted from depth to disparity) with the
 * effects' variances added (axial_quadratic), times their SD factors in registry order
 * (radial, incidence_angle, interference). The disparity is then quantised
 * (disparity_quantization) and reported as depth f b / d rounded to whole millimetres, 0 where
 * there is no reading (no surface, projector shadow, an effect's unreadable pixel or hole, or
 * outside the depth range).
 *
 * Geometry is computed once per sensor; a frame is a pure function of (seed, sensor, frame),
 * drawn from Philox counters, so frames can be made in any order on any number of threads and
 * come out the same.
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>
#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/simulation/depth_sensor.h>
#include <pcl_texlet/simulation/scene.h>
#include <pcl_texlet/simulation/simulation_settings.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace sim
{

/** \brief What a sensor sees, noise-free, per pixel (row-major, width * height). */
struct SensorTruth
{
  int width = 0;
  int height = 0;
  std::vector<float> depth_m;         ///< true depth along the optical axis, metres; 0 = no surface
  std::vector<Eigen::Vector3f> normal; ///< unit surface normal in the camera frame, facing the camera
  std::vector<float> cos_incidence;   ///< cosine of the angle between normal and viewing ray
  std::vector<std::uint8_t> lit;      ///< 1 where the sensor's own projector lights the surface
  std::vector<float> foreign_load;    ///< other active projectors' relative irradiance (interference)
  std::vector<double> disparity_px;   ///< disparity before noise (static offsets included); 0 = no reading
  std::vector<float> sigma_px;        ///< disparity noise SD, pixels
  std::vector<float> dropout;         ///< probability of an interference hole per frame
};

/** \brief The simulator. */
class KinectSimulator
{
public:
  using Ptr = std::shared_ptr<KinectSimulator>;
  using ConstPtr = std::shared_ptr<const KinectSimulator>;

  /** \brief Casts every sensor's rays into \a scene and prepares the static maps.
    * \param threads OpenMP threads for this and every later call (0: OpenMP's default)
    * \throws pcl::BadArgumentException for a null scene, no sensor, an invalid sensor or an
    *         effect parameter out of range.
    */
  KinectSimulator (const Scene::ConstPtr &scene, const std::vector<DepthSensor> &sensors,
                   const SimulationSettings &settings, unsigned threads = 0);

  /** \brief Threads for the following calls (0: OpenMP's default). Results do not depend on it. */
  void
  setNumberOfThreads (unsigned threads) { threads_ = threads; }

  /** \brief Threads the calls use: the number set, or OpenMP's default for 0. */
  int
  numberOfThreads () const;

  /** \brief Number of sensors in the setup (recorded or not). */
  std::size_t
  sensorCount () const { return sensors_.size (); }

  /** \throws pcl::BadArgumentException for an index out of range (as do all per-sensor calls). */
  const DepthSensor &
  sensor (std::size_t index) const;

  /** \brief Noise, effects and seed the frames are made with. */
  const SimulationSettings &
  settings () const { return settings_; }

  /** \brief The scene the sensors look at. */
  const Scene &
  scene () const { return *scene_; }

  /** \brief Number of sensors whose projector is on (the recording's `projectors`). */
  int
  activeProjectors () const;

  /** \brief Noise-free geometry and the static noise maps of sensor \a index. */
  const SensorTruth &
  truth (std::size_t index) const;

  /** \brief The intrinsics the recording is labelled with (camera.yaml): the sensor's, or the
    * intrinsics effect's wrong ones; baseline and disparity step of the sensor.
    */
  CameraInfo
  cameraInfo (std::size_t index) const;

  /** \brief Frame number \a frame (named %06u) of sensor \a index. */
  DepthFrame
  simulateFrame (std::size_t index, std::uint32_t frame) const;

  /** \brief Frames first .. first + count - 1 of sensor \a index, made in parallel. */
  std::vector<DepthFrame>
  simulate (std::size_t index, std::uint32_t first, std::uint32_t count) const;

  /** \brief Like simulateFrame, for callers that parallelise over frames themselves: runs on
    * the calling thread only and reuses \a frame's buffers.
    */
  void
  simulateFrameSerial (std::size_t index, std::uint32_t frame, DepthFrame &out) const;

private:
  void
  prepare (std::size_t index);

  void
  renderRows (std::size_t index, std::uint32_t frame, DepthFrame &out, bool parallel) const;

  /** The sensor as the effects' hooks see it. */
  effects::SimSensor
  simSensor (std::size_t index) const;

  Scene::ConstPtr scene_;
  std::vector<DepthSensor> sensors_;
  SimulationSettings settings_;
  GenerativeEffects effects_; // the settings' effects, ready to draw
  std::vector<SensorTruth> truth_;
  unsigned threads_;
};

} // namespace sim
} // namespace texlet
} // namespace pcl
