#include <pcl_texlet/simulation/simulation_meta.h>
#include <pcl_texlet/noise/model_description.h>
#include <pcl_texlet/common/shortest_decimal.h>

#include <pcl/exceptions.h>

#include <yaml-cpp/yaml.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace sim
{

namespace
{

/** Whether \a model is exactly the paper's polynomial (what "base_noise: paper" reads back as). */
bool
isPaperModel (const NoiseModel &model)
{
  const NoiseModel paper = NoiseModel::paper ();
  if (model.terms ().size () != 1 || model.minSigmaMm () != paper.minSigmaMm ())
    return false;
  const auto &t = model.terms ().front ();
  return t->name () == paper.terms ().front ()->name () && t->parameters () == paper.terms ().front ()->parameters ();
}

} // namespace

std::string
simulationMetaYaml (const SceneSetup &setup, const KinectSimulator &simulator, std::size_t sensor,
                    std::uint32_t first_frame, std::uint32_t frames)
{
  const DepthSensor &s = simulator.sensor (sensor);
  const SimulationSettings &settings = simulator.settings ();
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "generator" << YAML::Value << "pcl_texlet KinectSimulator";
  out << YAML::Key << "seed" << YAML::Value << settings.seed;
  out << YAML::Key << "first_frame" << YAML::Value << first_frame;
  out << YAML::Key << "frames" << YAML::Value << frames;
  out << YAML::Key << "scene" << YAML::Value << setup.kind;
  out << YAML::Key << "scene_parameters" << YAML::Value << YAML::BeginMap;
  for (const auto &p : setup.parameters)
    out << YAML::Key << p.first << YAML::Value << shortestDecimal (p.second);
  out << YAML::EndMap;
  if (setup.box_size_m.allFinite ())
    out << YAML::Key << "box_size_m" << YAML::Value << YAML::Flow << YAML::BeginSeq
        << shortestDecimal (setup.box_size_m.x ()) << shortestDecimal (setup.box_size_m.y ())
        << shortestDecimal (setup.box_size_m.z ()) << YAML::EndSeq;
  if (!setup.mesh_path.empty ())
    out << YAML::Key << "mesh" << YAML::Value << setup.mesh_path;
  out << YAML::Key << "projectors" << YAML::Value << simulator.activeProjectors ();
  out << YAML::Key << "sensors" << YAML::Value << simulator.sensorCount ();
  out << YAML::Key << "sensor" << YAML::Value << sensor;
  out << YAML::Key << "sensor_pose" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      out << shortestDecimal (s.pose.matrix () (r, c) + 0.0); // + 0.0: no "-0"
  out << YAML::EndSeq;
  out << YAML::Key << "render_camera" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "fx" << YAML::Value << shortestDecimal (s.fx);
  out << YAML::Key << "fy" << YAML::Value << shortestDecimal (s.fy);
  out << YAML::Key << "cx" << YAML::Value << shortestDecimal (s.cx);
  out << YAML::Key << "cy" << YAML::Value << shortestDecimal (s.cy);
  out << YAML::EndMap;
  out << YAML::Key << "depth_range_m" << YAML::Value << YAML::Flow << YAML::BeginSeq << shortestDecimal (s.min_depth_m)
      << shortestDecimal (s.max_depth_m) << YAML::EndSeq;

  if (!settings.base_noise)
    out << YAML::Key << "base_noise" << YAML::Value << "none";
  else if (isPaperModel (settings.noise_model))
    out << YAML::Key << "base_noise" << YAML::Value << "paper";
  else
  {
    out << YAML::Key << "base_noise" << YAML::Value << "custom";
    // The terms' parameters (meta.yaml records what the noise was; model.yaml is the file to
    // read a model back from).
    out << YAML::Key << "base_noise_terms" << YAML::Value << YAML::BeginMap;
    for (const auto &t : describeModel (settings.noise_model).terms)
    {
      out << YAML::Key << t.name << YAML::Value << YAML::Flow << YAML::BeginMap;
      for (const auto &p : t.parameters)
        out << YAML::Key << p.first << YAML::Value << shortestDecimal (p.second);
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  out << YAML::Key << "projector_shadows" << YAML::Value << settings.projector_shadows;

  out << YAML::Key << "effects" << YAML::Value << YAML::BeginMap;
  for (const std::string &name : enabledEffects (settings.effects))
  {
    out << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap;
    for (const auto &p : effectInfo (name).parameters)
      out << YAML::Key << p.name << YAML::Value << shortestDecimal (effectParameter (settings.effects, name, p.name));
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  out << YAML::EndMap;
  if (!out.good ())
    throw pcl::BadArgumentException ("meta.yaml: cannot format as YAML: " + out.GetLastError ());
  return std::string (out.c_str ()) + "\n";
}

} // namespace sim
} // namespace texlet
} // namespace pcl
