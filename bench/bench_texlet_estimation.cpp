/*
 * How long texlet extraction takes on a real 640x480 Kinect frame, next to PCL's
 * NormalEstimationOMP on the same centres (the hexagonal grid of TexletEstimation, spacing 6)
 * with the same neighbourhood size (k = 113, the pixels of the radius-6 disc): texlets
 * without uncertainty, with analytic uncertainty and with 50-sample Monte Carlo.
 *
 *   bench_texlet_estimation --benchmark_repetitions=10 --benchmark_enable_random_interleaving=true
 *
 * Args of BM_Texlet: uncertainty method (0 None, 1 Analytic, 2 MonteCarlo), threads.
 * Args of BM_NormalEstimationOMP: threads. Compare medians of one run (the machine may be shared);
 * the CPU column is the CPU time of all threads of the process.
 */
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/features/normal_3d_omp.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <benchmark/benchmark.h>

#include <stdexcept>

namespace
{

using Cloud = pcl::PointCloud<pcl::PointXYZRGBA>;

constexpr int kSpacing = 6;
constexpr int kRadius = 6;
constexpr int kRansacIterations = 20;
constexpr int kSamples = 50;

const Cloud::ConstPtr &
frame ()
{
  static const Cloud::ConstPtr cloud = [] {
    auto c = std::make_shared<Cloud> ();
    const std::string path = std::string (DATA_DIR) + "/kinect/milk_cartoon_all_small_clorox.pcd";
    if (pcl::io::loadPCDFile (path, *c) != 0 || c->width != 640 || c->height != 480)
      throw std::runtime_error ("bench_texlet_estimation: cannot read the 640x480 frame " + path);
    return Cloud::ConstPtr (c);
  }();
  return cloud;
}

pcl::TexletEstimation<pcl::PointXYZRGBA>
estimator (pcl::texlet::UncertaintyMethod method, unsigned threads)
{
  pcl::TexletEstimation<pcl::PointXYZRGBA> est;
  est.setInputCloud (frame ());
  est.setSpacing (kSpacing);
  est.setRadius (kRadius);
  est.setRansacIterations (kRansacIterations);
  est.setUncertaintyMethod (method);
  est.setMonteCarloSamples (kSamples);
  est.setNumberOfThreads (threads);
  return est;
}

/** The hexagonal grid of centres TexletEstimation uses, as indices for NormalEstimationOMP. */
pcl::IndicesPtr
hexCentres ()
{
  auto est = estimator (pcl::texlet::UncertaintyMethod::None, 1);
  pcl::PointCloud<pcl::Texlet> out;
  est.compute (out);
  auto idx = std::make_shared<pcl::Indices> ();
  for (const auto &t : out)
    idx->push_back (static_cast<pcl::index_t> (t.pixel_index));
  return idx;
}

void
BM_Texlet (benchmark::State &state)
{
  const auto method = static_cast<pcl::texlet::UncertaintyMethod> (state.range (0));
  auto est = estimator (method, static_cast<unsigned> (state.range (1)));
  pcl::PointCloud<pcl::Texlet> out;
  for (auto _ : state)
  {
    est.compute (out);
    benchmark::DoNotOptimize (out.points.data ());
  }
  state.counters["texlets"] = static_cast<double> (out.size ());
}

void
BM_NormalEstimationOMP (benchmark::State &state)
{
  const pcl::IndicesPtr centres = hexCentres ();
  pcl::NormalEstimationOMP<pcl::PointXYZRGBA, pcl::Normal> ne (static_cast<unsigned> (state.range (0)));
  ne.setInputCloud (frame ());
  ne.setIndices (centres);
  ne.setKSearch (113); // pixels within radius 6
  pcl::PointCloud<pcl::Normal> out;
  for (auto _ : state)
  {
    ne.compute (out);
    benchmark::DoNotOptimize (out.points.data ());
  }
  state.counters["normals"] = static_cast<double> (out.size ());
}

} // namespace

BENCHMARK (BM_NormalEstimationOMP)->ArgName ("threads")->Arg (1)->Arg (2)->Unit (benchmark::kMillisecond)->MeasureProcessCPUTime ()->UseRealTime ();
BENCHMARK (BM_Texlet)
    ->ArgNames ({"method", "threads"})
    ->ArgsProduct ({{0, 1, 2}, {1, 2}})
    ->Unit (benchmark::kMillisecond)
    ->MeasureProcessCPUTime ()
    ->UseRealTime ();

BENCHMARK_MAIN ();
