/*
 * pcl_texlet multi-sensor: the paper's interference study (Sect. 4, Fig. 11 and 13).
 *
 * Several sensors watch one scene; each sensor's depth frames become texlets (in its camera
 * frame), the extrinsics move them into one reference frame, and the relations of all texlet
 * pairs are scored against the known object. Repeated per neighbourhood radius and per number
 * of active projectors, this gives the quality histograms and the inlier-vs-radius curves.
 *
 * Recordings come from recording folders (one per sensor, any kind openRecording reads) with
 * an extrinsics YAML or the simulator's meta.yaml poses, or from the simulated setup:
 * three sensors in the paper's triangle around the box on a plate; with P active projectors
 * every sensor records while P - 1 others project too (sensor s with s + 1, ..., s + P - 1
 * mod 3), as the paper turned the Kinects on one, two and three at a time.
 */
#pragma once

#include <pcl_texlet/noise/effects/interference.h>
#include <pcl_texlet/relations/extrinsics.h>
#include <pcl_texlet/relations/known_object.h>
#include <pcl_texlet/relations/texlet_merge.h>
#include <pcl_texlet/relations/texlet_relations.h>
#include <pcl_texlet/camera/camera_info.h>
#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/features/texlet_parameters.h>

#include <functional>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief One sensor's frames, intrinsics and pose in the reference frame. */
struct SensorRecording
{
  std::string name;
  CameraInfo camera;
  std::vector<DepthFrame> frames;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity (); ///< reference from camera
};

/** \brief Reads the first \a frames frames of each recording (openRecording: recording folders,
  * PCD folders, grabber TIFFs, .oni). The pose of each comes from \a extrinsics, matched by the
  * folder's name (its last path component); with no entry there, from the recording's
  * meta.yaml sensor_pose.
  * \throws pcl::IOException naming the recording: unreadable, no frame, or no pose anywhere.
  */
std::vector<SensorRecording>
loadSensorRecordings (const std::vector<std::string> &folders, const std::vector<SensorExtrinsics> &extrinsics,
                      std::size_t frames = 1);

/** \brief The simulated setup of the paper's experiment. */
struct SimulatedSetup
{
  int width = 640;
  int height = 480;
  double distance_m = 1.0;    ///< sensors to the box centre
  double elevation_deg = 45.0;
  double plate_m = 0.35;      ///< the base plate's side (see paperBoxObject)
  Eigen::Vector3d box_size_m = Eigen::Vector3d (0.128, 0.112, 0.240);
  /** \brief The interference effect's parameters (docs/sensor_model.md); it is on and the rest
    * of the simulator's effects stay off, so that interference is what changes with the
    * projector count.
    */
  effects::Interference::SimParameters interference;
  std::uint32_t seed = 0;
  std::size_t frames = 1;
  unsigned threads = 0;
};

/** \brief Simulated recordings of the three sensors with \a projectors (1 to 3) active
  * projectors each (see the file comment), poses in the box's frame.
  * \throws pcl::BadArgumentException for projectors outside 1-3 or a bad setup.
  */
std::vector<SensorRecording>
simulateInterferenceRecordings (const SimulatedSetup &setup, int projectors);

/** \brief The known object of a simulated setup: boxOnPlate of its box and plate. */
KnownObject
simulatedObject (const SimulatedSetup &setup);

/** \brief One (projectors, radius) cell of the study. */
struct InterferenceCell
{
  int projectors = 1;
  int radius = 6;
  std::vector<std::size_t> texlets_per_sensor;
  RelationStatistics statistics;
  std::vector<FaceQuality> faces; ///< empty when the object has no faces
};

/** \brief Texlets of every frame of every recording (extracted with \a texlet_params and
  * the recording's pinhole camera), merged into the reference frame.
  */
MergedTexlets
extractMergedTexlets (const std::vector<SensorRecording> &recordings, const TexletParameters &texlet_params,
                      unsigned threads = 0);

/** \brief One cell: texlets at \a texlet_params.radius, merged, labelled when the object has
  * faces, and their relations accumulated.
  */
InterferenceCell
runInterferenceCell (const std::vector<SensorRecording> &recordings, int projectors, const TexletParameters &texlet_params,
                     const KnownObject &object, const RelationParameters &relation_params = RelationParameters ());

/** \brief Texlet settings of the study: the paper's (20 RANSAC iterations, PCA), no
  * uncertainty (the relations use P and N only), \a radius and \a spacing.
  */
TexletParameters
studyTexletParameters (int radius, int spacing = 4);

} // namespace texlet
} // namespace pcl
