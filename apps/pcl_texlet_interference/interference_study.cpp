#include "interference_study.h"

#include <pcl_texlet/camera/depth_image.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/io/open_recording.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/exceptions.h>

#include <filesystem>

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

std::vector<SensorRecording>
loadSensorRecordings (const std::vector<std::string> &folders, const std::vector<SensorExtrinsics> &extrinsics,
                      std::size_t frames)
{
  if (folders.empty ())
    throw pcl::IOException ("no recordings given");
  if (frames == 0)
    throw pcl::BadArgumentException ("loadSensorRecordings: frames must be at least 1");
  std::vector<SensorRecording> out;
  for (const auto &folder : folders)
  {
    SensorRecording rec;
    rec.name = fs::path (folder).lexically_normal ().filename ().string ();
    if (rec.name.empty () || rec.name == ".")
      rec.name = fs::absolute (folder).lexically_normal ().parent_path ().filename ().string ();
    for (const auto &other : out)
      if (other.name == rec.name)
        throw pcl::IOException ("recording '" + folder + "': a second recording named '" + rec.name +
                                "' (extrinsics are matched by the folder's name)");
    bool posed = false;
    for (const auto &e : extrinsics)
      if (e.name == rec.name)
      {
        rec.pose = e.pose;
        posed = true;
      }
    if (!posed)
      posed = poseFromMetaYaml ((fs::path (folder) / "meta.yaml").string (), rec.pose);
    if (!posed)
      throw pcl::IOException ("recording '" + folder + "': no pose: the extrinsics have no sensor named '" + rec.name +
                              "' and there is no meta.yaml with sensor_pose");
    const RecordingReader::Ptr reader = openRecording (folder);
    rec.camera = reader->cameraInfo ();
    DepthFrame frame;
    while (rec.frames.size () < frames && reader->next (frame))
      rec.frames.push_back (frame);
    if (rec.frames.empty ())
      throw pcl::IOException ("recording '" + folder + "': no frame");
    out.push_back (std::move (rec));
  }
  return out;
}

KnownObject
simulatedObject (const SimulatedSetup &setup)
{
  return boxOnPlate (setup.box_size_m, setup.plate_m);
}

std::vector<SensorRecording>
simulateInterferenceRecordings (const SimulatedSetup &setup, int projectors)
{
  if (projectors < 1 || projectors > 3)
    throw pcl::BadArgumentException ("simulateInterferenceRecordings: projectors must be 1, 2 or 3 (got " +
                                     std::to_string (projectors) + ")");
  if (setup.frames == 0)
    throw pcl::BadArgumentException ("simulateInterferenceRecordings: frames must be at least 1");
  const sim::SceneSetup scene =
      sim::boxSetup (setup.distance_m, setup.elevation_deg, 3, setup.box_size_m, setup.plate_m);
  sim::SimulationSettings settings;
  settings.effects.set<effects::Interference> (setup.interference);
  const sim::DepthSensor model = sim::DepthSensor::kinect (setup.width, setup.height);

  std::vector<SensorRecording> out;
  for (int s = 0; s < 3; ++s)
  {
    // The recording sensor first, then the P - 1 others whose projectors are on.
    std::vector<sim::DepthSensor> sensors;
    for (int k = 0; k < projectors; ++k)
    {
      sim::DepthSensor d = model;
      d.pose = scene.sensor_poses[(s + k) % 3];
      sensors.push_back (d);
    }
    // Same seed per sensor whatever the projector count: the runs differ by interference only.
    settings.seed = setup.seed * 1000003u + static_cast<std::uint32_t> (s);
    const sim::KinectSimulator simulator (scene.scene, sensors, settings, setup.threads);
    SensorRecording rec;
    rec.name = "sensor_" + std::to_string (s);
    rec.camera = simulator.cameraInfo (0);
    rec.pose = scene.sensor_poses[s];
    rec.frames = simulator.simulate (0, 0, static_cast<std::uint32_t> (setup.frames));
    out.push_back (std::move (rec));
  }
  return out;
}

TexletParameters
studyTexletParameters (int radius, int spacing)
{
  TexletParameters p;
  p.radius = radius;
  p.spacing = spacing;
  p.uncertainty = UncertaintyMethod::None;
  return p;
}

MergedTexlets
extractMergedTexlets (const std::vector<SensorRecording> &recordings, const TexletParameters &texlet_params,
                      unsigned threads)
{
  validate (texlet_params);
  MergedTexlets merged;
  for (std::size_t s = 0; s < recordings.size (); ++s)
  {
    const SensorRecording &rec = recordings[s];
    const auto camera = std::make_shared<PinholeModel> (PinholeModel::fromCameraInfo (rec.camera));
    for (const auto &frame : rec.frames)
    {
      auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
      depthToCloud (frame, *camera, *cloud);
      pcl::TexletEstimation<pcl::PointXYZ> est;
      est.setParameters (texlet_params);
      est.setCameraModel (camera);
      est.setNumberOfThreads (threads);
      est.setInputCloud (cloud);
      pcl::PointCloud<pcl::Texlet> texlets;
      est.compute (texlets);
      merged.add (texlets, rec.pose, static_cast<std::uint16_t> (s));
    }
  }
  return merged;
}

InterferenceCell
runInterferenceCell (const std::vector<SensorRecording> &recordings, int projectors, const TexletParameters &texlet_params,
                     const KnownObject &object, const RelationParameters &relation_params)
{
  InterferenceCell cell;
  cell.projectors = projectors;
  cell.radius = texlet_params.radius;
  const MergedTexlets merged = extractMergedTexlets (recordings, texlet_params, relation_params.threads);
  for (std::size_t s = 0; s < recordings.size (); ++s)
    cell.texlets_per_sensor.push_back (merged.countFrom (static_cast<std::uint16_t> (s)));
  std::vector<int> labels;
  if (!object.faces.empty ())
  {
    labels = labelTexlets (merged.texlets, object);
    cell.faces = faceQuality (merged.texlets, labels, object);
  }
  cell.statistics = accumulateRelations (merged.texlets, object, relation_params, labels);
  return cell;
}

} // namespace texlet
} // namespace pcl
