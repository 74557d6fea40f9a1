/*
 * pcl_texlet_sim: simulated Kinect recordings (recording folders, docs/sensor_model.md section 2)
 * of a tilted wall, the paper's box on a table, or a mesh, with the paper's noise and any of the
 * physical effects of docs/sensor_model.md section 6.
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 * The output is written to a hidden temporary folder and renamed when complete, so a failed
 * run leaves no recording.
 */
#include "../common/app_main.h"
#include "../common/folder_guard.h"
#include <pcl_texlet/simulation/effects.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/simulation/simulated_recording.h>
#include <pcl_texlet/simulation/simulation_config.h>
#include <pcl_texlet/simulation/triangle_mesh.h>

#include <pcl/console/print.h>
#include <pcl/exceptions.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;
using namespace pcl::texlet::sim;

using pcl_texlet_app::InputError;

namespace
{

const char *const kName = "pcl_texlet_sim";

struct Options
{
  std::string output;
  std::string scene = "plane";
  double distance = std::nan ("");
  double tilt_x = 0, tilt_y = 0, elevation = 40;
  std::string mesh;
  double mesh_scale = 1.0;
  int projectors = 1;
  std::string record = "0";
  unsigned frames = 30;
  std::uint32_t seed = 0;
  std::vector<std::string> effects, assignments;
  std::vector<double> poses; ///< 16 numbers per --pose
  std::string config, base_noise;
  bool no_shadows = false;
  int width = 640, height = 480;
  double fx = std::nan (""), fy = std::nan (""), cx = std::nan (""), cy = std::nan ("");
  double baseline = 0.075;
  unsigned threads = 0;
  bool list_effects = false, quiet = false;
};

void
printEffects ()
{
  std::cout << "Effects (docs/sensor_model.md section 6); switch on with --effect NAME, set with "
               "--set NAME.PARAMETER=VALUE\n";
  for (const auto &e : effectCatalogue ())
  {
    std::cout << "\n  " << e.name << ": " << e.summary << "\n";
    for (const auto &p : e.parameters)
      std::cout << "    " << std::left << std::setw (22) << p.name << std::right << " default " << std::setw (7)
                << p.default_value << " " << std::left << std::setw (7) << p.unit << std::right << p.description
                << " (" << toString (p.range) << ")\n";
  }
}

/** Whether an option was given on the command line. */
bool
given (const CLI::App &app, const std::string &name)
{
  return app.count (name) > 0;
}

/** The scene and where its sensors stand. */
SceneSetup
makeSetup (const Options &o, const CLI::App &app)
{
  if (o.scene != "mesh" && given (app, "--mesh"))
    throw InputError ("--mesh needs --scene mesh");
  if (o.scene != "mesh" && given (app, "--mesh-scale"))
    throw InputError ("--mesh-scale needs --scene mesh");
  if (o.scene == "box" && (given (app, "--tilt-x") || given (app, "--tilt-y")))
    throw InputError ("--tilt-x and --tilt-y apply to --scene plane or mesh; the box scene has --elevation");
  if (o.scene != "box" && given (app, "--elevation"))
    throw InputError ("--elevation applies to --scene box");
  if (o.scene == "plane")
    return planeSetup (std::isnan (o.distance) ? 1.5 : o.distance, o.tilt_x, o.tilt_y, o.projectors);
  if (o.scene == "box")
    return boxSetup (std::isnan (o.distance) ? 1.2 : o.distance, o.elevation, o.projectors);
  if (o.mesh.empty ())
    throw InputError ("--scene mesh needs --mesh FILE (.ply, .obj, .stl, .vtk or an organised .pcd)");
  const TriangleMeshSurface mesh = loadTriangleMesh (o.mesh, o.mesh_scale);
  return meshSetup (mesh, std::isnan (o.distance) ? 1.5 : o.distance, o.tilt_x, o.tilt_y, o.projectors, 0.3,
                    fs::absolute (o.mesh).string ());
}

/** Sensors placed by --pose (16 numbers each, row-major, scene from camera) instead of the
  * scene's own placement.
  */
void
placeSensors (const Options &o, SceneSetup &setup)
{
  if (o.poses.empty ())
    return;
  setup.sensor_poses.clear ();
  // The scene's own spacing of sensors no longer describes where they stand.
  setup.parameters.erase (std::remove_if (setup.parameters.begin (), setup.parameters.end (),
                                          [] (const auto &p) { return p.first == "sensor_spacing_m"; }),
                          setup.parameters.end ());
  for (std::size_t k = 0; k + 16 <= o.poses.size (); k += 16)
  {
    Eigen::Matrix4d m;
    for (int i = 0; i < 16; ++i)
      m (i / 4, i % 4) = o.poses[k + i];
    setup.sensor_poses.emplace_back (m);
  }
}

SimulationSettings
makeSettings (const Options &o, const CLI::App &app)
{
  SimulationSettings s;
  s.seed = o.seed;
  if (!o.config.empty ())
    loadSimulationConfig (o.config, s);
  for (const auto &name : o.effects)
    setEffectEnabled (s.effects, name, true);
  for (const auto &a : o.assignments)
    applyEffectAssignment (a, s.effects);
  if (given (app, "--base-noise"))
    s.base_noise = o.base_noise == "paper";
  if (o.no_shadows)
    s.projector_shadows = false;
  return s;
}

DepthSensor
makeSensor (const Options &o)
{
  DepthSensor s = DepthSensor::kinect (o.width, o.height);
  if (!std::isnan (o.fx))
    s.fx = o.fx;
  if (!std::isnan (o.fy))
    s.fy = o.fy;
  else if (!std::isnan (o.fx))
    s.fy = o.fx; // square pixels unless told otherwise
  if (!std::isnan (o.cx))
    s.cx = o.cx;
  if (!std::isnan (o.cy))
    s.cy = o.cy;
  s.baseline_m = o.baseline;
  return s;
}

using pcl_texlet_app::OutputFolder;

int
run (int argc, char **argv)
{
  Options o;
  CLI::App app ("Simulate Kinect-class structured-light depth recordings: the paper's depth noise plus any of the\n"
                "physical effects of docs/sensor_model.md section 6 (see --list-effects).\n"
                "OUTPUT: a recording folder (camera.yaml, depth/000000.png ..., meta.yaml); with --record all and\n"
                "several sensors, a folder holding one recording per sensor (sensor_0, sensor_1, ...).",
                kName);
  app.add_option ("OUTPUT", o.output, "recording folder to create (must not exist)");
  app.add_option ("--scene", o.scene, "plane (a wall), box (the paper's 128x112x240 mm box on a table) or mesh")
      ->check (CLI::IsMember ({"plane", "box", "mesh"}))
      ->capture_default_str ();
  app.add_option ("--distance", o.distance,
                  "metres from sensor 0 to the wall (plane, default 1.5), to the box centre (box, default 1.2) "
                  "or to the mesh centre (mesh, default 1.5)");
  app.add_option ("--tilt-x", o.tilt_x, "wall or mesh tilt about the image x axis, degrees")->capture_default_str ();
  app.add_option ("--tilt-y", o.tilt_y, "wall or mesh tilt about the image y axis, degrees")->capture_default_str ();
  app.add_option ("--elevation", o.elevation, "box scene: sensors' angle above the table, degrees")
      ->capture_default_str ();
  app.add_option ("--mesh", o.mesh, "mesh file for --scene mesh: .ply, .obj, .stl, .vtk, or an organised .pcd");
  app.add_option ("--mesh-scale", o.mesh_scale, "factor from mesh units to metres (0.001 for millimetres)")
      ->capture_default_str ();
  app.add_option ("--projectors", o.projectors,
                  "sensors in the setup, all with active projectors (box: the paper's triangle for up to 3)")
      ->capture_default_str ();
  app.add_option ("--pose", o.poses,
                  "a sensor's pose, 16 numbers row-major (scene from camera; x right, y down, z forward), "
                  "repeatable: replaces the scene's placement, one sensor per pose")
      ->expected (16)
      ->allow_extra_args (false)
      ->take_all ();
  app.add_option ("--record", o.record, "which sensor to record: an index, or 'all'")->capture_default_str ();
  app.add_option ("--frames", o.frames, "frames to simulate")->capture_default_str ();
  app.add_option ("--seed", o.seed, "random seed (same seed, same bytes)")->capture_default_str ();
  // One value per occurrence, so that OUTPUT after --effect NAME is not taken for a second name.
  app.add_option ("--effect", o.effects, "switch an effect on (repeatable; see --list-effects)")
      ->allow_extra_args (false);
  app.add_option ("--set", o.assignments, "effect parameter, EFFECT.PARAMETER=VALUE (repeatable)")
      ->allow_extra_args (false);
  app.add_option ("--config", o.config, "YAML file of effects (base_noise, projector_shadows, effects); "
                                        "--effect and --set apply after it");
  app.add_option ("--base-noise", o.base_noise, "paper (the paper's polynomial) or none")
      ->check (CLI::IsMember ({"paper", "none"}));
  app.add_flag ("--no-shadows", o.no_shadows, "do not drop pixels the sensor's own projector cannot light");
  app.add_option ("--width", o.width, "image width, pixels (640 VGA, 320 QVGA)")->capture_default_str ();
  app.add_option ("--height", o.height, "image height, pixels (480 VGA, 240 QVGA)")->capture_default_str ();
  app.add_option ("--fx", o.fx, "focal length x, pixels (default 580 x width / 640)");
  app.add_option ("--fy", o.fy, "focal length y, pixels (default fx)");
  app.add_option ("--cx", o.cx, "principal point x, pixels (default (width - 1) / 2)");
  app.add_option ("--cy", o.cy, "principal point y, pixels (default (height - 1) / 2)");
  app.add_option ("--baseline", o.baseline, "projector-camera baseline, metres")->capture_default_str ();
  app.add_option ("-j,--threads", o.threads, "threads (0: all)")->capture_default_str ();
  app.add_flag ("--list-effects", o.list_effects, "list the effects and their parameters, then exit");
  app.add_flag ("-q,--quiet", o.quiet, "no summary on stdout");
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv))
    return 0;
  if (o.list_effects)
  {
    printEffects ();
    return 0;
  }

  if (o.output.empty ())
    throw InputError ("OUTPUT is required (the recording folder to create)");
  if (o.frames == 0 || o.frames > 1000000)
    throw InputError ("--frames must be between 1 and 1000000 (got " + std::to_string (o.frames) + ")");
  if (o.projectors < 1 || o.projectors > 64)
    throw InputError ("--projectors must be between 1 and 64 (got " + std::to_string (o.projectors) + ")");
  if (!o.poses.empty ())
  {
    const int n = static_cast<int> (o.poses.size () / 16);
    if (app.count ("--projectors") && o.projectors != n)
      throw InputError ("--projectors " + std::to_string (o.projectors) + " disagrees with the " + std::to_string (n) +
                        " --pose options (each pose is one sensor with its projector)");
    o.projectors = n;
  }
  if (o.threads > 1024)
    throw InputError ("--threads " + std::to_string (o.threads) + " is not a sensible thread count");
  int record = -1; // all
  if (o.record != "all")
  {
    std::size_t end = 0;
    try
    {
      record = std::stoi (o.record, &end);
    }
    catch (const std::exception &)
    {
      end = 0;
    }
    if (end != o.record.size () || record < 0 || record >= o.projectors)
      throw InputError ("--record must be 'all' or a sensor index from 0 to " + std::to_string (o.projectors - 1) +
                        " (got '" + o.record + "')");
  }
  const fs::path out = pcl_texlet_app::newOutputFolder (o.output, "a recording is never written over another");

  SceneSetup setup = makeSetup (o, app);
  placeSensors (o, setup);
  const SimulationSettings settings = makeSettings (o, app);
  const DepthSensor model = makeSensor (o);
  const auto t0 = std::chrono::steady_clock::now ();
  const KinectSimulator sim (setup.scene, setup.sensors (model), settings, o.threads);

  std::vector<std::size_t> sensors;
  if (record >= 0)
    sensors.push_back (static_cast<std::size_t> (record));
  else
    for (std::size_t k = 0; k < sim.sensorCount (); ++k)
      sensors.push_back (k);

  if (sensors.size () == 1 && record >= 0)
    writeSimulatedRecording (sim, setup, sensors[0], 0, o.frames, out.string ());
  else
  {
    // Several recordings: all of them inside one temporary folder renamed at the end.
    OutputFolder folder (out, o.output);
    for (const std::size_t k : sensors)
      writeSimulatedRecording (sim, setup, k, 0, o.frames,
                               (folder.temporary () / ("sensor_" + std::to_string (k))).string ());
    folder.publish ();
  }
  const double seconds = std::chrono::duration<double> (std::chrono::steady_clock::now () - t0).count ();

  if (!o.quiet)
  {
    const auto active = enabledEffects (settings.effects);
    std::string effects;
    for (const auto &e : active)
      effects += (effects.empty () ? "" : ", ") + e;
    std::cout << std::fixed << std::setprecision (2);
    std::cout << "scene:       " << setup.kind << " (" << o.scene << ")\n"
              << "sensors:     " << sim.sensorCount () << " (" << sim.activeProjectors () << " active projectors), "
              << "recorded: " << (record >= 0 ? std::to_string (record) : std::string ("all")) << "\n"
              << "image:       " << model.width << "x" << model.height << ", fx " << model.fx << " px, baseline "
              << std::defaultfloat << model.baseline_m << std::fixed << " m\n"
              << "noise:       base " << (settings.base_noise ? "paper polynomial" : "none") << "; effects: "
              << (effects.empty () ? "none" : effects) << "\n"
              << "frames:      " << o.frames << " per sensor, seed " << o.seed << ", " << seconds << " s\n"
              << "output:      " << o.output << std::endl;
  }
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
