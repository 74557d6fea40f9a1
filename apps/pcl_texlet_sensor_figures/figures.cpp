#include "figures.h"
#include "measurements.h"

#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/kernels/structured_light.h>
#include <pcl_texlet/noise/pixel_context.h>

#include <algorithm>
#include <cmath>
#include <sstream>

using namespace pcl::texlet;
using namespace pcl::texlet::sim;

namespace pcl_texlet_sensor_figures
{

Figures::Figures (const Options &o, const std::filesystem::path &out)
  : o_ (o), out_ (out), model_ (DepthSensor::kinect (o.width, o.height))
{
  fb_ = model_.fb ();
}

SimulationSettings
Figures::settings () const
{
  SimulationSettings s;
  s.seed = o_.seed;
  return s;
}

KinectSimulator
Figures::simulator (const SceneSetup &setup, const SimulationSettings &s) const
{
  return KinectSimulator (setup.scene, setup.sensors (model_), s, o_.threads);
}

KinectSimulator
Figures::simulator (const Scene::ConstPtr &scene, const SimulationSettings &s) const
{
  return KinectSimulator (scene, {model_}, s, o_.threads);
}

std::vector<DepthFrame>
Figures::frames (const KinectSimulator &sim) const
{
  return sim.simulate (0, 0, o_.frames);
}

bool
Figures::central (int u, int v) const
{
  return std::hypot (u - model_.cx, v - model_.cy) < std::max (2.0, 0.05 * model_.width);
}

double
Figures::radius (int u, int v) const
{
  return std::hypot (u - model_.cx, v - model_.cy);
}

double
Figures::paperSigma (int u, int v, double depth_mm) const
{
  PixelContext ctx;
  ctx.u = u;
  ctx.v = v;
  ctx.radius_px = radius (u, v);
  ctx.depth_mm = depth_mm;
  return paper_.sigmaMm (ctx);
}

double
Figures::offsetDepth (double z_mm, double offset_px) const
{
  return 1000.0 * kernels::depthFromDisparity (kernels::disparityFromDepth (1e-3 * z_mm, fb_) + offset_px, fb_);
}

double
Figures::radialBin () const
{
  return std::max (1.0, model_.width / 64.0);
}

void
Figures::note (const std::string &figure, const std::string &key, double value, int precision)
{
  summary_[figure + "." + key] = num (value, precision);
}

void
Figures::write (const std::string &file, const std::string &text) const
{
  writeFileAtomically ((out_ / file).string (), text);
}

void
Figures::writeSummary () const
{
  std::ostringstream s;
  s << "# pcl_texlet_sensor_figures: " << o_.width << "x" << o_.height << ", " << o_.frames << " frames, seed "
    << o_.seed << ", f " << model_.fx << " px, baseline " << model_.baseline_m << " m\n";
  for (const auto &kv : summary_)
    s << kv.first << " = " << kv.second << "\n";
  write ("summary.txt", s.str ());
}

} // namespace pcl_texlet_sensor_figures
