/*
 * pcl_texlet_viewer: see texlets, live or from files, in the manner of pcl_viewer.
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 */
#include "../common/app_main.h"
#include "frame_sources.h"
#include "texlet_backend.h"
#include "texlet_layers.h"
#include "texlet_viewer.h"

#include <pcl_texlet/features/texlet_estimation.h>

#include <CLI/CLI.hpp>

#include <filesystem>

namespace fs = std::filesystem;
using namespace pcl_texlet_viewer;

using pcl_texlet_app::InputError;
using pcl_texlet_app::pclMessage;

namespace
{

const char *const kName = "pcl_texlet_viewer";

/** The bundled real frames: beside the installed binary, else in the source tree. */
std::string
bundledFrames ()
{
  for (const std::string &dir : {std::string (PCL_TEXLET_INSTALLED_DATA_DIR), std::string (PCL_TEXLET_SOURCE_DATA_DIR)})
  {
    const fs::path p = fs::path (dir) / "kinect" / "grabber_sequence" / "pcd";
    if (fs::is_directory (p))
      return p.string ();
  }
  throw InputError ("no input given, no sensor connected, and the bundled frames were not found");
}

int
run (int argc, char **argv)
{
  std::string input, screenshot, fit = "pca", uncertainty = "montecarlo", layers = "cloud,texlets";
  pcl::texlet::TexletParameters params;
  LayerScales scales;
  int width = 1024, height = 768;
  bool gpu = false;
  CLI::App app ("View texlets live or from files, in the manner of pcl_viewer.\n"
                "INPUT: an organised PCD file, a texlet PCD file (from pcl_texlet_extract), a folder of PCD files, a\n"
                "recording folder, a folder of PCL grabber TIFFs, a .oni file, or 'sensor'. Without INPUT: the first OpenNI2 sensor, else the bundled "
                "real frames.",
                kName);
  app.add_option ("INPUT", input, "what to show");
  app.add_option ("--screenshot", screenshot, "render one frame off screen to this PNG and exit");
  app.add_option ("--layers", layers, "layers shown at start: cloud,texlets,normals,sigma_p,sigma_n")->capture_default_str ();
  app.add_option ("-s,--spacing", params.spacing, "hexagonal grid spacing, pixels")->capture_default_str ();
  app.add_option ("-r,--radius", params.radius, "neighbourhood radius, pixels")->capture_default_str ();
  app.add_option ("-f,--fit", fit, "plane fit: pca, svd, averaging")->capture_default_str ();
  app.add_option ("-u,--uncertainty", uncertainty, "uncertainty: montecarlo, analytic, none")->capture_default_str ();
  app.add_option ("--disc-scale", scales.disc, "disc radius / texlet radius")->capture_default_str ();
  app.add_option ("--sigma-scale", scales.sigma_p, "length of the Sigma_P axes in SDs")->capture_default_str ();
  app.add_flag ("--gpu", gpu, "start on the CUDA backend (key g switches)");
  app.add_option ("--size", width, "window width, pixels (height = 3/4 of it)")->capture_default_str ();
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv, "\n" + keyHelp ()))
    return 0;
  height = width * 3 / 4;
  try
  {
    params.fit = pcl::texlet::planeFitMethodFromString (fit);
    params.uncertainty = pcl::texlet::uncertaintyMethodFromString (uncertainty);
    pcl::texlet::validate (params);
    if (width < 64 || width > 8192)
      throw InputError ("--size " + std::to_string (width) + " is not a sensible window width");
    if (!(scales.disc > 0) || !(scales.sigma_p > 0))
      throw InputError ("--disc-scale and --sigma-scale must be positive");
    const Layers shown = Layers::parse (layers);
    if (!screenshot.empty () && !fs::exists (fs::absolute (screenshot).parent_path ()))
      throw InputError ("the folder that should hold '" + screenshot + "' does not exist");

    FrameSource::Ptr source;
    if (!input.empty ())
      source = openSource (input);
    else if (!(source = openFirstSensor ()))
      source = openSource (bundledFrames ());

    std::string why;
    if (gpu && !gpuAvailable (why))
      throw InputError ("--gpu: " + why);
    TexletViewer viewer (std::move (source), params, shown, scales, screenshot.empty (), gpu, width, height);
    if (screenshot.empty ())
      viewer.spin ();
    else
      viewer.screenshot (screenshot);
  }
  catch (const pcl::PCLException &e)
  {
    throw InputError (pclMessage (e.what ()));
  }
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
