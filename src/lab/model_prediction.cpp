/*
 * pcl_texlet model lab: what a model predicts for a recording, per pixel and per frame, for the
 * report's maps and curves.
 */
#include <pcl_texlet/lab/model_lab.h>

#include "lab_data.h"
#include "likelihood.h"
#include "recorded_resolution.h"
#include "static_fit.h"

#include <pcl_texlet/kernels/structured_light.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl
{
namespace texlet
{
namespace lab
{

using namespace detail;

void
ModelLab::predict (const NoiseModel &model, std::vector<std::vector<float>> &sd_all,
                   std::vector<std::vector<float>> &mean_all) const
{
  const std::shared_ptr<const Data> data_all = data (Half::all, model);
  const Data &d = *data_all;
  const ModelView mv (model);
  StaticState s;
  staticFit (mv, d, recordings_, GridFit::none, s);
  sd_all.resize (recordings_.size ());
  mean_all.resize (recordings_.size ());
  for (std::size_t r = 0; r < recordings_.size (); ++r)
  {
    const RecordingMeasurement &m = *recordings_[r];
    std::vector<float> &sd_mm = sd_all[r], &mean_mm = mean_all[r];
    const std::size_t n = static_cast<std::size_t> (m.width) * m.height;
    sd_mm.assign (n, std::numeric_limits<float>::quiet_NaN ());
    mean_mm.assign (n, std::numeric_limits<float>::quiet_NaN ());
    double drift_var = 0;
    const PixelContext &rep = d.rep[r];
    const double Jr = kernels::depthPerDisparityMm (rep.true_depth_mm, rep.fb_px_m);
    if (frameDependent (model))
    {
      double s1 = 0, s2 = 0;
      for (int t : d.frame_list[r])
      {
        const double b = frameBias (mv.without_grid, rep, t) / Jr;
        s1 += b;
        s2 += b * b;
      }
      const double k = static_cast<double> (d.frame_list[r].size ());
      drift_var = k > 1 ? (s2 - s1 * s1 / k) / (k - 1) : 0.0;
    }
    const double fb1000 = 1000.0 * m.fb ();
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!m.used[i])
        continue;
      const double J = kernels::depthPerDisparityMm (m.surface_mm[i], m.fb ());
      const NoiseMoments mo = model.moments (pixelContext (m, i));
      const double x = (double (i % m.width) - m.camera.cx ()) / m.camera.fx ();
      const double y = (double (i / m.width) - m.camera.cy ()) / m.camera.fy ();
      const double disparity = d.plane[r] ? s.planes[r].dot (Eigen::Vector3d (1.0, x, y)) : fb1000 / m.surface_mm[i];
      const double mean = predictedMeanMm (disparity, fb1000, mo.bias_mm, J);
      const RecordedMoments recorded = recordedMoments (model, mv.quantised, mo.variance_mm2, mean);
      sd_mm[i] = static_cast<float> (std::sqrt (recorded.variance_mm2 + mo.sharedVarianceMm2 () + J * J * drift_var));
      mean_mm[i] = static_cast<float> (mean + recorded.mean_offset_mm);
    }
  }
}

void
ModelLab::frameCurve (const NoiseModel &model, std::size_t r, std::vector<double> &predicted_mm,
                      std::vector<double> &measured_mm) const
{
  const std::shared_ptr<const Data> data_all = data (Half::all, model);
  const Data &d = *data_all;
  const PixelContext &rep = d.rep.at (r);
  const double J = kernels::depthPerDisparityMm (rep.true_depth_mm, rep.fb_px_m);
  const auto &list = d.frame_list[r];
  predicted_mm.assign (list.size (), 0.0);
  measured_mm.assign (list.size (), std::numeric_limits<double>::quiet_NaN ());
  const ModelView mv (model);
  const NoiseModel &no_grid = mv.without_grid;
  double mean = 0;
  for (std::size_t k = 0; k < list.size (); ++k)
  {
    predicted_mm[k] = frameDependent (model) ? frameBias (no_grid, rep, list[k]) : 0.0;
    mean += predicted_mm[k];
  }
  for (double &p : predicted_mm)
    p -= mean / list.size ();
  for (const FrameStat &f : d.frames)
    if (f.rec == static_cast<int> (r))
    {
      const std::size_t k = std::lower_bound (list.begin (), list.end (), f.frame) - list.begin ();
      measured_mm[k] = f.D * J;
    }
}

} // namespace lab
} // namespace texlet
} // namespace pcl
