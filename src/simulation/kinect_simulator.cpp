#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/kernels/depth_sensor.h>
#include <pcl_texlet/kernels/structured_light.h>
#include <pcl_texlet/noise/pixel_context.h>

#include <pcl_texlet/common/error_text.h>
#include <pcl_texlet/common/parallel_for.h>

#include <pcl/exceptions.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pcl
{
namespace texlet
{
namespace sim
{

namespace
{

std::string
frameName (std::uint32_t frame)
{
  char name[16];
  std::snprintf (name, sizeof (name), "%06u", frame);
  return name;
}

} // namespace

KinectSimulator::KinectSimulator (const Scene::ConstPtr &scene, const std::vector<DepthSensor> &sensors,
                                  const SimulationSettings &settings, unsigned threads)
  : scene_ (scene), sensors_ (sensors), settings_ (settings), threads_ (threads)
{
  if (!scene_)
    throw pcl::BadArgumentException ("KinectSimulator: the scene is null");
  if (sensors_.empty ())
    throw pcl::BadArgumentException ("KinectSimulator: no sensor given");
  for (std::size_t i = 0; i < sensors_.size (); ++i)
  {
    try
    {
      sensors_[i].validate ();
    }
    catch (const pcl::BadArgumentException &e)
    {
      throw pcl::BadArgumentException ("KinectSimulator: sensor " + std::to_string (i) + ": " + errorText (e));
    }
  }
  validate (settings_.effects);
  effects_ = generativeEffects (settings_.effects);
  truth_.resize (sensors_.size ());
  for (std::size_t i = 0; i < sensors_.size (); ++i)
    prepare (i);
}

int
KinectSimulator::numberOfThreads () const
{
  return threads_ > 0 ? static_cast<int> (threads_) : omp_get_max_threads ();
}

const DepthSensor &
KinectSimulator::sensor (std::size_t index) const
{
  if (index >= sensors_.size ())
    throw pcl::BadArgumentException ("KinectSimulator: sensor " + std::to_string (index) + " does not exist (there are " +
                                     std::to_string (sensors_.size ()) + ")");
  return sensors_[index];
}

const SensorTruth &
KinectSimulator::truth (std::size_t index) const
{
  sensor (index);
  return truth_[index];
}

int
KinectSimulator::activeProjectors () const
{
  int n = 0;
  for (const auto &s : sensors_)
    n += s.projector_active ? 1 : 0;
  return n;
}

effects::SimSensor
KinectSimulator::simSensor (std::size_t index) const
{
  const DepthSensor &s = sensors_[index];
  effects::SimSensor out;
  out.seed = settings_.seed;
  out.sensor = static_cast<std::uint32_t> (index);
  out.width = s.width;
  out.height = s.height;
  out.cx = s.cx;
  out.cy = s.cy;
  // The distance of the corner farthest from the principal point (depth_distortion's bowl).
  out.r_corner = std::sqrt (std::pow (std::max (s.cx, s.width - 1 - s.cx), 2) +
                            std::pow (std::max (s.cy, s.height - 1 - s.cy), 2));
  out.fb = s.fb ();
  return out;
}

void
KinectSimulator::prepare (std::size_t index)
{
  const DepthSensor &s = sensors_[index];
  SensorTruth &t = truth_[index];
  const std::size_t n = static_cast<std::size_t> (s.width) * s.height;
  t.width = s.width;
  t.height = s.height;
  t.depth_m.assign (n, 0.0f);
  t.normal.assign (n, Eigen::Vector3f::Zero ());
  t.cos_incidence.assign (n, 0.0f);
  t.lit.assign (n, 0);
  t.foreign_load.assign (n, 0.0f);
  t.disparity_px.assign (n, 0.0);
  t.sigma_px.assign (n, 0.0f);
  t.dropout.assign (n, 0.0f);

  const Eigen::Matrix3d rotation = s.pose.linear ();
  const Eigen::Vector3d camera = s.cameraPosition (), projector = s.projectorPosition ();
  const double fb = s.fb ();
  const effects::SimSensor sensor = simSensor (index);
  const std::vector<GenerativeEffect::ConstPtr> &on = effects_.on;
  bool foreign_load = false;
  for (const auto &e : on)
    foreign_load = foreign_load || e->needsForeignLoad ();
  // The base noise sees the sensor's own f b and projectors, and each pixel's incidence angle.
  PixelContextBuilder contexts (s.cx, s.cy, fb);
  contexts.setActiveProjectors (activeProjectors ());

  parallelFor (s.height, numberOfThreads (), true, [&] (int v) {
    for (int u = 0; u < s.width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * s.width + u;
      const Eigen::Vector3d ray_camera ((u - s.cx) / s.fx, (v - s.cy) / s.fy, 1.0);
      const Eigen::Vector3d direction = rotation * ray_camera;
      SurfaceHit hit;
      if (!scene_->intersect (camera, direction, 1e-9, std::numeric_limits<double>::infinity (), hit))
        continue;
      const double z = hit.t;
      const Eigen::Vector3d point = camera + z * direction;
      const Eigen::Vector3d normal = hit.normal.dot (direction) > 0 ? Eigen::Vector3d (-hit.normal) : hit.normal;
      const double cos_view = -normal.dot (direction) / direction.norm ();
      t.depth_m[i] = static_cast<float> (z);
      t.normal[i] = (rotation.transpose () * normal).cast<float> ();
      t.cos_incidence[i] = static_cast<float> (cos_view);

      // The own projector: lights the point unless the point faces away from it or is hidden.
      const Eigen::Vector3d to_own = projector - point;
      const double r_own = to_own.norm (), cos_own = normal.dot (to_own) / r_own;
      const bool lit = !settings_.projector_shadows || (cos_own > 0 && !scene_->occluded (projector, point));
      t.lit[i] = lit ? 1 : 0;

      if (foreign_load)
      {
        double load = 0.0;
        for (std::size_t j = 0; j < sensors_.size (); ++j)
        {
          const DepthSensor &o = sensors_[j];
          if (j == index || !o.projector_active)
            continue;
          // The other projector is modelled with its camera's field of view and orientation.
          const Eigen::Vector3d pj = o.projectorPosition ();
          const Eigen::Vector3d q = o.pose.linear ().transpose () * (point - pj);
          if (!(q.z () > 0))
            continue;
          const double pu = o.fx * q.x () / q.z () + o.cx, pv = o.fy * q.y () / q.z () + o.cy;
          if (pu < -0.5 || pu > o.width - 0.5 || pv < -0.5 || pv > o.height - 0.5)
            continue;
          const Eigen::Vector3d to_j = pj - point;
          const double r_j = to_j.norm (), cos_j = normal.dot (to_j) / r_j;
          if (!(cos_j > 0) || scene_->occluded (pj, point))
            continue;
          load += kernels::relativeIrradiance (cos_j, r_j, cos_own, r_own);
        }
        t.foreign_load[i] = static_cast<float> (load);
      }

      effects::SimPixel px;
      px.u = u;
      px.v = v;
      px.radius_px = std::hypot (u - s.cx, v - s.cy);
      px.depth_m = z;
      px.cos_incidence = cos_view;
      px.foreign_load = t.foreign_load[i];
      bool readable = lit;
      for (const auto &e : on)
        readable = readable && e->readable (px);
      if (!readable)
        continue;

      double base = 0.0;
      if (settings_.base_noise)
      {
        PixelContext ctx = contexts.at (u, v, px.radius_px, 1000.0 * z);
        ctx.cos_incidence = cos_view;
        base = kernels::disparitySigmaFromDepthSigma (1e-3 * settings_.noise_model.sigmaMm (ctx), z, fb);
      }
      // The SD in two phases: variances added to the base noise's, then the factors in registry
      // order; an effect without a hook adds exactly 0 or multiplies by exactly 1.
      double variance = base * base;
      for (const auto &e : on)
        variance += e->disparityVariance (px);
      double sigma = std::sqrt (variance);
      for (const auto &e : on)
        sigma *= e->sdFactor (px);
      t.sigma_px[i] = static_cast<float> (sigma);
      double dropout = 0.0;
      for (const auto &e : on)
      {
        const double q = e->dropout (px);
        dropout = dropout + q - dropout * q;
      }
      t.dropout[i] = static_cast<float> (dropout);
      double disparity = kernels::disparityFromDepth (z, fb);
      for (const auto &e : on)
        disparity += e->disparityOffset (sensor, px);
      t.disparity_px[i] = disparity;
    }
  });
}

CameraInfo
KinectSimulator::cameraInfo (std::size_t index) const
{
  const DepthSensor &s = sensor (index);
  effects::CameraLabel label;
  label.fx = s.fx;
  label.fy = s.fy;
  label.cx = s.cx;
  label.cy = s.cy;
  label.disparity_step_px = CameraInfo ().disparity_subpixel;
  for (std::size_t k = 0; k < effects_.all.size (); ++k)
    effects_.all[k]->labelCamera (effects_.enabled[k], label);
  CameraInfo info;
  info.width = s.width;
  info.height = s.height;
  const double K[9] = {label.fx, 0, label.cx, 0, label.fy, label.cy, 0, 0, 1};
  std::copy (K, K + 9, info.K);
  info.distortion_model = "plumb_bob";
  info.D.assign (5, 0.0);
  info.baseline_m = s.baseline_m;
  info.disparity_subpixel = label.disparity_step_px;
  return info;
}

void
KinectSimulator::renderRows (std::size_t index, std::uint32_t frame, DepthFrame &out, bool parallel) const
{
  const DepthSensor &s = sensor (index);
  const SensorTruth &t = truth_[index];

  bool dropout = false, columns_offset = false;
  for (const auto &e : effects_.on)
  {
    dropout = dropout || e->hasDropout ();
    columns_offset = columns_offset || e->hasColumnOffsets ();
  }

  kernels::SensorPixelMaps maps;
  maps.width = s.width;
  maps.height = s.height;
  maps.disparity_px = t.disparity_px.data ();
  maps.sigma_px = t.sigma_px.data ();
  maps.dropout = dropout ? t.dropout.data () : nullptr;
  maps.depth_m = t.depth_m.data ();

  const effects::SimSensor sensor = simSensor (index);
  std::vector<float> columns;
  kernels::SensorFrameSettings fs;
  fs.seed = settings_.seed;
  fs.sensor = static_cast<std::uint32_t> (index);
  fs.frame = frame;
  fs.fb = s.fb ();
  fs.min_depth_m = s.min_depth_m;
  fs.max_depth_m = s.max_depth_m;
  if (columns_offset)
  {
    columns.assign (s.width, 0.0f);
    fs.column_offset_px = columns.data ();
  }
  for (const auto &e : effects_.on)
  {
    fs.frame_offset_px += e->frameOffset (frame);
    if (columns_offset)
      e->addColumnOffsets (sensor, frame, columns.data ());
    e->frameSettings (fs);
  }

  out.name = frameName (frame);
  out.width = s.width;
  out.height = s.height;
  out.depth_mm.resize (static_cast<std::size_t> (s.width) * s.height);
  out.rgb.clear ();
  std::uint16_t *depth = out.depth_mm.data ();
  parallelFor (s.height, numberOfThreads (), parallel, [&] (int v) {
    for (int u = 0; u < s.width; ++u)
      depth[static_cast<std::size_t> (v) * s.width + u] = kernels::simulateDepthPixel (maps, fs, u, v);
  });
}

DepthFrame
KinectSimulator::simulateFrame (std::size_t index, std::uint32_t frame) const
{
  DepthFrame out;
  renderRows (index, frame, out, true);
  return out;
}

void
KinectSimulator::simulateFrameSerial (std::size_t index, std::uint32_t frame, DepthFrame &out) const
{
  renderRows (index, frame, out, false);
}

std::vector<DepthFrame>
KinectSimulator::simulate (std::size_t index, std::uint32_t first, std::uint32_t count) const
{
  sensor (index);
  std::vector<DepthFrame> frames (count);
  parallelFor (static_cast<int> (count), numberOfThreads (), true,
               [&] (int k) { renderRows (index, first + static_cast<std::uint32_t> (k), frames[k], false); });
  return frames;
}

} // namespace sim
} // namespace texlet
} // namespace pcl
