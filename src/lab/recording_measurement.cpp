#include <pcl_texlet/lab/recording_measurement.h>

#include "quantisation_lattice.h"

#include <pcl_texlet/io/open_recording.h>

#include <pcl/exceptions.h>

#include <Eigen/Dense>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <sys/stat.h>

namespace pcl
{
namespace texlet
{
namespace lab
{

namespace
{

bool
isFile (const std::string &path)
{
  struct stat st;
  return ::stat (path.c_str (), &st) == 0 && S_ISREG (st.st_mode);
}

/** Scene facts from meta.yaml: the scene kind and the number of active projectors. Nothing
  * else is read (in particular not the effects a simulator switched on).
  */
void
readSceneFacts (const std::string &yaml, const std::string &name, RecordingMeasurement &m)
{
  if (yaml.empty ())
    return;
  YAML::Node root;
  try
  {
    root = YAML::Load (yaml);
  }
  catch (const YAML::Exception &e)
  {
    throw pcl::IOException ("recording '" + name + "': meta.yaml is not valid YAML (" + e.what () + ")");
  }
  if (!root.IsMap ())
    return;
  try
  {
    if (root["scene"])
      m.scene = root["scene"].as<std::string> ();
    if (root["projectors"])
      m.active_projectors = root["projectors"].as<double> ();
  }
  catch (const YAML::Exception &)
  {
    throw pcl::IOException ("recording '" + name + "': meta.yaml has a malformed 'scene' or 'projectors'");
  }
  if (!(m.active_projectors >= 1) || !std::isfinite (m.active_projectors))
    throw pcl::IOException ("recording '" + name + "': meta.yaml 'projectors' must be at least 1");
  m.plane_scene = m.scene == "plane";
}

/** Two-pass chamfer distance (3-4 weights, in pixels) to the nearest edge pixel. */
void
distanceToEdges (const std::vector<std::uint8_t> &edge, int w, int h, std::vector<float> &dist)
{
  const float big = 1e6f;
  dist.assign (edge.size (), big);
  for (std::size_t i = 0; i < edge.size (); ++i)
    if (edge[i])
      dist[i] = 0.0f;
  const float a = 1.0f, b = 1.41421356f;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
    {
      float &d = dist[static_cast<std::size_t> (v) * w + u];
      if (u > 0)
        d = std::min (d, dist[v * w + u - 1] + a);
      if (v > 0)
      {
        d = std::min (d, dist[(v - 1) * w + u] + a);
        if (u > 0)
          d = std::min (d, dist[(v - 1) * w + u - 1] + b);
        if (u + 1 < w)
          d = std::min (d, dist[(v - 1) * w + u + 1] + b);
      }
    }
  for (int v = h - 1; v >= 0; --v)
    for (int u = w - 1; u >= 0; --u)
    {
      float &d = dist[static_cast<std::size_t> (v) * w + u];
      if (u + 1 < w)
        d = std::min (d, dist[v * w + u + 1] + a);
      if (v + 1 < h)
      {
        d = std::min (d, dist[(v + 1) * w + u] + a);
        if (u + 1 < w)
          d = std::min (d, dist[(v + 1) * w + u + 1] + b);
        if (u > 0)
          d = std::min (d, dist[(v + 1) * w + u - 1] + b);
      }
    }
}

} // namespace

double
RecordingMeasurement::radius (double u, double v) const
{
  return std::hypot (u - camera.cx (), v - camera.cy ());
}

std::size_t
RecordingMeasurement::usedCount () const
{
  return static_cast<std::size_t> (std::count (used.begin (), used.end (), 1));
}

RecordingMeasurement::Ptr
measureRecording (RecordingReader &reader, const std::string &name, const std::string &meta_yaml,
                  const MeasurementSettings &settings)
{
  auto m = std::make_shared<RecordingMeasurement> ();
  m->name = name;
  m->camera = reader.cameraInfo ();
  m->width = m->camera.width;
  m->height = m->camera.height;
  readSceneFacts (meta_yaml, name, *m);
  if (!(m->camera.fx () > 0) || !(m->camera.baseline_m > 0))
    throw pcl::BadArgumentException ("recording '" + name + "': focal length and baseline must be positive");

  const std::size_t n = static_cast<std::size_t> (m->width) * m->height;
  DepthFrame frame;
  std::vector<double> grey_sum;
  int colour_frames = 0;
  while (reader.next (frame))
  {
    if (frame.width != m->width || frame.height != m->height)
    {
      std::ostringstream msg;
      msg << "recording '" << name << "': frame " << frame.name << " is " << frame.width << "x" << frame.height
          << ", the recording " << m->width << "x" << m->height;
      throw pcl::BadArgumentException (msg.str ());
    }
    // valid_frames counts in 16 bits.
    if (m->frames == 65535)
      throw pcl::BadArgumentException ("recording '" + name + "': more than 65535 frames; measure a subset");
    m->depth_mm.insert (m->depth_mm.end (), frame.depth_mm.begin (), frame.depth_mm.end ());
    if (frame.rgb.size () == 3 * n)
    {
      grey_sum.resize (n, 0.0);
      for (std::size_t i = 0; i < n; ++i)
        grey_sum[i] += greyLevel (frame.rgb[3 * i], frame.rgb[3 * i + 1], frame.rgb[3 * i + 2]);
      ++colour_frames;
    }
    ++m->frames;
  }
  if (colour_frames > 0)
  {
    m->intensity.resize (n);
    for (std::size_t i = 0; i < n; ++i)
      m->intensity[i] = static_cast<float> (grey_sum[i] / colour_frames);
  }
  if (m->frames == 0)
    throw pcl::BadArgumentException ("recording '" + name + "': it has no frames");

  // Temporal mean and SD of the valid frames.
  // A recording of one frame is a set of single frames: a pixel is used where it has its reading.
  const int min_valid =
      std::min (m->frames, std::max (2, static_cast<int> (std::ceil (settings.min_valid_share * m->frames))));
  m->valid_frames.assign (n, 0);
  m->mean_mm.assign (n, 0.0f);
  m->sd_mm.assign (n, 0.0f);
  m->used.assign (n, 0);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < m->height; ++v)
    for (int u = 0; u < m->width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * m->width + u;
      double s = 0, s2 = 0;
      int c = 0;
      for (int t = 0; t < m->frames; ++t)
      {
        const double z = m->at (t, i);
        if (z > 0)
        {
          s += z;
          s2 += z * z;
          ++c;
        }
      }
      m->valid_frames[i] = static_cast<std::uint16_t> (c);
      if (c == 0)
        continue;
      const double mean = s / c;
      m->mean_mm[i] = static_cast<float> (mean);
      double ss = 0;
      for (int t = 0; t < m->frames; ++t)
      {
        const double z = m->at (t, i);
        if (z > 0)
          ss += (z - mean) * (z - mean);
      }
      m->sd_mm[i] = c > 1 ? static_cast<float> (std::sqrt (ss / (c - 1))) : std::numeric_limits<float>::quiet_NaN ();
      m->used[i] = c >= min_valid ? 1 : 0;
    }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (m->valid_frames[i] == 0)
      ++m->no_surface;
    else if (!m->used[i])
      ++m->left_out;
  }

  // Depth edges: jumps between used neighbours; distance to them.
  std::vector<std::uint8_t> edge (n, 0);
  for (int v = 0; v < m->height; ++v)
    for (int u = 0; u < m->width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * m->width + u;
      if (!m->used[i])
        continue;
      const std::size_t nb[2] = {u + 1 < m->width ? i + 1 : i, v + 1 < m->height ? i + m->width : i};
      for (std::size_t j : nb)
        if (j != i && m->used[j] && std::fabs (m->mean_mm[j] - m->mean_mm[i]) > settings.edge_jump_share * m->mean_mm[i])
          edge[i] = edge[j] = 1;
    }
  distanceToEdges (edge, m->width, m->height, m->edge_distance_px);

  // Reference surface, in disparity (linear in the normalised image coordinates for a plane).
  const double fb1000 = 1000.0 * m->fb ();
  const double fx = m->camera.fx (), fy = m->camera.fy (), cx = m->camera.cx (), cy = m->camera.cy ();
  m->surface_mm.assign (n, 0.0f);
  m->cos_incidence.assign (n, 1.0f);
  m->inlier.assign (n, 0);
  if (m->plane_scene)
  {
    for (std::size_t i = 0; i < n; ++i)
      m->inlier[i] = m->used[i];
    Eigen::Vector3d p = Eigen::Vector3d::Zero ();
    for (int iteration = 0; iteration < 4; ++iteration)
    {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero ();
      Eigen::Vector3d b = Eigen::Vector3d::Zero ();
      for (std::size_t i = 0; i < n; ++i)
        if (m->inlier[i])
        {
          const Eigen::Vector3d x (1.0, (double (i % m->width) - cx) / fx, (double (i / m->width) - cy) / fy);
          A += x * x.transpose ();
          b += x * (fb1000 / m->mean_mm[i]);
        }
      if (A (0, 0) < 3)
        break;
      p = A.ldlt ().solve (b);
      std::vector<float> r;
      for (std::size_t i = 0; i < n; ++i)
        if (m->used[i])
          r.push_back (static_cast<float> (
              std::fabs (fb1000 / m->mean_mm[i] - (p[0] + p[1] * ((double (i % m->width) - cx) / fx) +
                                                   p[2] * ((double (i / m->width) - cy) / fy)))));
      std::nth_element (r.begin (), r.begin () + r.size () / 2, r.end ());
      const double scale = std::max (1.4826 * r[r.size () / 2], 1e-6);
      for (std::size_t i = 0; i < n; ++i)
        if (m->used[i])
        {
          const double res = fb1000 / m->mean_mm[i] - (p[0] + p[1] * ((double (i % m->width) - cx) / fx) +
                                                       p[2] * ((double (i / m->width) - cy) / fy));
          m->inlier[i] = std::fabs (res) < settings.outlier_sigmas * scale ? 1 : 0;
        }
    }
    for (int k = 0; k < 3; ++k)
      m->plane[k] = p[k];
    const Eigen::Vector3d normal = Eigen::Vector3d (p[1], p[2], p[0]).normalized ();
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!m->used[i])
        continue;
      const Eigen::Vector3d ray ((double (i % m->width) - cx) / fx, (double (i / m->width) - cy) / fy, 1.0);
      const double disparity = p.dot (Eigen::Vector3d (1.0, ray.x (), ray.y ()));
      if (!(disparity > 0))
      {
        m->used[i] = 0;
        ++m->left_out;
        continue;
      }
      m->surface_mm[i] = static_cast<float> (fb1000 / disparity);
      m->cos_incidence[i] = static_cast<float> (std::fabs (normal.dot (ray)) / ray.norm ());
    }
  }
  else
  {
    // A local plane in disparity over a small window of the same side of any edge.
    const int R = settings.local_fit_radius_px;
    std::vector<float> surface (n, 0.0f), cosines (n, 1.0f);
#pragma omp parallel for schedule(static)
    for (int v = 0; v < m->height; ++v)
      for (int u = 0; u < m->width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * m->width + u;
        if (!m->used[i])
          continue;
        Eigen::Matrix3d A = Eigen::Matrix3d::Zero ();
        Eigen::Vector3d b = Eigen::Vector3d::Zero ();
        int count = 0;
        for (int dv = -R; dv <= R; ++dv)
          for (int du = -R; du <= R; ++du)
          {
            const int uu = u + du, vv = v + dv;
            if (uu < 0 || vv < 0 || uu >= m->width || vv >= m->height)
              continue;
            const std::size_t j = static_cast<std::size_t> (vv) * m->width + uu;
            if (!m->used[j] || std::fabs (m->mean_mm[j] - m->mean_mm[i]) > settings.edge_jump_share * m->mean_mm[i])
              continue;
            const Eigen::Vector3d x (1.0, (uu - cx) / fx, (vv - cy) / fy);
            A += x * x.transpose ();
            b += x * (fb1000 / m->mean_mm[j]);
            ++count;
          }
        if (count < 12 || std::fabs (A.determinant ()) < 1e-18)
          continue;
        const Eigen::Vector3d p = A.ldlt ().solve (b);
        const Eigen::Vector3d ray ((u - cx) / fx, (v - cy) / fy, 1.0);
        const double disparity = p.dot (Eigen::Vector3d (1.0, ray.x (), ray.y ()));
        if (!(disparity > 0))
          continue;
        surface[i] = static_cast<float> (fb1000 / disparity);
        const Eigen::Vector3d normal = Eigen::Vector3d (p[1], p[2], p[0]).normalized ();
        cosines[i] = static_cast<float> (std::fabs (normal.dot (ray)) / ray.norm ());
      }
    for (std::size_t i = 0; i < n; ++i)
    {
      if (m->used[i] && !(surface[i] > 0))
      {
        m->used[i] = 0;
        ++m->left_out;
      }
      m->inlier[i] = m->used[i];
    }
    m->surface_mm = std::move (surface);
    m->cos_incidence = std::move (cosines);
  }

  m->bias_mm.assign (n, 0.0f);
  m->phase.assign (n, 0.0f);
  const double step = m->camera.disparity_subpixel > 0 ? m->camera.disparity_subpixel : 0.125;
  for (std::size_t i = 0; i < n; ++i)
    if (m->used[i])
    {
      m->bias_mm[i] = m->mean_mm[i] - m->surface_mm[i];
      m->phase[i] = static_cast<float> (detail::subStepPhase (fb1000 / m->surface_mm[i], step, 0.0));
    }
  if (m->usedCount () == 0)
    throw pcl::BadArgumentException ("recording '" + name + "': no pixel has " + std::to_string (min_valid) +
                                     " valid frame" + (min_valid > 1 ? "s" : "") + " of " +
                                     std::to_string (m->frames) + " and a surface");
  return m;
}

namespace
{
/** Frames held in memory, read like a recording. */
class FrameListReader : public RecordingReader
{
public:
  FrameListReader (const std::vector<DepthFrame> &frames, const CameraInfo &info) : frames_ (frames), info_ (info) {}
  std::size_t size () const override { return frames_.size (); }
  const CameraInfo &cameraInfo () const override { return info_; }
  bool
  next (DepthFrame &frame) override
  {
    if (next_ >= frames_.size ())
      return false;
    frame = frames_[next_++];
    return true;
  }

private:
  const std::vector<DepthFrame> &frames_;
  CameraInfo info_;
  std::size_t next_ = 0;
};
} // namespace

RecordingMeasurement::Ptr
measureFrames (const std::vector<DepthFrame> &frames, const CameraInfo &camera, const std::string &name,
               const std::string &meta_yaml, const MeasurementSettings &settings)
{
  FrameListReader reader (frames, camera);
  return measureRecording (reader, name, meta_yaml, settings);
}

std::string
readMetaYaml (const std::string &folder)
{
  const std::string meta_path = folder + "/meta.yaml";
  if (!isFile (meta_path))
    return "";
  std::ifstream in (meta_path);
  std::stringstream text;
  text << in.rdbuf ();
  if (!in && !in.eof ())
    throw pcl::IOException ("cannot read '" + meta_path + "'");
  return text.str ();
}

PixelContext
recordingNoiseContext (const CameraInfo &camera, const std::string &meta_yaml, const std::string &name)
{
  RecordingMeasurement facts;
  readSceneFacts (meta_yaml, name, facts);
  PixelContextBuilder contexts (camera.cx (), camera.cy (), camera.fb ());
  contexts.setActiveProjectors (facts.active_projectors);
  return contexts.shared ();
}

RecordingMeasurement::Ptr
measureRecording (const std::string &path, const MeasurementSettings &settings)
{
  RecordingReader::Ptr reader = openRecording (path);
  return measureRecording (*reader, path, readMetaYaml (path), settings);
}

} // namespace lab
} // namespace texlet
} // namespace pcl
