/*
 * pcl_texlet_viewer: the viewer itself, one frame at a time on a PCLVisualizer, and its keys.
 *
 * Kept out of main.cpp so that the tests drive it: they press keys through the visualizer's
 * VTK interactor (the path a real key press takes) and check what each key did to the layers
 * in the renderer and to the texlets of the next frame (test/test_viewer_keys.cpp).
 */
#pragma once

#include "frame_sources.h"
#include "texlet_layers.h"

#include <pcl_texlet/features/texlet_parameters.h>

#include <pcl/visualization/keyboard_event.h>
#include <pcl/visualization/pcl_visualizer.h>

#include <vtkActor.h>
#include <vtkSmartPointer.h>

#include <chrono>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace pcl_texlet_viewer
{

/** \brief Which layers are drawn. */
struct Layers
{
  bool cloud = true, texlets = true, normals = false, sigma_p = false, sigma_n = false;

  /** \brief "cloud,texlets,normals,sigma_p,sigma_n" (any subset).
    * \throws pcl_texlet_app::InputError naming an unknown layer
    */
  static Layers
  parse (const std::string &list);
};

/** \brief One key of the viewer: what to press (X key symbols) and what it does. */
struct KeyBinding
{
  std::vector<std::string> keysyms; ///< e.g. {"plus", "KP_Add"}
  std::string label;                ///< as the help shows it, e.g. "+"
  std::string action;               ///< what it does
};

/** \brief Every key the viewer handles itself, in the order the help lists them. */
const std::vector<KeyBinding> &
keyBindings ();

/** \brief The help the viewer prints at start and on `h`: every key of keyBindings (). */
std::string
keyHelp ();

/** \brief The viewer: a PCLVisualizer showing one frame's cloud and texlet layers; texlets are
  * recomputed when the frame or a setting changes (the next update ()).
  *
  * Interactive, its keys (keyBindings) reach it through the visualizer's keyboard callback.
  * The interactor style passes them to the viewer only: PCL's own meaning of those keys
  * (p: draw every actor as points, c: print the camera, +/-: point size, f: fly to, g: grid,
  * u: lookup table, h: PCL's help) would otherwise act too.
  */
class TexletViewer
{
public:
  /** \param interactive a window with an interactor and the keys; false: off-screen rendering
    *        for screenshot ()
    * \param messages where help and key messages go
    */
  TexletViewer (FrameSource::Ptr source, const pcl::texlet::TexletParameters &params, const Layers &layers,
                const LayerScales &scales, bool interactive, bool gpu, int width, int height,
                std::ostream &messages = std::cout);

  /** \brief Reads the next frame (if \a advance or none yet), recomputes and redraws if
    * anything changed. \return whether anything changed.
    */
  bool
  update (bool advance);

  /** \brief The interactive loop until the window is closed (or q). */
  void
  spin ();

  /** \brief Renders off screen and writes a PNG through a temporary file. */
  void
  screenshot (const std::string &path);

  /** \brief What a key press does (the keyboard callback's handler). */
  void
  onKey (const pcl::visualization::KeyboardEvent &e);

  // State, for the status line and the tests.
  pcl::visualization::PCLVisualizer &
  visualizer () { return *vis_; }
  const Layers &
  layers () const { return layers_; }
  const pcl::texlet::TexletParameters &
  parameters () const { return params_; }
  const LayerScales &
  scales () const { return scales_; }
  /** \brief Whether texlets are computed on the GPU. */
  bool
  usingGpu () const { return gpu_; }
  /** \brief Whether a recording plays (space pauses). */
  bool
  playing () const { return playing_; }
  /** \brief The texlets drawn now. */
  const Texlets::ConstPtr &
  texlets () const { return texlets_; }
  /** \brief The status line shown at the top of the window. */
  const std::string &
  status () const { return status_; }
  /** \brief The actor of a texlet layer ("texlets", "normals", "sigma_p", "sigma_n") in the
    * renderer, or null if it is not there.
    */
  vtkActor *
  layerActor (const std::string &name) const;
  /** \brief The cloud's actor in the visualizer, or null. */
  vtkActor *
  cloudActor () const;

private:
  void
  compute ();
  void
  setActor (const std::string &name, vtkSmartPointer<vtkActor> actor, bool visible);
  void
  draw ();
  void
  showCloud ();
  void
  toggle (bool &flag, const std::string &actor);
  void
  scaleAxes (double factor);
  void
  switchBackend ();
  template <typename F> void
  changeParameters (F &&f);

  FrameSource::Ptr source_;
  pcl::texlet::TexletParameters params_;
  Layers layers_;
  LayerScales scales_;
  bool interactive_;
  bool gpu_; ///< texlets on the CUDA backend
  int height_;
  std::ostream &messages_;
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

} // namespace pcl_texlet_viewer
