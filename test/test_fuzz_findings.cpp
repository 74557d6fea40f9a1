/*
 * Regression tests for what the fuzz targets (test/fuzz/, docs/fuzzing.md) found: each input is
 * the minimised crashing input (also kept in the target's corpus), and each test checks the
 * documented failure, a pcl::PCLException naming the input and the problem, or the right result.
 */
#include <pcl_texlet/noise_model_io.h>
#include <pcl_texlet/simulator/simulation_config.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <string>

using namespace pcl::texlet;

namespace
{

/** Runs \a f, which must throw a pcl::PCLException whose message contains every one of \a parts. */
template <typename F> void
expectClearError (F f, std::initializer_list<std::string> parts)
{
  try
  {
    f ();
    ADD_FAILURE () << "no exception";
  }
  catch (const pcl::PCLException &e)
  {
    const std::string msg = e.what ();
    for (const auto &p : parts)
      EXPECT_NE (msg.find (p), std::string::npos) << "'" << msg << "' lacks '" << p << "'";
  }
  catch (const std::exception &e)
  {
    ADD_FAILURE () << "not a pcl::PCLException: " << e.what ();
  }
}

} // namespace

// fuzz_noise_model_yaml: a list as a key (`? - name: ...`, YAML's complex key) made yaml-cpp's
// YAML::TypedBadConversion escape the loader instead of pcl::IOException.
TEST (FuzzFindings, NoiseModelYamlComplexKeyIsAClearError)
{
  expectClearError ([] { parseNoiseModelYaml ("min_sigma_mm: 0.1\nterms:\n? - name: polynomial\n", "model.yaml"); },
                    {"model.yaml", "key", "list or map"});
  // The same inside a term: as its name, as one of its keys, as a parameter's name.
  expectClearError ([] { parseNoiseModelYaml ("terms:\n  - name: [polynomial]\n", "model.yaml"); },
                    {"model.yaml", "term 1's name"});
  expectClearError ([] { parseNoiseModelYaml ("terms:\n  - name: polynomial\n    ? [a]\n    : 1\n", "model.yaml"); },
                    {"model.yaml", "term 'polynomial'"});
  expectClearError ([] { parseNoiseModelYaml ("terms:\n  - name: polynomial\n    parameters: {[p00]: 1}\n", "m.yaml"); },
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
    expectClearError ([&] { sim::parseSimulationConfig (yaml, settings, "config.yaml"); },
                      {"config.yaml", "must be a plain name, not a list or map"});
    EXPECT_EQ (settings.seed, 7u) << "a bad file leaves the settings as they were";
  }
}
