/*
 * Fuzz target: the simulator's configuration YAML (parseSimulationConfig,
 * src/simulation/simulation_config.cpp), as pcl_texlet_sim --config reads it.
 */
#include <pcl_texlet/simulation/simulation_config.h>
#include <pcl/exceptions.h>

#include <cstdint>
#include <string>

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  const std::string text (reinterpret_cast<const char *> (data), size);
  pcl::texlet::sim::SimulationSettings settings;
  try
  {
    pcl::texlet::sim::parseSimulationConfig (text, settings, "fuzz input");
  }
  catch (const pcl::PCLException &)
  {
  }
  return 0;
}
