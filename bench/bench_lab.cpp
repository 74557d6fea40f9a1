/*
 * How long the model lab takes to analyse 5 plane recordings of 30 frames at 640x480 with the
 * full candidate ranking (every effect fitted on the even frames and scored on the odd ones,
 * plus the bootstrap significance test), on 2 threads: the "under 60 s on 2 cores".
 * The recordings are written by the simulator before timing; the timed part reads them from
 * disk (measureRecording), compares the paper's model and ranks the candidates.
 *
 *   bench_lab --benchmark_filter=Lab
 */
#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/noise/effects/disparity_quantization.h>
#include <pcl_texlet/noise/effects/incidence_angle.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/simulation/simulated_recording.h>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
using namespace pcl::texlet;

namespace
{

/** Five walls from 0.8 to 3 m with quantisation and the incidence effect hidden in them. */
std::vector<std::string>
writeWalls (const fs::path &dir)
{
  const double distances[5] = {0.8, 1.35, 1.9, 2.45, 3.0}, tilts[5] = {0, 20, 40, 55, 70};
  std::vector<std::string> paths;
  for (int k = 0; k < 5; ++k)
  {
    const sim::SceneSetup setup = sim::planeSetup (distances[k], 5, tilts[k]);
    sim::SimulationSettings s;
    s.seed = 100 + k;
    sim::setEffectEnabled (s.effects, effects::DisparityQuantization::kName, true);
    sim::setEffectEnabled (s.effects, effects::IncidenceAngle::kName, true);
    sim::KinectSimulator simulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (640, 480)), s);
    const std::string path = (dir / ("wall_" + std::to_string (k))).string ();
    sim::writeSimulatedRecording (simulator, setup, 0, 0, 30, path);
    paths.push_back (path);
  }
  return paths;
}

void
BM_LabFiveRecordings30VGA (benchmark::State &state)
{
  const fs::path dir = fs::temp_directory_path () / ("pcl_texlet_bench_lab_" + std::to_string (::getpid ()));
  fs::remove_all (dir);
  fs::create_directories (dir);
  const std::vector<std::string> paths = writeWalls (dir);
  std::size_t significant = 0;
  for (auto _ : state)
  {
    lab::LabSettings settings;
    settings.threads = static_cast<int> (state.range (0));
    lab::ModelLab lab (settings);
    for (const auto &p : paths)
      lab.addRecording (lab::measureRecording (p));
    const NoiseModel paper = NoiseModel::paper ();
    benchmark::DoNotOptimize (lab.evaluate (paper));
    const auto candidates = lab.rankCandidates (paper);
    significant = 0;
    for (const auto &c : candidates)
      significant += c.significant ? 1 : 0;
  }
  state.counters["significant"] = static_cast<double> (significant);
  fs::remove_all (dir);
}
BENCHMARK (BM_LabFiveRecordings30VGA)->Arg (2)->Unit (benchmark::kSecond)->Iterations (1)->UseRealTime ();

} // namespace

BENCHMARK_MAIN ();
