/*
 * pcl_texlet_bench: the studies, one a file. Each prints its table on stdout and returns its
 * figures for the JSON; the ones with gnuplot data return that text too.
 */
#pragma once

#include "bench_input.h"
#include "methods.h"
#include "options.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pcl_texlet_bench
{

/** \brief \a methods timed interleaved at the same hexagonal centres of \a in, against
  * NormalEstimationOMP over the same pixel disc (timing_study.cpp).
  */
nlohmann::json
runTiming (const Options &o, const Input &in, const std::vector<MethodSpec> &methods);

/** \brief The angle of each method's normals to the true ones on the simulated scenes, near edges
  * and away from them (accuracy_study.cpp).
  */
nlohmann::json
runAccuracy (const Options &o, const std::vector<MethodSpec> &methods);

/** \brief The paper's Table 1 measured on \a in beside the paper's figures (table1_study.cpp). */
nlohmann::json
runTable1 (const Options &o, const Input &in);

/** \brief The paper's Fig. 8: the plane fits' normal error against depth noise; \a dat receives
  * the gnuplot data (fig8_study.cpp).
  */
nlohmann::json
runFig8 (const Options &o, std::string &dat);

/** \brief Time against the texlet count (spacing) and the neighbourhood size (radius), with
  * least-squares lines; \a dat_spacing and \a dat_radius receive the gnuplot data (scaling_study.cpp).
  */
nlohmann::json
runScaling (const Options &o, const Input &in, std::string &dat_spacing, std::string &dat_radius);

} // namespace pcl_texlet_bench
