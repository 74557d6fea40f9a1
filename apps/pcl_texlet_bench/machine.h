/*
 * pcl_texlet_bench: the machine a run measures on, for the JSON and the tables.
 */
#pragma once

#include <cmath>
#include <fstream>
#include <string>

namespace pcl_texlet_bench
{

/** \brief The processor's model name (/proc/cpuinfo); "unknown" elsewhere. */
inline std::string
cpuModel ()
{
  std::ifstream f ("/proc/cpuinfo");
  std::string line;
  while (std::getline (f, line))
    if (line.rfind ("model name", 0) == 0)
      return line.substr (line.find (':') + 2);
  return "unknown";
}

/** \brief The 1-minute load average (/proc/loadavg); NaN elsewhere. */
inline double
loadAverage ()
{
  std::ifstream f ("/proc/loadavg");
  double l = NAN;
  f >> l;
  return l;
}

} // namespace pcl_texlet_bench
