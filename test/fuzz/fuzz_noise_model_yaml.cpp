/*
 * Fuzz target: the noise model YAML (src/io/noise_model_io.cpp), as pcl_texlet_extract
 * --noise-model and the model lab read it. A model that loads must write back to YAML that loads
 * to the same parameters, and must give a finite sigma at a valid depth or throw.
 */
#include "fuzz_input_file.h"

#include <pcl_texlet/io/noise_model_io.h>
#include <pcl/exceptions.h>

#include <cmath>
#include <cstdio>

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  const std::string text (reinterpret_cast<const char *> (data), size);
  pcl::texlet::NoiseModel model;
  try
  {
    model = pcl::texlet::parseNoiseModelYaml (text, "fuzz input");
  }
  catch (const pcl::PCLException &)
  {
    return 0;
  }
  // Round trip: what was loaded is written and loaded again, with every parameter kept.
  const std::string yaml = pcl::texlet::noiseModelToYaml (model);
  const pcl::texlet::NoiseModel again = pcl::texlet::parseNoiseModelYaml (yaml, "round trip");
  if (again.terms ().size () != model.terms ().size ())
    std::abort ();
  for (std::size_t i = 0; i < model.terms ().size (); ++i)
  {
    const auto a = model.terms ()[i]->parameters (), b = again.terms ()[i]->parameters ();
    if (a.size () != b.size ())
      std::abort ();
    for (std::size_t k = 0; k < a.size (); ++k)
      if (!(a[k] == b[k]))
      {
        std::fprintf (stderr, "round trip changed %s parameter %zu: %.17g -> %.17g\n",
                      model.terms ()[i]->name ().c_str (), k, a[k], b[k]);
        std::abort ();
      }
  }
  // Evaluating the model anywhere in the image at ordinary depths must not crash.
  pcl::texlet::PixelContext ctx;
  for (double depth : {500.0, 1500.0, 4000.0})
  {
    ctx.u = 320, ctx.v = 240, ctx.radius_px = 100, ctx.depth_mm = depth;
    try
    {
      (void) model.moments (ctx);
    }
    catch (const pcl::PCLException &)
    {
    }
  }
  return 0;
}
