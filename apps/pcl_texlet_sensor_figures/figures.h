/*
 * pcl_texlet_sensor_figures: what every study shares. The simulated Kinect of the run's image
 * size, simulators of a scene with the run's seed, frames and threads, the paper's model beside
 * the measurements, and the output: data files in the output folder and summary.txt's numbers.
 */
#pragma once

#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/noise/noise_model.h>
#include <pcl_texlet/simulation/depth_sensor.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/simulation/simulation_settings.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace pcl_texlet_sensor_figures
{

/** \brief The command line. */
struct Options
{
  std::string output;
  int width = 640, height = 480;
  unsigned frames = 30;
  std::uint32_t seed = 0;
  unsigned threads = 0;
  std::vector<std::string> only;
  bool quiet = false;
};

/** \brief The run's sensor, simulators and output, shared by the studies (studies.h). */
class Figures
{
public:
  /** \brief Data files go to the folder \a out, which exists. */
  Figures (const Options &o, const std::filesystem::path &out);

  const Options &
  options () const { return o_; }

  /** \brief The simulated Kinect (Kinect v1 focal length scaled with the width). */
  const pcl::texlet::sim::DepthSensor &
  sensor () const { return model_; }

  /** \brief Its focal length times baseline, px m. */
  double
  fb () const { return fb_; }

  /** \brief Simulation settings with the run's seed and nothing switched on but the base noise. */
  pcl::texlet::sim::SimulationSettings
  settings () const;

  /** \brief A simulator of \a setup's sensors of the run's kind. */
  pcl::texlet::sim::KinectSimulator
  simulator (const pcl::texlet::sim::SceneSetup &setup, const pcl::texlet::sim::SimulationSettings &s) const;

  /** \brief A simulator of \a scene seen by the run's sensor at the origin. */
  pcl::texlet::sim::KinectSimulator
  simulator (const pcl::texlet::sim::Scene::ConstPtr &scene, const pcl::texlet::sim::SimulationSettings &s) const;

  /** \brief The run's number of frames of sensor 0. */
  std::vector<pcl::texlet::DepthFrame>
  frames (const pcl::texlet::sim::KinectSimulator &sim) const;

  /** \brief The pixels of the central window: within 5 % of the image width of the principal point. */
  bool
  central (int u, int v) const;

  /** \brief Distance of (u, v) from the principal point, px. */
  double
  radius (int u, int v) const;

  /** \brief The paper's depth SD (mm) at pixel (u, v) and depth \a depth_mm. */
  double
  paperSigma (int u, int v, double depth_mm) const;

  /** \brief Depth (mm) reported for true depth \a z_mm with a disparity offset of \a offset_px. */
  double
  offsetDepth (double z_mm, double offset_px) const;

  /** \brief The bin width of radial profiles, px. */
  double
  radialBin () const;

  /** \brief Records "figure.key = value" for summary.txt. */
  void
  note (const std::string &figure, const std::string &key, double value, int precision = 4);

  /** \brief Writes \a text to the data file \a file (through a temporary, renamed when complete).
    * \throws pcl::IOException when it cannot be written
    */
  void
  write (const std::string &file, const std::string &text) const;

  /** \brief summary.txt: the key numbers, "figure.key = value" lines. */
  void
  writeSummary () const;

private:
  const Options &o_;
  std::filesystem::path out_;
  pcl::texlet::sim::DepthSensor model_;
  double fb_ = 0;
  pcl::texlet::NoiseModel paper_ = pcl::texlet::NoiseModel::paper ();
  std::map<std::string, std::string> summary_;
};

} // namespace pcl_texlet_sensor_figures
