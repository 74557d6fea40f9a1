/*
 * pcl_texlet_bench: what the command line sets, shared by the studies.
 */
#pragma once

#include "methods.h"

#include <iostream>
#include <string>
#include <vector>

#ifndef PCL_TEXLET_DEFAULT_FRAME
#define PCL_TEXLET_DEFAULT_FRAME ""
#endif

namespace pcl_texlet_bench
{

const char *const kName = "pcl_texlet_bench";

struct Options
{
  std::string input = PCL_TEXLET_DEFAULT_FRAME;
  std::string scene; // simulated input instead of a PCD
  int sim_width = 640, sim_height = 480;
  Setup setup;
  std::vector<std::string> fits = {"pca", "svd", "averaging"};
  int repetitions = 15, warmup = 2;
  bool organized_knn = true;
  bool timing = true, accuracy = true, table1 = false, fig8 = false, scaling = false;
  int table1_reps = 5, scaling_reps = 5, fig8_runs = 100;
  std::string json_path, data_dir;
  std::string noise_model; ///< --noise-model YAML, or empty: the paper's
  bool quiet = false;
};

/** \brief A progress line on stderr, unless --quiet. */
inline void
progress (const Options &o, const std::string &line)
{
  if (!o.quiet)
    std::cerr << kName << ": " << line << std::endl;
}

} // namespace pcl_texlet_bench
