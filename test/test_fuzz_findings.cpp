/*
 * Regression tests for what the fuzz targets (test/fuzz/, docs/fuzzing.md) found: each input is
 * the minimised crashing input (also kept in the target's corpus), and each test checks the
 * documented failure, a pcl::PCLException naming the input and the problem, or the right result.
 */
#include "support/expect_error.h"
#include "support/temp_dir.h"

#include <pcl_texlet/io/noise_model_io.h>
#include <pcl_texlet/io/png_image.h>
#include <pcl_texlet/simulation/simulation_config.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <zlib.h>

using namespace pcl::texlet;
using pcl_texlet_test::expectError;

namespace
{

/** A PNG of \a width x \a height pixels in its header whose only image data is a few zero bytes. */
std::string
pngClaiming (std::uint32_t width, std::uint32_t height, int bit_depth, int colour_type)
{
  const auto be32 = [] (std::string &s, std::uint32_t v) {
    for (int shift : {24, 16, 8, 0})
      s.push_back (static_cast<char> ((v >> shift) & 0xff));
  };
  const auto chunk = [&] (std::string &png, const std::string &type, const std::string &data) {
    be32 (png, static_cast<std::uint32_t> (data.size ()));
    const std::string body = type + data;
    png += body;
    be32 (png, static_cast<std::uint32_t> (crc32 (0L, reinterpret_cast<const Bytef *> (body.data ()), body.size ())));
  };
  std::string png ("\x89PNG\r\n\x1a\n", 8), ihdr;
  be32 (ihdr, width);
  be32 (ihdr, height);
  ihdr += std::string {static_cast<char> (bit_depth), static_cast<char> (colour_type), 0, 0, 0};
  chunk (png, "IHDR", ihdr);
  std::vector<Bytef> zipped (64);
  uLongf zipped_size = zipped.size ();
  const Bytef zeros[16] = {};
  compress (zipped.data (), &zipped_size, zeros, sizeof (zeros));
  chunk (png, "IDAT", std::string (zipped.begin (), zipped.begin () + zipped_size));
  chunk (png, "IEND", "");
  return png;
}

/** A file of this test's own, in a folder removed at the end of the scope. */
struct ScratchFile
{
  pcl_texlet_test::TempDir dir;
  std::string path;
  explicit ScratchFile (const std::string &name, const std::string &bytes = "")
    : dir ("fuzz_findings_" + pcl_texlet_test::TempDir::currentTestName () + "_" + name),
      path (dir.write (name, bytes).string ())
  {}
};

} // namespace

// fuzz_noise_model_yaml: a list as a key (`? - name: ...`, YAML's complex key) made yaml-cpp's
// YAML::TypedBadConversion escape the loader instead of pcl::IOException.
TEST (FuzzFindings, NoiseModelYamlComplexKeyIsAClearError)
{
  expectError<pcl::PCLException> ([] { parseNoiseModelYaml ("min_sigma_mm: 0.1\nterms:\n? - name: polynomial\n", "model.yaml"); },
                    {"model.yaml", "key", "list or map"});
  // The same inside a term: as its name, as one of its keys, as a parameter's name.
  expectError<pcl::PCLException> ([] { parseNoiseModelYaml ("terms:\n  - name: [polynomial]\n", "model.yaml"); },
                    {"model.yaml", "term 1's name"});
  expectError<pcl::PCLException> ([] { parseNoiseModelYaml ("terms:\n  - name: polynomial\n    ? [a]\n    : 1\n", "model.yaml"); },
                    {"model.yaml", "term 'polynomial'"});
  expectError<pcl::PCLException> ([] { parseNoiseModelYaml ("terms:\n  - name: polynomial\n    parameters: {[p00]: 1}\n", "m.yaml"); },
                    {"m.yaml", "term 'polynomial'", "list or map"});
}

// The same yaml-cpp conversion in the simulator's config (found by replaying the noise model's
// finding against fuzz_simulation_config): a list or map as a key, at the top, under effects or
// among an effect's parameters.
TEST (FuzzFindings, SimulationConfigComplexKeyIsAClearError)
{
  for (const char *yaml : {"{[a]: 1}\n", "effects: {[radial]: true}\n", "effects:\n  radial: {[gain]: 1}\n"})
  {
    sim::SimulationSettings settings;
    settings.seed = 7;
    expectError<pcl::PCLException> ([&] { sim::parseSimulationConfig (yaml, settings, "config.yaml"); },
                      {"config.yaml", "must be a plain name, not a list or map"});
    EXPECT_EQ (settings.seed, 7u) << "a bad file leaves the settings as they were";
  }
}

// fuzz_depth_png (from a header-only input written after the fuzzer stalled on libpng's CRCs, see
// docs/fuzzing.md): a PNG header claiming 1,000,000 x 1,000,000 pixels made the reader allocate
// 2 TB before reading a row (ASan: allocation-size-too-big; without ASan std::bad_alloc, not the
// documented pcl::IOException).
TEST (FuzzFindings, PngHeaderClaimingMoreThanTheFileHoldsIsAClearError)
{
  int w = -1, h = -1;
  // Claims beyond any sensor's size are refused by the side limit (docs/inputs.md) ...
  const ScratchFile depth ("huge_depth.png", pngClaiming (1000000, 1000000, 16, 0));
  expectError<pcl::PCLException> ([&] { readDepthPng (depth.path, w, h); }, {depth.path, "1000000x1000000", "corrupt header"});
  const ScratchFile rgb ("huge_rgb.png", pngClaiming (200000, 3000, 8, 2));
  expectError<pcl::PCLException> ([&] { readRgbPng (rgb.path, w, h); }, {rgb.path, "200000x3000", "corrupt header"});
  // ... and claims within it (here 512 MB and 144 MB of pixels) by what the small file can hold.
  const ScratchFile big_depth ("big_depth.png", pngClaiming (16000, 16000, 16, 0));
  expectError<pcl::PCLException> ([&] { readDepthPng (big_depth.path, w, h); }, {big_depth.path, "16000 x 16000", "corrupt header"});
  const ScratchFile big_rgb ("big_rgb.png", pngClaiming (16000, 3000, 8, 2));
  expectError<pcl::PCLException> ([&] { readRgbPng (big_rgb.path, w, h); }, {big_rgb.path, "16000 x 3000", "corrupt header"});
  // Small claims with too little data stay libpng's own error (truncated or corrupt data).
  const ScratchFile small ("small_depth.png", pngClaiming (64, 48, 16, 0));
  expectError<pcl::PCLException> ([&] { readDepthPng (small.path, w, h); }, {small.path});
}

// The bound must not refuse real frames, however well they compress: an all-zero SXGA depth frame
// (1280 x 1024, the largest sensor mode) and an all-zero VGA RGB frame read back.
TEST (FuzzFindings, HighlyCompressedFramesStillRead)
{
  const ScratchFile depth ("zero_depth.png"), rgb ("zero_rgb.png");
  const std::vector<std::uint16_t> zeros (1280 * 1024, 0);
  writeDepthPng (depth.path, zeros.data (), 1280, 1024);
  int w = 0, h = 0;
  const auto back = readDepthPng (depth.path, w, h);
  EXPECT_EQ (w, 1280);
  EXPECT_EQ (h, 1024);
  EXPECT_EQ (back, zeros);
  const std::vector<std::uint8_t> black (640 * 480 * 3, 0);
  writeRgbPng (rgb.path, black.data (), 640, 480);
  const auto rgb_back = readRgbPng (rgb.path, w, h);
  EXPECT_EQ (w, 640);
  EXPECT_EQ (h, 480);
  EXPECT_EQ (rgb_back, black);
}
