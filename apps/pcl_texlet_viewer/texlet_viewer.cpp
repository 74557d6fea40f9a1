#include "texlet_viewer.h"

#include "../common/app_main.h"
#include "texlet_backend.h"

#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/filters/filter.h>
#include <pcl/visualization/interactor_style.h>

#include <vtkObjectFactory.h>
#include <vtkPNGWriter.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace fs = std::filesystem;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::UncertaintyMethod;
using pcl_texlet_app::InputError;
using pcl_texlet_app::pclMessage;

namespace pcl_texlet_viewer
{

namespace
{

const char *const kName = "pcl_texlet_viewer";

/** Whether \a keysym is one of the viewer's keys (keyBindings). */
bool
isViewerKey (const std::string &keysym)
{
  for (const auto &b : keyBindings ())
    if (std::find (b.keysyms.begin (), b.keysyms.end (), keysym) != b.keysyms.end ())
      return true;
  return false;
}

/** PCL's interactor style, but the viewer's keys go to the keyboard callback only: PCL would
  * otherwise also act on them (p turns every actor, the discs too, into points; +/- change
  * the point size; c, f, g, u, h have their own meanings). Other keys (q, r, j, mouse) keep
  * PCL's meaning.
  */
class ViewerInteractorStyle : public pcl::visualization::PCLVisualizerInteractorStyle
{
public:
  static ViewerInteractorStyle *
  New ();
  vtkTypeMacro (ViewerInteractorStyle, pcl::visualization::PCLVisualizerInteractorStyle);

protected:
  bool
  viewerKey () const
  {
    return Interactor && Interactor->GetKeySym () && !Interactor->GetControlKey () && !Interactor->GetAltKey () &&
           isViewerKey (Interactor->GetKeySym ());
  }

  void
  OnKeyDown () override
  {
    if (!viewerKey ())
      return Superclass::OnKeyDown ();
    keyboard_signal_ (pcl::visualization::KeyboardEvent (true, Interactor->GetKeySym (), Interactor->GetKeyCode (),
                                                         false, false, Interactor->GetShiftKey () != 0));
  }

  void
  OnChar () override
  {
    if (!viewerKey ())
      Superclass::OnChar (); // VTK's own char keys (e.g. w, s) as pcl_viewer has them
  }
};
vtkStandardNewMacro (ViewerInteractorStyle);

} // namespace

Layers
Layers::parse (const std::string &list)
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

const std::vector<KeyBinding> &
keyBindings ()
{
  static const std::vector<KeyBinding> bindings = {
      {{"c"}, "c", "toggle the point cloud"},
      {{"t"}, "t", "toggle the texlet discs"},
      {{"n"}, "n", "toggle the normals"},
      {{"p"}, "p", "toggle the Sigma_P axes (red)"},
      {{"u"}, "u", "toggle the Sigma_N axes (green)"},
      {{"plus", "KP_Add"}, "+", "grid spacing up (fewer texlets)"},
      {{"minus", "KP_Subtract"}, "-", "grid spacing down (more texlets)"},
      {{"bracketright"}, "]", "neighbourhood radius up"},
      {{"bracketleft"}, "[", "neighbourhood radius down"},
      {{"f"}, "f", "next plane fit (pca, svd, averaging)"},
      {{"m"}, "m", "next uncertainty method (montecarlo, analytic, none)"},
      {{"asterisk", "KP_Multiply"}, "*", "uncertainty axes twice as long"},
      {{"slash", "KP_Divide"}, "/", "uncertainty axes half as long"},
      {{"g"}, "g", "switch the CPU / GPU backend"},
      {{"space"}, "space", "pause or play a recording"},
      {{"h"}, "h", "this help"},
  };
  return bindings;
}

std::string
keyHelp ()
{
  std::ostringstream s;
  s << "pcl_texlet_viewer keys:\n";
  for (const auto &b : keyBindings ())
    s << "  " << std::left << std::setw (6) << b.label << b.action << "\n";
  s << "  q     quit (other keys and the mouse as in pcl_viewer: r reset camera, j screenshot, ...)\n";
  return s.str ();
}

TexletViewer::TexletViewer (FrameSource::Ptr source, const pcl::texlet::TexletParameters &params, const Layers &layers,
                            const LayerScales &scales, bool interactive, bool gpu, int width, int height,
                            std::ostream &messages)
  : source_ (std::move (source)), params_ (params), layers_ (layers), scales_ (scales), interactive_ (interactive),
    gpu_ (gpu), height_ (height), messages_ (messages)
{
  int argc = 0;
  char **argv = nullptr;
  // PCLVisualizer keeps its own reference to the style (a vtkSmartPointer member); New()'s
  // reference is released here, else the style and everything it holds outlive the viewer
  // (LeakSanitizer found this).
  vtkSmartPointer<pcl::visualization::PCLVisualizerInteractorStyle> style;
  if (interactive)
    style = vtkSmartPointer<ViewerInteractorStyle>::New ();
  else
    style = vtkSmartPointer<pcl::visualization::PCLVisualizerInteractorStyle>::New ();
  // Off screen (not interactive), rendering goes to the X server given by DISPLAY; under Xvfb
  // that is off screen.
  vis_ = std::make_unique<pcl::visualization::PCLVisualizer> (argc, argv, kName, style.Get (), interactive);
  vis_->setSize (width, height);
  vis_->setBackgroundColor (0, 0, 0);
  vis_->addText ("", 10, height - 24, 14, 1, 1, 1, "status"); // top left: PCL's FPS counter is bottom left
  if (interactive)
    vis_->registerKeyboardCallback ([this] (const pcl::visualization::KeyboardEvent &e) { onKey (e); });
}

bool
TexletViewer::update (bool advance)
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
TexletViewer::spin ()
{
  messages_ << keyHelp () << std::flush;
  while (!vis_->wasStopped ())
  {
    update (playing_);
    vis_->spinOnce (30);
  }
}

void
TexletViewer::screenshot (const std::string &path)
{
  if (!update (true))
    throw InputError ("no frame to render from " + source_->describe ());
  vis_->getRenderWindow ()->Render ();
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New ();
  grab->SetInput (vis_->getRenderWindow ());
  grab->ReadFrontBufferOff ();
  grab->Update ();
  pcl::texlet::AtomicFile file (path);
  auto writer = vtkSmartPointer<vtkPNGWriter>::New ();
  writer->SetFileName (file.temporaryPath ().c_str ());
  writer->SetInputConnection (grab->GetOutputPort ());
  writer->Write ();
  std::error_code ec;
  if (writer->GetErrorCode () != 0 || !fs::is_regular_file (file.temporaryPath (), ec))
    throw InputError ("cannot write screenshot '" + path + "'");
  file.commit ();
  messages_ << status_ << "\nscreenshot: " << path << std::endl;
}

vtkActor *
TexletViewer::layerActor (const std::string &name) const
{
  const auto it = actors_.find (name);
  if (it == actors_.end ())
    return nullptr;
  vtkRenderer *renderer = vis_->getRendererCollection ()->GetFirstRenderer ();
  return renderer->HasViewProp (it->second) ? it->second.Get () : nullptr;
}

vtkActor *
TexletViewer::cloudActor () const
{
  const auto actors = vis_->getCloudActorMap ();
  const auto it = actors->find ("cloud");
  return it == actors->end () ? nullptr : it->second.actor.Get ();
}

void
TexletViewer::compute ()
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
    messages_ << "GPU backend failed (" << e.what () << "); back on the CPU backend" << std::endl;
    gpu_ = false;
    computeTexlets (frame_.cloud, frame_.camera, params_, false, *out);
  }
  ms_ = std::chrono::duration<double, std::milli> (std::chrono::steady_clock::now () - t0).count ();
  texlets_ = out;
}

void
TexletViewer::setActor (const std::string &name, vtkSmartPointer<vtkActor> actor, bool visible)
{
  vtkRenderer *renderer = vis_->getRendererCollection ()->GetFirstRenderer ();
  if (actors_.count (name))
    renderer->RemoveActor (actors_[name]);
  actors_[name] = actor;
  actor->SetVisibility (visible);
  renderer->AddActor (actor);
}

void
TexletViewer::draw ()
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
    // A new cloud actor per frame, not PCLVisualizer::updatePointCloud: PCL 1.13's casts the
    // actor's vtkDataSetMapper to a vtkPolyDataMapper (pcl_visualizer.hpp:1597), undefined
    // behaviour that UBSan reports. Both convert the whole cloud; the point size the user chose
    // with PCL's +/- keys is carried over.
    double point_size = 1.0;
    if (vtkActor *old = cloudActor ())
      point_size = old->GetProperty ()->GetPointSize ();
    vis_->removePointCloud ("cloud");
    vis_->addPointCloud<pcl::PointXYZRGBA> (shown, colour, "cloud");
    vis_->setPointCloudRenderingProperties (pcl::visualization::PCL_VISUALIZER_POINT_SIZE, point_size, "cloud");
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
  const double fps =
      frames_drawn_++ ? 1000.0 / std::max (1.0, std::chrono::duration<double, std::milli> (now - last_draw_).count ())
                      : 0.0;
  last_draw_ = now;
  std::ostringstream s;
  s << std::fixed << std::setprecision (1) << frame_.name << "  |  " << valid << " texlets";
  if (!frame_.texlets)
    s << " in " << ms_ << " ms (" << (gpu_ ? "GPU" : "CPU") << ", spacing " << params_.spacing << ", radius "
      << params_.radius << ", " << pcl::texlet::toString (params_.fit) << ", "
      << pcl::texlet::toString (params_.uncertainty) << ")";
  if (interactive_)
    s << "  |  " << fps << " fps";
  status_ = s.str ();
  vis_->updateText (status_, 10, height_ - 24, 14, 1, 1, 1, "status");
}

void
TexletViewer::showCloud ()
{
  if (vtkActor *a = cloudActor ())
    a->SetVisibility (layers_.cloud);
}

void
TexletViewer::toggle (bool &flag, const std::string &actor)
{
  flag = !flag;
  if (actors_.count (actor))
    actors_[actor]->SetVisibility (flag);
}

void
TexletViewer::scaleAxes (double factor)
{
  scales_.sigma_p *= factor;
  scales_.sigma_n *= factor;
  dirty_ = true;
}

template <typename F> void
TexletViewer::changeParameters (F &&f)
{
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
    messages_ << pclMessage (ex.what ()) << "; unchanged" << std::endl;
  }
}

void
TexletViewer::switchBackend ()
{
  std::string why;
  if (!gpu_ && !gpuAvailable (why))
  {
    messages_ << "GPU backend not available: " << why << "; staying on the CPU backend" << std::endl;
    return;
  }
  gpu_ = !gpu_;
  dirty_ = true;
  messages_ << "texlets on the " << (gpu_ ? "GPU" : "CPU") << " backend" << std::endl;
}

void
TexletViewer::onKey (const pcl::visualization::KeyboardEvent &e)
{
  if (!e.keyDown ())
    return;
  const std::string key = e.getKeySym ();
  if (key == "c")
  {
    layers_.cloud = !layers_.cloud;
    showCloud ();
  }
  else if (key == "t") toggle (layers_.texlets, "texlets");
  else if (key == "n") toggle (layers_.normals, "normals");
  else if (key == "p") toggle (layers_.sigma_p, "sigma_p");
  else if (key == "u") toggle (layers_.sigma_n, "sigma_n");
  else if (key == "f")
    changeParameters ([] (auto &p) { p.fit = static_cast<PlaneFitMethod> ((static_cast<int> (p.fit) + 1) % 3); });
  else if (key == "m")
    changeParameters (
        [] (auto &p) { p.uncertainty = static_cast<UncertaintyMethod> ((static_cast<int> (p.uncertainty) + 2) % 3); });
  else if (key == "plus" || key == "KP_Add") changeParameters ([] (auto &p) { ++p.spacing; });
  else if (key == "minus" || key == "KP_Subtract") changeParameters ([] (auto &p) { --p.spacing; });
  else if (key == "bracketright") changeParameters ([] (auto &p) { ++p.radius; });
  else if (key == "bracketleft") changeParameters ([] (auto &p) { --p.radius; });
  else if (key == "asterisk" || key == "KP_Multiply") scaleAxes (2.0);
  else if (key == "slash" || key == "KP_Divide") scaleAxes (0.5);
  else if (key == "g") switchBackend ();
  else if (key == "space") playing_ = !playing_;
  else if (key == "h") messages_ << keyHelp () << std::flush;
}

} // namespace pcl_texlet_viewer
