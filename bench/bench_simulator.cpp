/*
 * How long the Kinect simulator takes to make a 30-frame 640x480 recording: the whole job
 * (ray casting the scene, simulating, compressing the PNGs, writing the folder) and the
 * simulation alone, on 1 and 2 threads, for the paper's noise alone and with every effect on.
 *
 *   bench_simulator --benchmark_filter=Recording
 */
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/simulation/simulated_recording.h>

#include <benchmark/benchmark.h>

#include <filesystem>

#include <unistd.h>

namespace fs = std::filesystem;
using namespace pcl::texlet::sim;

namespace
{

constexpr std::uint32_t kFrames = 30;

SimulationSettings
settings (bool all_effects)
{
  SimulationSettings s;
  s.seed = 1;
  if (all_effects)
    for (const auto &e : effectCatalogue ())
      setEffectEnabled (s.effects, e.name, true);
  return s;
}

/** The box scene with three projectors when every effect is on (interference needs them). */
SceneSetup
setup (bool all_effects)
{
  return all_effects ? boxSetup (1.2, 40, 3) : planeSetup (1.5, 20, 10);
}

/** Args: threads, all effects (0/1). */
void
BM_Recording30VGA (benchmark::State &state)
{
  const unsigned threads = static_cast<unsigned> (state.range (0));
  const bool all = state.range (1) != 0;
  const SceneSetup scene = setup (all);
  const fs::path folder = fs::temp_directory_path () / ("pcl_texlet_bench_" + std::to_string (::getpid ()));
  for (auto _ : state)
  {
    fs::remove_all (folder);
    const KinectSimulator sim (scene.scene, scene.sensors (DepthSensor::kinect ()), settings (all), threads);
    writeSimulatedRecording (sim, scene, 0, 0, kFrames, folder.string ());
  }
  fs::remove_all (folder);
  state.counters["frames_per_s"] = benchmark::Counter (kFrames * state.iterations (), benchmark::Counter::kIsRate);
}

/** Args: threads, all effects (0/1). Frames in memory only. */
void
BM_Simulate30VGA (benchmark::State &state)
{
  const unsigned threads = static_cast<unsigned> (state.range (0));
  const bool all = state.range (1) != 0;
  const SceneSetup scene = setup (all);
  const KinectSimulator sim (scene.scene, scene.sensors (DepthSensor::kinect ()), settings (all), threads);
  for (auto _ : state)
    benchmark::DoNotOptimize (sim.simulate (0, 0, kFrames));
  state.counters["frames_per_s"] = benchmark::Counter (kFrames * state.iterations (), benchmark::Counter::kIsRate);
}

/** Both benchmarks: 1 and 2 threads, with and without every effect; three timed runs each. */
void
threadsAndEffects (benchmark::internal::Benchmark *b)
{
  b->ArgsProduct ({{1, 2}, {0, 1}})
      ->ArgNames ({"threads", "all_effects"})
      ->Unit (benchmark::kMillisecond)
      ->UseRealTime ()
      ->Iterations (3);
}

} // namespace

BENCHMARK (BM_Recording30VGA)->Apply (threadsAndEffects);
BENCHMARK (BM_Simulate30VGA)->Apply (threadsAndEffects);

BENCHMARK_MAIN ();
