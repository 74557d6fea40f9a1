/*
 * pcl_texlet_viewer: see texlets, live or from files, in the manner of pcl_viewer.
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 */
#include "../common/app_main.h"
#include "frame_sources.h"
#include "texlet_backend.h"
#include "texlet_layers.h"

#include <pcl_texlet/texlet_estimation.h>

#include <pcl/console/print.h>
#include <pcl/filters/filter.h>
#include <pcl/visualization/pcl_visualizer.h>

#include <CLI/CLI.hpp>

#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkWindowToImageFilter.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;
using namespace pcl_texlet_viewer;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::UncertaintyMethod;

using pcl_texlet_app::InputError;
using pcl_texlet_app::pclMessage;

namespace
{

const char *const kName = "pcl_texlet_viewer";

/** Which layers are drawn. */
struct Layers
{
  bool cloud = true, texlets = true, normals = false, sigma_p = false, sigma_n = false;

  /** "cloud,texlets,normals,sigma_p,sigma_n" (any subset). */
  static Layers
  parse (const std::string &list)
  {
    Layers l;
    l.cloud = l.texlets = false;
    std::stringstream ss (list);
    std::string item;
    while (std::getline (ss, item, ','))
    {
      if (item == "cloud") l.cloud = true;
      else if (item == "texlets") l.texlets = true;
      else if (item == "normals") l.normals = true;
      else if (item == "sigma_p") l.sigma_p = true;
      else if (item == "sigma_n") l.sigma_n = true;
      else
        throw InputError ("--layers: unknown layer '" + item + "' (use cloud, texlets, normals, sigma_p, sigma_n)");
    }
    return l;
  }
};

const char *const kHelp =
    "pcl_texlet_viewer keys:\n"
    "  c  toggle the point cloud        t  toggle the texlet discs\n"
    "  n  toggle the normals            p  toggle Sigma_P axes (red)\n"
    "  u  toggle Sigma_N axes (green)   f  next plane fit (pca, svd, averaging)\n"
    "  m  next uncertainty (montecarlo, analytic, none)\n"
    "  +/-  grid spacing up/down        ]/[  neighbourhood radius up/down\n"
    "  */   uncertainty axes longer/shorter\n"
    "  g  CPU or GPU backend            space  pause or play a recording\n"
    "  h  this help                     q  quit\n";

/** The viewer: one frame at a time, texlets recomputed when the frame or a setting changes. */
class Viewer
{
public:
  Viewer (FrameSource::Ptr source, const pcl::texlet::TexletParameters &params, const Layers &layers,
          const LayerScales &scales, bool interactive, bool gpu, int width, int height)
    : source_ (std::move (source)), params_ (params), layers_ (layers), scales_ (scales), interactive_ (interactive),
      gpu_ (gpu), height_ (height)
  {
    if (interactive)
      vis_ = std::make_unique<pcl::visualization::PCLVisualizer> (kName);
    else
    {
      int argc = 0;
      char **argv = nullptr;
      vis_ = std::make_unique<pcl::visualization::PCLVisualizer> (argc, argv, kName,
                                                                  pcl::visualization::PCLVisualizerInteractorStyle::New (),
                                                                  false);
      // (Rendering goes to the X server given by DISPLAY; under Xvfb that is off screen.)
    }
    vis_->setSize (width, height);
    vis_->setBackgroundColor (0, 0, 0);
    vis_->addText ("", 10, height - 24, 14, 1, 1, 1, "status"); // top left: PCL's FPS counter is bottom left
    if (interactive)
      vis_->registerKeyboardCallback ([this] (const pcl::visualization::KeyboardEvent &e) { onKey (e); });
  }

  /** Reads the next frame (if any), recomputes and redraws. \return whether anything changed. */
  bool
  update (bool advance)
  {
    bool changed = dirty_;
    if (advance || !have_frame_)
    {
      Frame f;
      if (source_->next (f))
      {
        frame_ = f;
        have_frame_ = changed = true;
      }
    }
    if (!changed || !have_frame_)
      return false;
    dirty_ = false;
    compute ();
    draw ();
    return true;
  }

  void
  spin ()
  {
    std::cout << kHelp << std::flush;
    while (!vis_->wasStopped ())
    {
      update (playing_);
      vis_->spinOnce (30);
    }
  }

  /** Renders off screen and writes a PNG through a temporary file. */
  void
  screenshot (const std::string &path)
  {
    if (!update (true))
      throw InputError ("no frame to render from " + source_->describe ());
    vis_->getRenderWindow ()->Render ();
    auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New ();
    grab->SetInput (vis_->getRenderWindow ());
    grab->ReadFrontBufferOff ();
    grab->Update ();
    const std::string tmp = path + ".tmp.png";
    auto writer = vtkSmartPointer<vtkPNGWriter>::New ();
    writer->SetFileName (tmp.c_str ());
    writer->SetInputConnection (grab->GetOutputPort ());
    writer->Write ();
    std::error_code ec;
    if (writer->GetErrorCode () != 0 || !fs::is_regular_file (tmp))
    {
      fs::remove (tmp, ec);
      throw InputError ("cannot write screenshot '" + path + "'");
    }
    fs::rename (tmp, path, ec);
    if (ec)
      throw InputError ("cannot write screenshot '" + path + "': " + ec.message ());
    std::cout << status_ << "\nscreenshot: " << path << std::endl;
  }

private:
  void
  compute ()
  {
    if (frame_.texlets)
    {
      texlets_ = frame_.texlets;
      ms_ = 0;
      return;
    }
    auto out = std::make_shared<Texlets> ();
    const auto t0 = std::chrono::steady_clock::now ();
    try
    {
      computeTexlets (frame_.cloud, frame_.camera, params_, gpu_, *out);
    }
    catch (const pcl::PCLException &e)
    {
      throw InputError (frame_.name + ": " + pclMessage (e.what ()));
    }
    catch (const std::runtime_error &e) // a CUDA error: say so and go on on the CPU
    {
      if (!gpu_)
        throw;
      std::cout << "GPU backend failed (" << e.what () << "); back on the CPU" << std::endl;
      gpu_ = false;
      computeTexlets (frame_.cloud, frame_.camera, params_, false, *out);
    }
    ms_ = std::chrono::duration<double, std::milli> (std::chrono::steady_clock::now () - t0).count ();
    texlets_ = out;
  }

  void
  setActor (const std::string &name, vtkSmartPointer<vtkActor> actor, bool visible)
  {
    vtkRenderer *renderer = vis_->getRendererCollection ()->GetFirstRenderer ();
    if (actors_.count (name))
      renderer->RemoveActor (actors_[name]);
    actors_[name] = actor;
    actor->SetVisibility (visible);
    renderer->AddActor (actor);
  }

  void
  draw ()
  {
    if (frame_.cloud)
    {
      // Only the valid points, in the camera frame the texlets are in: PCLVisualizer would apply
      // the file's VIEWPOINT pose (PCL's grabber writes a 180-degree turn about x).
      auto shown = std::make_shared<Cloud> ();
      pcl::Indices kept;
      pcl::removeNaNFromPointCloud (*frame_.cloud, *shown, kept);
      shown->sensor_origin_.setZero ();
      shown->sensor_orientation_.setIdentity ();
      pcl::visualization::PointCloudColorHandlerRGBField<pcl::PointXYZRGBA> colour (shown);
      if (!vis_->updatePointCloud<pcl::PointXYZRGBA> (shown, colour, "cloud"))
        vis_->addPointCloud<pcl::PointXYZRGBA> (shown, colour, "cloud");
      showCloud ();
    }
    setActor ("texlets", makeDiscActor (*texlets_, scales_), layers_.texlets);
    setActor ("normals", makeNormalActor (*texlets_, scales_), layers_.normals);
    setActor ("sigma_p", makeSigmaPActor (*texlets_, scales_), layers_.sigma_p);
    setActor ("sigma_n", makeSigmaNActor (*texlets_, scales_), layers_.sigma_n);
    if (!camera_set_)
    {
      // The sensor's own view: at the origin, looking along +z, image rows downward.
      vis_->setCameraPosition (0, 0, 0, 0, 0, 1, 0, -1, 0);
      vis_->setCameraFieldOfView (0.87); // about a Kinect's vertical field of view
      camera_set_ = true;
    }
    vis_->getRendererCollection ()->GetFirstRenderer ()->ResetCameraClippingRange ();

    std::size_t valid = 0;
    for (const auto &t : *texlets_)
      valid += std::isfinite (t.x) ? 1 : 0;
    const auto now = std::chrono::steady_clock::now ();
    const double fps = frames_drawn_++ ? 1000.0 / std::max (1.0, std::chrono::duration<double, std::milli> (now - last_draw_).count ()) : 0.0;
    last_draw_ = now;
    std::ostringstream s;
    s << std::fixed << std::setprecision (1) << frame_.name << "  |  " << valid << " texlets";
    if (!frame_.texlets)
      s << " in " << ms_ << " ms (" << (gpu_ ? "GPU" : "CPU") << ", spacing " << params_.spacing << ", radius " << params_.radius << ", "
        << pcl::texlet::toString (params_.fit) << ", " << pcl::texlet::toString (params_.uncertainty) << ")";
    if (interactive_)
      s << "  |  " << fps << " fps";
    status_ = s.str ();
    vis_->updateText (status_, 10, height_ - 24, 14, 1, 1, 1, "status");
  }

  void
  showCloud ()
  {
    const auto actors = vis_->getCloudActorMap ();
    const auto it = actors->find ("cloud");
    if (it != actors->end ())
      it->second.actor->SetVisibility (layers_.cloud);
  }

  void
  toggle (bool &flag, const std::string &actor)
  {
    flag = !flag;
    if (actors_.count (actor))
      actors_[actor]->SetVisibility (flag);
  }

  void
  onKey (const pcl::visualization::KeyboardEvent &e)
  {
    if (!e.keyDown ())
      return;
    const std::string key = e.getKeySym ();
    const auto change = [this] (auto &&f) {
      pcl::texlet::TexletParameters p = params_;
      f (p);
      try
      {
        pcl::texlet::validate (p);
        params_ = p;
        dirty_ = true;
      }
      catch (const pcl::PCLException &ex)
      {
        std::cout << pclMessage (ex.what ()) << std::endl;
      }
    };
    if (key == "c")
    {
      layers_.cloud = !layers_.cloud;
      showCloud ();
    }
    else if (key == "t") toggle (layers_.texlets, "texlets");
    else if (key == "n") toggle (layers_.normals, "normals");
    else if (key == "p") toggle (layers_.sigma_p, "sigma_p");
    else if (key == "u") toggle (layers_.sigma_n, "sigma_n");
    else if (key == "f") change ([] (auto &p) { p.fit = static_cast<PlaneFitMethod> ((static_cast<int> (p.fit) + 1) % 3); });
    else if (key == "m")
      change ([] (auto &p) { p.uncertainty = static_cast<UncertaintyMethod> ((static_cast<int> (p.uncertainty) + 2) % 3); });
    else if (key == "plus" || key == "KP_Add") change ([] (auto &p) { ++p.spacing; });
    else if (key == "minus" || key == "KP_Subtract") change ([] (auto &p) { --p.spacing; });
    else if (key == "bracketright") change ([] (auto &p) { ++p.radius; });
    else if (key == "bracketleft") change ([] (auto &p) { --p.radius; });
    else if (key == "asterisk" || key == "KP_Multiply") { scaleAxes (2.0); }
    else if (key == "slash" || key == "KP_Divide") { scaleAxes (0.5); }
    else if (key == "g")
    {
      std::string why;
      if (!gpu_ && !gpuAvailable (why))
        std::cout << "GPU backend: " << why << "; staying on the CPU" << std::endl;
      else
      {
        gpu_ = !gpu_;
        dirty_ = true;
      }
    }
    else if (key == "space") playing_ = !playing_;
    else if (key == "h") std::cout << kHelp << std::flush;
  }

  void
  scaleAxes (double factor)
  {
    scales_.sigma_p *= factor;
    scales_.sigma_n *= factor;
    dirty_ = true;
  }

  FrameSource::Ptr source_;
  pcl::texlet::TexletParameters params_;
  Layers layers_;
  LayerScales scales_;
  bool interactive_;
  bool gpu_; ///< texlets on the CUDA backend
  int height_;
  std::unique_ptr<pcl::visualization::PCLVisualizer> vis_;
  std::map<std::string, vtkSmartPointer<vtkActor>> actors_;
  Frame frame_;
  Texlets::ConstPtr texlets_;
  bool have_frame_ = false, dirty_ = false, camera_set_ = false, playing_ = true;
  double ms_ = 0;
  std::size_t frames_drawn_ = 0;
  std::chrono::steady_clock::time_point last_draw_;
  std::string status_;
};

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
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv, std::string ("\n") + kHelp))
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
    Viewer viewer (std::move (source), params, shown, scales, screenshot.empty (), gpu, width, height);
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
