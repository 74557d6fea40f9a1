/*
 * bench_relations: all-pairs texlet relations (normal distance x angle histogram plus inlier
 * boxes of the paper's Table 2) for n texlets, on 1 and 2 threads. Items are directed
 * relations, n (n - 1) per run. Texlets are random patches around the paper's box.
 * In builds with CUDA, BM_AllPairRelationsGpu runs the same on the GPU backend
 * (pcl::texlet::gpu::accumulateRelations: upload, kernel, download); it reports an error and no time
 * when there is no CUDA device.
 *
 *   build/bench/bench_relations --benchmark_filter='/30000/'
 */
#include <pcl_texlet/relations/texlet_relations.h>

#ifdef PCL_TEXLET_BENCH_WITH_GPU
#include <pcl_texlet/gpu/containers/cuda_error.h>
#include <pcl_texlet/gpu/texlet_relations.h>
#endif

#include <benchmark/benchmark.h>

#include <random>

namespace
{

pcl::PointCloud<pcl::Texlet>
randomTexlets (int n)
{
  std::mt19937 rng (1);
  std::uniform_real_distribution<float> u (-0.2f, 0.2f);
  std::normal_distribution<float> g (0.0f, 1.0f);
  pcl::PointCloud<pcl::Texlet> cloud;
  for (int i = 0; i < n; ++i)
  {
    pcl::Texlet t;
    t.x = u (rng);
    t.y = u (rng);
    t.z = 0.12f + u (rng);
    Eigen::Vector3f nrm (g (rng), g (rng), g (rng));
    t.getNormalVector3fMap () = nrm.normalized ();
    t.support = 50;
    cloud.push_back (t);
  }
  return cloud;
}

/** Times accumulateRelations () over \a n random texlets against the paper's box, with six labels
  * cycled over the texlets when \a labelled. One untimed call first: on the GPU backend it pays
  * for the CUDA context and the module load.
  */
void
timeAllPairRelations (benchmark::State &state, int n, const pcl::texlet::RelationParameters &params, bool labelled)
{
  const auto cloud = randomTexlets (n);
  const pcl::texlet::KnownObject box = pcl::texlet::paperBoxObject ();
  std::vector<int> labels; // empty: unlabelled
  if (labelled)
    for (std::size_t i = 0; i < cloud.size (); ++i)
      labels.push_back (static_cast<int> (i % 6));
  pcl::texlet::accumulateRelations (randomTexlets (100), box, params);
  for (auto _ : state)
  {
    const auto s = pcl::texlet::accumulateRelations (cloud, box, params, labels);
    benchmark::DoNotOptimize (s.inliers);
  }
  state.SetItemsProcessed (state.iterations () * static_cast<std::int64_t> (n) * (n - 1));
  state.counters["texlets"] = n;
}

void
BM_AllPairRelations (benchmark::State &state)
{
  pcl::texlet::RelationParameters params;
  params.threads = static_cast<unsigned> (state.range (1));
  timeAllPairRelations (state, static_cast<int> (state.range (0)), params, state.range (2) != 0);
  state.counters["threads"] = static_cast<double> (params.threads);
}

#ifdef PCL_TEXLET_BENCH_WITH_GPU
void
BM_AllPairRelationsGpu (benchmark::State &state)
{
  if (pcl::texlet::gpu::cudaDeviceCount () == 0)
  {
    state.SkipWithError ("no CUDA device");
    return;
  }
  pcl::texlet::RelationParameters params;
  params.backend = [] (const auto &in, const auto &config, auto &counts) {
    pcl::texlet::gpu::accumulateRelations (in, config, counts);
  };
  timeAllPairRelations (state, static_cast<int> (state.range (0)), params, state.range (1) != 0);
}
#endif

} // namespace

#ifdef PCL_TEXLET_BENCH_WITH_GPU
BENCHMARK (BM_AllPairRelationsGpu)
    ->ArgNames ({"texlets", "labels"})
    ->Args ({10000, 0})
    ->Args ({30000, 0})
    ->Args ({30000, 1})
    ->Args ({100000, 1})
    ->Unit (benchmark::kMillisecond)
    ->UseRealTime ()
    ->Iterations (3);
#endif

BENCHMARK (BM_AllPairRelations)
    ->ArgNames ({"texlets", "threads", "labels"})
    ->Args ({3000, 1, 0})
    ->Args ({3000, 2, 0})
    ->Args ({10000, 1, 0})
    ->Args ({10000, 2, 0})
    ->Args ({10000, 2, 1})
    ->Args ({30000, 1, 0})
    ->Args ({30000, 2, 0})
    ->Args ({30000, 2, 1})
    ->Unit (benchmark::kMillisecond)
    ->UseRealTime ()
    ->Iterations (1);

BENCHMARK_MAIN ();
