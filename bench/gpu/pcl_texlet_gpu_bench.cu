/*
 * pcl_texlet_gpu_bench: texlet extraction on the GPU at the paper's settings (Table 1:
 * spacing 6, radius 6, 20 RANSAC iterations, 50 Monte Carlo samples) and at spacing 2, on a
 * full frame read from a file or synthesised.
 *
 * Each run uploads the 16-bit depth frame from pinned memory, back-projects it and computes
 * the texlets on the device, and downloads them into pinned memory. CUDA events time the
 * kernels (back-projection and texlets) and the whole run (transfers included); the report
 * gives the median of the runs after warm-up, as a table and optionally as JSON. Needs CUDA
 * only (no PCL).
 *
 * --relations N times the texlet relations instead (gpu::accumulateRelations on N noisy
 * texlets on the paper's box, labelled, the paper's histogram axes and the box's relations):
 * host arrays in, counts out, so uploads and downloads are included.
 */
#include <pcl_texlet/gpu/containers/device_array.h>
#include <pcl_texlet/gpu/texlet_estimation.h>
#include <pcl_texlet/gpu/texlet_relations.h>

#include <common/app_main.h>
#include <gpu/synthetic_box_texlets.h> // test/gpu: the tests' synthetic scenes
#include <gpu/synthetic_frame.h>

#include <CLI/CLI.hpp>

#include <cuda_runtime_api.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace gpu = pcl::texlet::gpu;
using gpu::DeviceArray;
using gpu::DeviceArray2D;
using gpu::DeviceTexlet;
using gpu::Precision;
using pcl_texlet_app::InputError;

namespace
{

/** Page-locked host memory, so transfers run at full speed and can be timed on the stream. */
template <typename T>
class PinnedBuffer
{
public:
  explicit PinnedBuffer (std::size_t n) : n_ (n)
  {
    PCL_TEXLET_CUDA_CHECK (cudaMallocHost (reinterpret_cast<void **> (&p_), n * sizeof (T)));
  }
  ~PinnedBuffer () { cudaFreeHost (p_); }
  PinnedBuffer (const PinnedBuffer &) = delete;
  PinnedBuffer &operator= (const PinnedBuffer &) = delete;
  T *data () { return p_; }
  std::size_t size () const { return n_; }

private:
  T *p_ = nullptr;
  std::size_t n_;
};

struct DepthFrame
{
  int width = 0, height = 0;
  std::vector<std::uint16_t> depth_mm;
  std::string source;
};

constexpr char kDumpMagic[8] = {'P', 'T', 'X', 'D', 'E', 'P', 'T', 'H'};

/** Binary dump: "PTXDEPTH", uint32 width, uint32 height (little-endian), then the depth in mm
  * as little-endian uint16, row by row. */
DepthFrame
readDump (const std::string &path)
{
  std::ifstream in (path, std::ios::binary);
  if (!in)
    throw InputError ("cannot open depth dump '" + path + "'");
  char magic[8];
  std::uint32_t wh[2];
  if (!in.read (magic, 8) || std::memcmp (magic, kDumpMagic, 8) != 0 || !in.read (reinterpret_cast<char *> (wh), 8))
    throw InputError ("'" + path + "' is not a depth dump (no PTXDEPTH header)");
  if (wh[0] == 0 || wh[1] == 0 || wh[0] > 16384 || wh[1] > 16384)
    throw InputError ("depth dump '" + path + "' has an impossible size " + std::to_string (wh[0]) + "x" +
                      std::to_string (wh[1]));
  DepthFrame f;
  f.width = static_cast<int> (wh[0]);
  f.height = static_cast<int> (wh[1]);
  f.depth_mm.resize (static_cast<std::size_t> (f.width) * f.height);
  if (!in.read (reinterpret_cast<char *> (f.depth_mm.data ()), f.depth_mm.size () * 2))
    throw InputError ("depth dump '" + path + "' is truncated: expected " + std::to_string (f.depth_mm.size ()) +
                      " depth values");
  f.source = path;
  return f;
}

/** Raw little-endian uint16 millimetres of a given size, or a 16-bit binary PGM (P5). */
DepthFrame
readDepth (const std::string &path, int width, int height)
{
  std::ifstream in (path, std::ios::binary);
  if (!in)
    throw InputError ("cannot open depth image '" + path + "'");
  DepthFrame f;
  f.source = path;
  std::string magic (2, '\0');
  in.read (&magic[0], 2);
  if (magic == "P5")
  {
    int maxval = 0;
    in >> f.width >> f.height >> maxval;
    in.get ();
    if (!in || f.width <= 0 || f.height <= 0 || maxval < 256 || maxval > 65535)
      throw InputError ("'" + path + "' is not a 16-bit binary PGM (P5 with maxval > 255)");
    f.depth_mm.resize (static_cast<std::size_t> (f.width) * f.height);
    std::vector<unsigned char> bytes (f.depth_mm.size () * 2);
    if (!in.read (reinterpret_cast<char *> (bytes.data ()), bytes.size ()))
      throw InputError ("16-bit PGM '" + path + "' is truncated");
    for (std::size_t i = 0; i < f.depth_mm.size (); ++i) // PGM is big-endian
      f.depth_mm[i] = static_cast<std::uint16_t> (bytes[2 * i] << 8 | bytes[2 * i + 1]);
    return f;
  }
  if (width <= 0 || height <= 0)
    throw InputError ("raw depth '" + path + "' needs --width and --height");
  f.width = width;
  f.height = height;
  f.depth_mm.resize (static_cast<std::size_t> (width) * height);
  in.seekg (0, std::ios::end);
  const std::streamoff size = in.tellg ();
  if (size != static_cast<std::streamoff> (f.depth_mm.size () * 2))
    throw InputError ("raw depth '" + path + "' has " + std::to_string (size) + " bytes, expected " +
                      std::to_string (f.depth_mm.size () * 2) + " for " + std::to_string (width) + "x" +
                      std::to_string (height) + " uint16");
  in.seekg (0);
  in.read (reinterpret_cast<char *> (f.depth_mm.data ()), size);
  return f;
}

/** Writes \a text to \a path through a temporary file in the same folder. */
void
writeAtomically (const std::string &path, const std::string &bytes)
{
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out (tmp, std::ios::binary);
    if (!out.write (bytes.data (), bytes.size ()) || !out.flush ())
    {
      std::remove (tmp.c_str ());
      throw InputError ("cannot write '" + path + "'");
    }
  }
  if (std::rename (tmp.c_str (), path.c_str ()) != 0)
  {
    std::remove (tmp.c_str ());
    throw InputError ("cannot write '" + path + "'");
  }
}

struct Stats
{
  double median = 0, min = 0, p90 = 0, max = 0;
};

Stats
stats (std::vector<float> v)
{
  std::sort (v.begin (), v.end ());
  Stats s;
  s.min = v.front ();
  s.max = v.back ();
  s.median = v.size () % 2 ? v[v.size () / 2] : 0.5 * (v[v.size () / 2 - 1] + v[v.size () / 2]);
  s.p90 = v[std::min (v.size () - 1, static_cast<std::size_t> (0.9 * (v.size () - 1) + 0.5))];
  return s;
}

/** The relations of \a n box texlets on the device, \a runs times after \a warmup: wall ms. */
int
measureRelations (int n, int warmup, int runs)
{
  namespace kn = pcl::texlet::kernels;
  const pcl_texlet_test::BoxTexlets texlets = pcl_texlet_test::syntheticBoxTexlets (std::max (1, n / 5), 1);
  const std::vector<kn::RelationBox> boxes = pcl_texlet_test::syntheticBoxRelations ();
  kn::RelationConfig config; // the paper's axes: 0-300 mm in 2 mm x 0-180 degrees in 1 degree
  config.boxes = boxes.data ();
  config.box_count = static_cast<int> (boxes.size ());
  config.label_count = 5;
  const kn::RelationInput<float> in = texlets.input (true);
  std::vector<std::uint64_t> histogram (static_cast<std::size_t> (config.axes.distance_bins) * config.axes.angle_bins),
      box_hits (boxes.size ()), label_pairs (25), label_inliers (25);
  std::vector<float> ms;
  kn::RelationCounts<std::uint64_t> counts;
  for (int k = 0; k < warmup + runs; ++k)
  {
    std::fill (histogram.begin (), histogram.end (), 0);
    std::fill (box_hits.begin (), box_hits.end (), 0);
    std::fill (label_pairs.begin (), label_pairs.end (), 0);
    std::fill (label_inliers.begin (), label_inliers.end (), 0);
    counts = kn::RelationCounts<std::uint64_t> ();
    counts.histogram = histogram.data ();
    counts.box_hits = box_hits.data ();
    counts.label_pairs = label_pairs.data ();
    counts.label_inliers = label_inliers.data ();
    const auto t0 = std::chrono::steady_clock::now ();
    gpu::accumulateRelations (in, config, counts);
    const float t = std::chrono::duration<float, std::milli> (std::chrono::steady_clock::now () - t0).count ();
    if (k >= warmup)
      ms.push_back (t);
  }
  const gpu::RelationLaunch launch = gpu::relationLaunch (in.count, config);
  std::sort (ms.begin (), ms.end ());
  const double median = ms[ms.size () / 2];
  std::cout << "relations of " << in.count << " texlets (" << counts.relations << " directed relations, "
            << std::setprecision (4) << 100.0 * counts.inliers / std::max<std::uint64_t> (1, counts.relations)
            << " % inliers): " << launch.blocks << " blocks x " << launch.threads_per_block << " threads, "
            << (launch.shared_histogram ? "shared-memory" : "global") << " histogram; median " << median << " ms, min "
            << ms.front () << " ms of " << runs << " runs after " << warmup << " warm-up ("
            << counts.relations / (median * 1e6) << " G relations/s, transfers included)" << std::endl;
  return 0;
}

struct Result
{
  std::string name;
  int spacing, radius, iterations, samples;
  std::string fit, uncertainty, precision, strategy;
  int texlets = 0;
  unsigned made = 0;
  Stats kernel, end_to_end, upload, download;
  double target_ms = 0;
};

class Events
{
public:
  explicit Events (int n) : e_ (n)
  {
    for (auto &e : e_)
      PCL_TEXLET_CUDA_CHECK (cudaEventCreate (&e));
  }
  ~Events ()
  {
    for (auto &e : e_)
      cudaEventDestroy (e);
  }
  cudaEvent_t operator[] (int i) const { return e_[i]; }
  float
  ms (int a, int b) const
  {
    float t = 0;
    PCL_TEXLET_CUDA_CHECK (cudaEventElapsedTime (&t, e_[a], e_[b]));
    return t;
  }

private:
  std::vector<cudaEvent_t> e_;
};

Result
measure (const DepthFrame &frame, const gpu::DeviceCamera &camera, const pcl::texlet::TexletParameters &params,
         Precision precision, gpu::Strategy strategy, int warmup, int runs)
{
  gpu::TexletEstimation est;
  est.setStrategy (strategy);
  est.setParameters (params);
  est.setCamera (camera);
  est.setPrecision (precision);
  const int n = est.texletCount (frame.width, frame.height);
  PinnedBuffer<std::uint16_t> depth_host (frame.depth_mm.size ());
  std::copy (frame.depth_mm.begin (), frame.depth_mm.end (), depth_host.data ());
  PinnedBuffer<DeviceTexlet> texlets_host (n);
  DeviceArray2D<std::uint16_t> depth (frame.height, frame.width);
  DeviceArray<DeviceTexlet> texlets (n);
  cudaStream_t stream;
  PCL_TEXLET_CUDA_CHECK (cudaStreamCreate (&stream));
  est.setStream (stream);
  Events ev (4);
  std::vector<float> kernel, e2e, up, down;
  for (int r = 0; r < warmup + runs; ++r)
  {
    PCL_TEXLET_CUDA_CHECK (cudaEventRecord (ev[0], stream));
    PCL_TEXLET_CUDA_CHECK (cudaMemcpy2DAsync (depth.ptr (), depth.step (), depth_host.data (),
                                              frame.width * sizeof (std::uint16_t), frame.width * sizeof (std::uint16_t),
                                              frame.height, cudaMemcpyHostToDevice, stream));
    PCL_TEXLET_CUDA_CHECK (cudaEventRecord (ev[1], stream));
    est.compute (depth, texlets); // back-projection and texlets
    PCL_TEXLET_CUDA_CHECK (cudaEventRecord (ev[2], stream));
    PCL_TEXLET_CUDA_CHECK (cudaMemcpyAsync (texlets_host.data (), texlets.ptr (), texlets.sizeBytes (),
                                            cudaMemcpyDeviceToHost, stream));
    PCL_TEXLET_CUDA_CHECK (cudaEventRecord (ev[3], stream));
    PCL_TEXLET_CUDA_CHECK (cudaEventSynchronize (ev[3]));
    if (r >= warmup)
    {
      up.push_back (ev.ms (0, 1));
      kernel.push_back (ev.ms (1, 2));
      down.push_back (ev.ms (2, 3));
      e2e.push_back (ev.ms (0, 3));
    }
  }
  cudaStreamDestroy (stream);
  Result res;
  res.spacing = params.spacing;
  res.radius = params.radius;
  res.iterations = params.ransac_iterations;
  res.samples = params.samples;
  const char *fits[] = {"pca", "svd", "averaging"}, *uncertainties[] = {"none", "analytic", "montecarlo"};
  res.fit = fits[static_cast<int> (params.fit)];
  res.uncertainty = uncertainties[static_cast<int> (params.uncertainty)];
  res.precision = precision == Precision::Double ? "double" : "float";
  res.strategy = est.effectiveStrategy () == gpu::Strategy::Warp ? "warp" : "thread";
  res.texlets = n;
  res.made = est.getMadeCount ();
  res.kernel = stats (kernel);
  res.end_to_end = stats (e2e);
  res.upload = stats (up);
  res.download = stats (down);
  return res;
}

std::string
json (const std::vector<Result> &results, const DepthFrame &frame, const cudaDeviceProp &prop, int warmup, int runs)
{
  std::ostringstream o;
  o << std::setprecision (6);
  const auto st = [&] (const Stats &s) {
    std::ostringstream t;
    t << std::setprecision (6) << "{\"median\": " << s.median << ", \"min\": " << s.min << ", \"p90\": " << s.p90
      << ", \"max\": " << s.max << "}";
    return t.str ();
  };
  std::string src;
  for (const char c : frame.source)
    src += (c == '"' || c == '\\') ? std::string ("\\") + c : std::string (1, c);
  o << "{\n  \"device\": \"" << prop.name << "\",\n  \"frame\": {\"source\": \"" << src << "\", \"width\": "
    << frame.width << ", \"height\": " << frame.height << "},\n  \"warmup\": " << warmup << ",\n  \"runs\": " << runs
    << ",\n  \"unit\": \"ms\",\n  \"results\": [\n";
  for (std::size_t i = 0; i < results.size (); ++i)
  {
    const Result &r = results[i];
    o << "    {\"name\": \"" << r.name << "\", \"spacing\": " << r.spacing << ", \"radius\": " << r.radius
      << ", \"ransac_iterations\": " << r.iterations << ", \"samples\": " << r.samples << ", \"fit\": \"" << r.fit
      << "\", \"uncertainty\": \"" << r.uncertainty << "\", \"precision\": \"" << r.precision << "\", \"strategy\": \"" << r.strategy
      << "\", \"texlets\": " << r.texlets << ", \"made\": " << r.made << ",\n     \"kernel_ms\": " << st (r.kernel)
      << ",\n     \"end_to_end_ms\": " << st (r.end_to_end) << ",\n     \"upload_ms\": " << st (r.upload)
      << ", \"download_ms\": " << st (r.download) << ",\n     \"target_end_to_end_ms\": " << r.target_ms
      << ", \"meets_target\": " << (r.end_to_end.median < r.target_ms ? "true" : "false") << "}"
      << (i + 1 < results.size () ? "," : "") << "\n";
  }
  o << "  ]\n}\n";
  return o.str ();
}

int
run (int argc, char **argv)
{
  CLI::App app ("Times GPU texlet extraction (CUDA events, median after warm-up) at the paper's settings.");
  std::string depth_path, dump_path, json_path, save_path, precision_name = "both", strategy_name = "both", fit_name = "pca",
                                                              uncertainty_name = "montecarlo";
  int width = 0, height = 0, runs = 100, warmup = 10;
  double fx = 0, fy = 0, cx = -1, cy = -1;
  app.add_option ("--depth", depth_path, "depth image: 16-bit binary PGM, or raw little-endian uint16 mm (with --width/--height)");
  app.add_option ("--dump", dump_path, "depth dump: 'PTXDEPTH', uint32 width, height, then uint16 mm");
  app.add_option ("--width", width, "width of a raw depth image");
  app.add_option ("--height", height, "height of a raw depth image");
  app.add_option ("--fx", fx, "focal length x, pixels (default 580 at 640 wide, scaled)");
  app.add_option ("--fy", fy, "focal length y, pixels (default fx)");
  app.add_option ("--cx", cx, "principal point x, pixels (default the image centre)");
  app.add_option ("--cy", cy, "principal point y, pixels (default the image centre)");
  app.add_option ("--runs", runs, "timed runs per setting (at least 50)")->check (CLI::Range (50, 100000));
  app.add_option ("--warmup", warmup, "untimed runs first")->check (CLI::Range (1, 10000));
  app.add_option ("--precision", precision_name, "double, float or both")->check (CLI::IsMember ({"double", "float", "both"}));
  app.add_option ("--strategy", strategy_name, "thread (one thread per texlet), warp (one warp per texlet) or both")
      ->check (CLI::IsMember ({"thread", "warp", "both"}));
  app.add_option ("--fit", fit_name, "plane fit: pca, svd or averaging")->check (CLI::IsMember ({"pca", "svd", "averaging"}));
  app.add_option ("--uncertainty", uncertainty_name, "none, analytic or montecarlo")
      ->check (CLI::IsMember ({"none", "analytic", "montecarlo"}));
  app.add_option ("--json", json_path, "also write the results as JSON here");
  app.add_option ("--save-frame", save_path, "write the frame used as a depth dump (e.g. the synthetic one)");
  int relations = 0;
  app.add_option ("--relations", relations, "time the texlet relations of this many texlets instead (see the file comment)")
      ->check (CLI::Range (2, 2000000));
  try
  {
    app.parse (argc, argv);
  }
  catch (const CLI::CallForHelp &e)
  {
    return app.exit (e);
  }
  catch (const CLI::ParseError &e)
  {
    throw InputError (e.what ());
  }
  if (!depth_path.empty () && !dump_path.empty ())
    throw InputError ("give either --depth or --dump, not both");
  if (relations > 0)
  {
    if (gpu::cudaDeviceCount () == 0)
      throw InputError ("no CUDA device found (cudaGetDeviceCount reports none)");
    return measureRelations (relations, warmup, runs);
  }

  DepthFrame frame;
  if (!dump_path.empty ())
    frame = readDump (dump_path);
  else if (!depth_path.empty ())
    frame = readDepth (depth_path, width, height);
  else
  {
    pcl_texlet_test::SyntheticFrame scene;
    frame.width = scene.width;
    frame.height = scene.height;
    frame.depth_mm = scene.render ();
    frame.source = "synthetic (tilted wall and sphere, 640x480)";
  }
  if (!save_path.empty ())
  {
    std::string bytes (kDumpMagic, 8);
    const std::uint32_t wh[2] = {static_cast<std::uint32_t> (frame.width), static_cast<std::uint32_t> (frame.height)};
    bytes.append (reinterpret_cast<const char *> (wh), 8);
    bytes.append (reinterpret_cast<const char *> (frame.depth_mm.data ()), frame.depth_mm.size () * 2);
    writeAtomically (save_path, bytes);
  }

  if (gpu::cudaDeviceCount () == 0)
    throw InputError ("no CUDA device found (cudaGetDeviceCount reports none)");
  cudaDeviceProp prop;
  PCL_TEXLET_CUDA_CHECK (cudaGetDeviceProperties (&prop, 0));

  if (fx <= 0)
    fx = 580.0 * frame.width / 640.0;
  if (fy <= 0)
    fy = fx;
  if (cx < 0)
    cx = 0.5 * (frame.width - 1);
  if (cy < 0)
    cy = 0.5 * (frame.height - 1);
  const gpu::DeviceCamera camera = gpu::DeviceCamera::pinhole (fx, fy, cx, cy);

  std::vector<Precision> precisions;
  if (precision_name != "float")
    precisions.push_back (Precision::Double);
  if (precision_name != "double")
    precisions.push_back (Precision::Float);

  std::vector<gpu::Strategy> strategies;
  if (strategy_name != "warp")
    strategies.push_back (gpu::Strategy::Thread);
  if (strategy_name != "thread")
    strategies.push_back (gpu::Strategy::Warp);

  std::vector<Result> results;
  for (const int spacing : {6, 2})
    for (const Precision precision : precisions)
    for (const gpu::Strategy strategy : strategies)
    {
      pcl::texlet::TexletParameters p; // Table 1: radius 6, RANSAC 20, Monte Carlo 50
      p.spacing = spacing;
      p.fit = fit_name == "pca" ? pcl::texlet::PlaneFitMethod::PCA
              : fit_name == "svd" ? pcl::texlet::PlaneFitMethod::SVD
                                  : pcl::texlet::PlaneFitMethod::Averaging;
      p.uncertainty = uncertainty_name == "none" ? pcl::texlet::UncertaintyMethod::None
                      : uncertainty_name == "analytic" ? pcl::texlet::UncertaintyMethod::Analytic
                                                       : pcl::texlet::UncertaintyMethod::MonteCarlo;
      std::cerr << "measuring spacing " << spacing << ", " << (precision == Precision::Double ? "double" : "float")
                << ", " << (strategy == gpu::Strategy::Warp ? "warp" : "thread") << " (" << warmup
                << " warm-up + " << runs << " runs)..." << std::endl;
      Result r = measure (frame, camera, p, precision, strategy, warmup, runs);
      r.name = spacing == 6 ? "table1_spacing6" : "spacing2";
      r.target_ms = spacing == 6 ? 1.0 : 3.0;
      results.push_back (r);
    }

  std::cout << "pcl_texlet_gpu_bench on " << prop.name << ", frame " << frame.source << " (" << frame.width << "x"
            << frame.height << "), radius 6, RANSAC 20, " << fit_name << ", " << uncertainty_name
            << " (50 samples); median of " << runs << " runs after " << warmup << " warm-up, ms\n\n";
  std::cout << std::left << std::setw (18) << "setting" << std::setw (10) << "precision" << std::setw (8) << "threads" << std::right << std::setw (9)
            << "texlets" << std::setw (9) << "made" << std::setw (11) << "kernel" << std::setw (11) << "upload"
            << std::setw (11) << "download" << std::setw (13) << "end-to-end" << std::setw (9) << "target" << "\n";
  std::cout << std::fixed << std::setprecision (3);
  for (const Result &r : results)
    std::cout << std::left << std::setw (18) << r.name << std::setw (10) << r.precision << std::setw (8) << r.strategy << std::right << std::setw (9)
              << r.texlets << std::setw (9) << r.made << std::setw (11) << r.kernel.median << std::setw (11)
              << r.upload.median << std::setw (11) << r.download.median << std::setw (13) << r.end_to_end.median
              << std::setw (6) << "< " << std::setprecision (0) << r.target_ms << std::setprecision (3)
              << (r.end_to_end.median < r.target_ms ? " met" : " MISSED") << "\n";
  std::cout << "\nkernel: back-projection and texlets (with the count of texlets made); end-to-end: depth upload "
               "from pinned memory, kernels, texlet download to pinned memory.\n";
  if (!json_path.empty ())
    writeAtomically (json_path, json (results, frame, prop, warmup, runs));
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp ("pcl_texlet_gpu_bench", run, argc, argv);
}
