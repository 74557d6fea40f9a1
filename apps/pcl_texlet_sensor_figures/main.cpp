/*
 * pcl_texlet_sensor_figures: the measurements behind docs/sensor_model.md.
 *
 * For each physical effect of the simulator it simulates a small scene (mostly a wall 1.5 m
 * away) with the base noise alone and with the effect added, measures the quantity in which
 * the effect shows, and writes it, beside the closed-form prediction from the effect's
 * parameters, as gnuplot data files (columns named in a '#' header). summary.txt lists the key
 * numbers. scripts/make_sensor_model_figures.sh draws the PNGs from these files.
 *
 * Exit codes: 0 success, 2 bad input or options (one line on stderr), 1 unexpected failure.
 * Every file is written to a temporary name and renamed, so no half-written file is left.
 */
#include "../common/app_main.h"
#include <pcl_texlet/kernels/structured_light.h>
#include <pcl_texlet/noise/noise_model.h>
#include <pcl_texlet/noise/effects/axial_quadratic.h>
#include <pcl_texlet/noise/effects/depth_distortion.h>
#include <pcl_texlet/noise/effects/disparity_quantization.h>
#include <pcl_texlet/noise/effects/incidence_angle.h>
#include <pcl_texlet/noise/effects/interference.h>
#include <pcl_texlet/noise/effects/intrinsics.h>
#include <pcl_texlet/noise/effects/lateral_noise.h>
#include <pcl_texlet/noise/effects/radial.h>
#include <pcl_texlet/noise/effects/temporal_drift.h>
#include <pcl_texlet/noise/effects/vertical_stripes.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <pcl/console/print.h>
#include <pcl/exceptions.h>

#include <Eigen/Eigenvalues>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include <unistd.h>

namespace fs = std::filesystem;
using namespace pcl::texlet;
using namespace pcl::texlet::sim;

using pcl_texlet_app::InputError;

namespace
{

const char *const kName = "pcl_texlet_sensor_figures";
const double kNaN = std::numeric_limits<double>::quiet_NaN ();
/** Variance of rounding to whole millimetres (Sheppard's correction), mm^2. */
const double kRoundingVariance = 1.0 / 12.0;

/** The figures in the order the document shows them. */
const std::vector<std::string> &
figureNames ()
{
  static const std::vector<std::string> names = {
      "base_noise",       "projector_shadows", effects::AxialQuadratic::kName, effects::Radial::kName,        effects::DisparityQuantization::kName,
      effects::IncidenceAngle::kName,  effects::VerticalStripes::kName,  effects::DepthDistortion::kName, effects::Interference::kName, effects::TemporalDrift::kName,
      effects::LateralNoise::kName,    effects::Intrinsics::kName};
  return names;
}

struct Options
{
  std::string output;
  int width = 640, height = 480;
  unsigned frames = 30;
  std::uint32_t seed = 0;
  unsigned threads = 0;
  std::vector<std::string> only;
  bool quiet = false;
};

/** Writes \a text to \a path through a temporary file in the same folder, renamed at the end. */
void
writeFile (const fs::path &path, const std::string &text)
{
  const fs::path tmp = path.parent_path () / ("." + path.filename ().string () + ".tmp-" + std::to_string (::getpid ()));
  {
    std::ofstream f (tmp, std::ios::binary | std::ios::trunc);
    f << text;
    f.close ();
    if (!f)
    {
      std::error_code ec;
      fs::remove (tmp, ec);
      throw pcl::IOException ("cannot write '" + path.string () + "'");
    }
  }
  std::error_code ec;
  fs::rename (tmp, path, ec);
  if (ec)
  {
    fs::remove (tmp, ec);
    throw pcl::IOException ("cannot rename a temporary file onto '" + path.string () + "': " + ec.message ());
  }
}

/** A number for a data file: NaN as gnuplot's "NaN". */
std::string
num (double v, int precision = 6)
{
  if (!std::isfinite (v))
    return "NaN";
  std::ostringstream s;
  s << std::setprecision (precision) << v;
  return s.str ();
}

/** Per-pixel statistics over frames of the reported depth minus the true depth, mm. */
struct PixelStats
{
  int width = 0, height = 0;
  std::vector<int> n;        ///< frames with a reading
  std::vector<double> mean;  ///< mean residual, mm
  std::vector<double> m2;    ///< sum of squared deviations from the mean, mm^2
  std::vector<double> truth; ///< true depth, mm (0: no surface)
  std::size_t frames = 0;

  double
  sd (std::size_t i) const { return n[i] >= 2 ? std::sqrt (m2[i] / (n[i] - 1)) : kNaN; }

  double
  bias (std::size_t i) const { return n[i] >= 1 ? mean[i] : kNaN; }
};

PixelStats
pixelStats (const KinectSimulator &sim, const std::vector<DepthFrame> &frames)
{
  const SensorTruth &t = sim.truth (0);
  PixelStats s;
  s.width = t.width;
  s.height = t.height;
  const std::size_t n = static_cast<std::size_t> (t.width) * t.height;
  s.n.assign (n, 0);
  s.mean.assign (n, 0.0);
  s.m2.assign (n, 0.0);
  s.truth.resize (n);
  s.frames = frames.size ();
  for (std::size_t i = 0; i < n; ++i)
    s.truth[i] = 1000.0 * t.depth_m[i];
  for (const auto &f : frames)
    for (std::size_t i = 0; i < n; ++i)
    {
      if (f.depth_mm[i] == 0 || s.truth[i] <= 0)
        continue;
      // Welford's update: stable for any number of frames.
      const double r = f.depth_mm[i] - s.truth[i];
      const int k = ++s.n[i];
      const double delta = r - s.mean[i];
      s.mean[i] += delta / k;
      s.m2[i] += delta * (r - s.mean[i]);
    }
  return s;
}

/** Mean of \a value over the pixels where it is finite, in bins of the distance from the
  * principal point (bin width \a bin_px); one row per bin with data.
  */
struct RadialProfile
{
  double bin_px = 10;
  std::vector<double> sum;
  std::vector<int> count;

  void
  add (double r, double v)
  {
    if (!std::isfinite (v))
      return;
    const std::size_t b = static_cast<std::size_t> (r / bin_px);
    if (b >= sum.size ())
    {
      sum.resize (b + 1, 0.0);
      count.resize (b + 1, 0);
    }
    sum[b] += v;
    ++count[b];
  }

  double
  mean (std::size_t b) const { return b < sum.size () && count[b] > 0 ? sum[b] / count[b] : kNaN; }

  double
  centre (std::size_t b) const { return (b + 0.5) * bin_px; }
};

/** Mean of the finite values in blocks of \a block x \a block pixels: a map for gnuplot's
  * `with image` (x y value, a blank line after each row), in pixel coordinates of the block centres.
  */
std::string
blockMap (const std::vector<double> &values, int width, int height, int block)
{
  std::ostringstream out;
  out << "# u_px v_px value (mean over " << block << "x" << block << " pixel blocks)\n";
  for (int by = 0; by * block < height; ++by)
  {
    for (int bx = 0; bx * block < width; ++bx)
    {
      double sum = 0;
      int n = 0;
      for (int v = by * block; v < std::min (height, (by + 1) * block); ++v)
        for (int u = bx * block; u < std::min (width, (bx + 1) * block); ++u)
        {
          const double x = values[static_cast<std::size_t> (v) * width + u];
          if (std::isfinite (x))
          {
            sum += x;
            ++n;
          }
        }
      out << num ((bx + 0.5) * block - 0.5) << " " << num ((by + 0.5) * block - 0.5) << " "
          << (n > 0 ? num (sum / n) : std::string ("NaN")) << "\n";
    }
    out << "\n";
  }
  return out.str ();
}

/** Mean of finite values. */
double
meanOf (const std::vector<double> &v)
{
  double s = 0;
  int n = 0;
  for (const double x : v)
    if (std::isfinite (x))
    {
      s += x;
      ++n;
    }
  return n > 0 ? s / n : kNaN;
}

/** Standard deviation of finite values. */
double
sdOf (const std::vector<double> &v)
{
  const double m = meanOf (v);
  double s = 0;
  int n = 0;
  for (const double x : v)
    if (std::isfinite (x))
    {
      s += (x - m) * (x - m);
      ++n;
    }
  return n > 1 ? std::sqrt (s / (n - 1)) : kNaN;
}

/** Standard normal CDF. */
double
normalCdf (double x)
{
  return 0.5 * std::erfc (-x / std::sqrt (2.0));
}

class FigureMaker
{
public:
  FigureMaker (const Options &o, const fs::path &out) : o_ (o), out_ (out), model_ (DepthSensor::kinect (o.width, o.height))
  {
    fb_ = model_.fb ();
  }

  void
  make (const std::string &name)
  {
    static const std::map<std::string, void (FigureMaker::*) ()> studies = {
        {"base_noise", &FigureMaker::baseNoise},
        {"projector_shadows", &FigureMaker::projectorShadows},
        {effects::AxialQuadratic::kName, &FigureMaker::axialQuadratic},
        {effects::Radial::kName, &FigureMaker::radial},
        {effects::DisparityQuantization::kName, &FigureMaker::disparityQuantization},
        {effects::IncidenceAngle::kName, &FigureMaker::incidenceAngle},
        {effects::VerticalStripes::kName, &FigureMaker::verticalStripes},
        {effects::DepthDistortion::kName, &FigureMaker::depthDistortion},
        {effects::Interference::kName, &FigureMaker::interference},
        {effects::TemporalDrift::kName, &FigureMaker::temporalDrift},
        {effects::LateralNoise::kName, &FigureMaker::lateralNoise},
        {effects::Intrinsics::kName, &FigureMaker::intrinsics}};
    (this->*studies.at (name)) ();
  }

  /** summary.txt: the key numbers, "figure.key = value" lines. */
  void
  writeSummary () const
  {
    std::ostringstream s;
    s << "# pcl_texlet_sensor_figures: " << o_.width << "x" << o_.height << ", " << o_.frames << " frames, seed "
      << o_.seed << ", f " << model_.fx << " px, baseline " << model_.baseline_m << " m\n";
    for (const auto &kv : summary_)
      s << kv.first << " = " << kv.second << "\n";
    writeFile (out_ / "summary.txt", s.str ());
  }

private:
  // --- set-up --------------------------------------------------------------------------------

  SimulationSettings
  settings () const
  {
    SimulationSettings s;
    s.seed = o_.seed;
    return s;
  }

  KinectSimulator
  simulator (const SceneSetup &setup, const SimulationSettings &s) const
  {
    return KinectSimulator (setup.scene, setup.sensors (model_), s, o_.threads);
  }

  KinectSimulator
  simulator (const Scene::ConstPtr &scene, const SimulationSettings &s) const
  {
    return KinectSimulator (scene, {model_}, s, o_.threads);
  }

  std::vector<DepthFrame>
  frames (const KinectSimulator &sim) const
  {
    return sim.simulate (0, 0, o_.frames);
  }

  /** The pixels of the central window: within 5 % of the image width of the principal point. */
  bool
  central (int u, int v) const
  {
    return std::hypot (u - model_.cx, v - model_.cy) < std::max (2.0, 0.05 * model_.width);
  }

  double
  radius (int u, int v) const
  {
    return std::hypot (u - model_.cx, v - model_.cy);
  }

  /** The paper's depth SD (mm) at pixel (u, v) and depth \a depth_mm. */
  double
  paperSigma (int u, int v, double depth_mm) const
  {
    PixelContext ctx;
    ctx.u = u;
    ctx.v = v;
    ctx.radius_px = radius (u, v);
    ctx.depth_mm = depth_mm;
    return paper_.sigmaMm (ctx);
  }

  /** SD (mm) of a reading whose noise-free SD is \a sigma_mm once rounded to whole millimetres. */
  static double
  withRounding (double sigma_mm)
  {
    return std::sqrt (sigma_mm * sigma_mm + kRoundingVariance);
  }

  /** Depth (mm) reported for true depth \a z_mm with a disparity offset of \a offset_px. */
  double
  offsetDepth (double z_mm, double offset_px) const
  {
    return 1000.0 * kernels::depthFromDisparity (kernels::disparityFromDepth (1e-3 * z_mm, fb_) + offset_px, fb_);
  }

  double
  radialBin () const
  {
    return std::max (1.0, model_.width / 64.0);
  }

  void
  note (const std::string &figure, const std::string &key, double value, int precision = 4)
  {
    summary_[figure + "." + key] = num (value, precision);
  }

  void
  write (const std::string &file, const std::string &text) const
  {
    writeFile (out_ / file, text);
  }

  // --- the studies ---------------------------------------------------------------------------

  /** The paper's polynomial alone: SD vs radius at three depths, and the SD map at 1.5 m. */
  void
  baseNoise ()
  {
    const std::vector<double> distances = {0.8, 1.2, 1.6};
    std::vector<RadialProfile> measured (distances.size ()), predicted (distances.size ());
    for (std::size_t k = 0; k < distances.size (); ++k)
    {
      const KinectSimulator sim = simulator (planeSetup (distances[k], 0, 0), settings ());
      const PixelStats st = pixelStats (sim, frames (sim));
      measured[k].bin_px = predicted[k].bin_px = radialBin ();
      for (int v = 0; v < st.height; ++v)
        for (int u = 0; u < st.width; ++u)
        {
          const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
          measured[k].add (radius (u, v), st.sd (i));
          predicted[k].add (radius (u, v), withRounding (paperSigma (u, v, st.truth[i])));
        }
      note ("base_noise", "sd_centre_mm_at_" + num (distances[k]) + "m", measured[k].mean (0));
      note ("base_noise", "model_centre_mm_at_" + num (distances[k]) + "m", predicted[k].mean (0));
      const std::size_t outer = measured[k].sum.size () - 1;
      note ("base_noise", "sd_outer_mm_at_" + num (distances[k]) + "m", measured[k].mean (outer));
      note ("base_noise", "model_outer_mm_at_" + num (distances[k]) + "m", predicted[k].mean (outer));
    }
    note ("base_noise", "outer_radius_px", measured[0].centre (measured[0].sum.size () - 1));
    std::ostringstream out;
    out << "# radius_px";
    for (const double d : distances)
      out << " sd_" << num (d) << "m_mm model_" << num (d) << "m_mm";
    out << "\n# model: sqrt(f(r,d)^2 + 1/12), the paper's Eq. 4 plus rounding to whole mm\n";
    for (std::size_t b = 0; b < measured[0].sum.size (); ++b)
    {
      out << num (measured[0].centre (b));
      for (std::size_t k = 0; k < distances.size (); ++k)
        out << " " << num (measured[k].mean (b)) << " " << num (predicted[k].mean (b));
      out << "\n";
    }
    write ("base_noise_radius.dat", out.str ());

    const KinectSimulator sim = simulator (planeSetup (1.5, 0, 0), settings ());
    const PixelStats st = pixelStats (sim, frames (sim));
    std::vector<double> sd (st.n.size ());
    for (std::size_t i = 0; i < sd.size (); ++i)
      sd[i] = st.sd (i);
    write ("base_noise_map.dat", blockMap (sd, st.width, st.height, std::max (1, o_.width / 160)));
    note ("base_noise", "sd_mean_mm_at_1.5m", meanOf (sd));
  }

  /** The own projector's shadow beside a step: width vs background depth, and a row profile. */
  void
  projectorShadows ()
  {
    const double z_front = 1.5;
    const std::vector<double> backs = {1.6, 1.8, 2.0, 2.5, 3.0};
    std::ostringstream widths;
    widths << "# z_back_m width_measured_px width_model_px   (front: a panel at " << z_front
           << " m covering x > 0, its edge on the optical axis)\n"
           << "# model: f b (1/z_front - 1/z_back), the disparity difference across the step\n";
    for (const double zb : backs)
    {
      for (const bool shadows : {true, false})
      {
        auto scene = std::make_shared<Scene> ();
        scene->add (std::make_shared<PlaneSurface> (Eigen::Vector3d (0, 0, zb), Eigen::Vector3d (0, 0, -1)));
        scene->add (std::make_shared<RectangleSurface> (Eigen::Vector3d (1.0, 0, z_front), Eigen::Vector3d (0, 0, -1),
                                                        Eigen::Vector3d::UnitX (), 1.0, 2.0));
        SimulationSettings s = settings ();
        s.projector_shadows = shadows;
        const KinectSimulator sim = simulator (scene, s);
        const SensorTruth &t = sim.truth (0);
        // The step: the first column of the central row on the front panel.
        const int row = static_cast<int> (std::lround (model_.cy));
        int edge = 0;
        while (edge < t.width && !(t.depth_m[static_cast<std::size_t> (row) * t.width + edge] < 0.5 * (z_front + zb)))
          ++edge;
        const std::vector<DepthFrame> fr = frames (sim);
        // Shadow width: pixels without a reading left of the step, averaged over rows and frames.
        double missing = 0;
        for (const auto &f : fr)
          for (int v = 0; v < f.height; ++v)
            for (int u = 0; u < edge; ++u)
              missing += f.depth_mm[static_cast<std::size_t> (v) * f.width + u] == 0 ? 1 : 0;
        const double width = missing / (static_cast<double> (fr.size ()) * t.height);
        const double model = fb_ * (1.0 / z_front - 1.0 / zb);
        if (shadows)
        {
          widths << num (zb) << " " << num (width) << " " << num (model) << "\n";
          note ("projector_shadows", "width_px_at_" + num (zb) + "m", width);
          note ("projector_shadows", "model_px_at_" + num (zb) + "m", model);
        }
        else
          note ("projector_shadows", "width_px_without_shadows_at_" + num (zb) + "m", width);
        if (zb == 1.8)
        {
          std::ostringstream row_out;
          row_out << "# u_px depth_mm (frame 0, row " << row << "; 0 = no reading), back wall " << zb
                  << " m, panel " << z_front << " m from column " << edge << ", shadows "
                  << (shadows ? "on" : "off") << "\n";
          for (int u = std::max (0, edge - 30); u < std::min (t.width, edge + 15); ++u)
            row_out << u << " " << fr[0].depth_mm[static_cast<std::size_t> (row) * t.width + u] << "\n";
          write (std::string ("projector_shadows_row_") + (shadows ? "on" : "off") + ".dat", row_out.str ());
          note ("projector_shadows", "edge_column", edge, 6);
        }
      }
    }
    write ("projector_shadows.dat", widths.str ());
  }

  /** SD vs depth on a frontal wall, central window: base alone and base + axial_quadratic. */
  void
  axialQuadratic ()
  {
    std::ostringstream out;
    const double sigma_px = effects::AxialQuadratic::SimParameters ().sigma_px;
    out << "# z_m sd_base_mm sd_axial_mm model_base_mm model_axial_mm   (central window; axial sigma_px "
        << sigma_px << ")\n# model_axial: sqrt(f(r,d)^2 + (1000 sigma_px z^2 / (f b))^2 + 1/12)\n";
    for (int k = 0; k <= 23; ++k)
    {
      const double z = 0.7 + 0.1 * k;
      double sd[2] = {0, 0}, model[2] = {0, 0};
      for (int with = 0; with < 2; ++with)
      {
        SimulationSettings s = settings ();
        setEffectEnabled (s.effects, effects::AxialQuadratic::kName, with == 1);
        const KinectSimulator sim = simulator (planeSetup (z, 0, 0), s);
        const PixelStats st = pixelStats (sim, frames (sim));
        std::vector<double> measured, predicted;
        for (int v = 0; v < st.height; ++v)
          for (int u = 0; u < st.width; ++u)
            if (central (u, v))
            {
              const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
              const double base = paperSigma (u, v, st.truth[i]);
              const double axial = with ? 1000.0 * kernels::depthSigmaFromDisparitySigma (sigma_px, z, fb_) : 0.0;
              measured.push_back (st.sd (i));
              predicted.push_back (withRounding (std::hypot (base, axial)));
            }
        sd[with] = meanOf (measured);
        model[with] = meanOf (predicted);
      }
      out << num (z) << " " << num (sd[0]) << " " << num (sd[1]) << " " << num (model[0]) << " " << num (model[1])
          << "\n";
      for (const double at : {1.0, 1.5, 2.0, 3.0})
        if (std::fabs (z - at) < 1e-9)
        {
          note (effects::AxialQuadratic::kName, "sd_base_mm_at_" + num (at) + "m", sd[0]);
          note (effects::AxialQuadratic::kName, "sd_axial_mm_at_" + num (at) + "m", sd[1]);
          note (effects::AxialQuadratic::kName, "model_axial_mm_at_" + num (at) + "m", model[1]);
          note (effects::AxialQuadratic::kName, "axial_term_mm_at_" + num (at) + "m",
                1000.0 * kernels::depthSigmaFromDisparitySigma (sigma_px, at, fb_));
        }
    }
    write ("axial_quadratic.dat", out.str ());
  }

  /** SD vs radius on a frontal wall at 1.5 m: base alone and base + radial. */
  void
  radial ()
  {
    const effects::Radial::SimParameters p;
    RadialProfile measured[2], predicted[2];
    for (int with = 0; with < 2; ++with)
    {
      SimulationSettings s = settings ();
      setEffectEnabled (s.effects, effects::Radial::kName, with == 1);
      const KinectSimulator sim = simulator (planeSetup (1.5, 0, 0), s);
      const PixelStats st = pixelStats (sim, frames (sim));
      measured[with].bin_px = predicted[with].bin_px = radialBin ();
      for (int v = 0; v < st.height; ++v)
        for (int u = 0; u < st.width; ++u)
        {
          const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
          const double factor = with ? effects::Radial::factor (p, radius (u, v)) : 1.0;
          measured[with].add (radius (u, v), st.sd (i));
          predicted[with].add (radius (u, v), withRounding (factor * paperSigma (u, v, st.truth[i])));
        }
    }
    std::ostringstream out;
    out << "# radius_px sd_base_mm sd_radial_mm model_base_mm model_radial_mm   (wall at 1.5 m; gain " << p.gain
        << ", reference radius " << p.reference_radius_px << " px)\n"
        << "# model_radial: sqrt((f(r,d) (1 + gain (r/r_ref)^2))^2 + 1/12)\n";
    for (std::size_t b = 0; b < measured[0].sum.size (); ++b)
      out << num (measured[0].centre (b)) << " " << num (measured[0].mean (b)) << " " << num (measured[1].mean (b))
          << " " << num (predicted[0].mean (b)) << " " << num (predicted[1].mean (b)) << "\n";
    write ("radial.dat", out.str ());
    const std::size_t outer = measured[0].sum.size () - 1;
    note (effects::Radial::kName, "outer_radius_px", measured[0].centre (outer));
    note (effects::Radial::kName, "sd_base_outer_mm", measured[0].mean (outer));
    note (effects::Radial::kName, "sd_radial_outer_mm", measured[1].mean (outer));
    note (effects::Radial::kName, "model_radial_outer_mm", predicted[1].mean (outer));
    note (effects::Radial::kName, "sd_base_centre_mm", measured[0].mean (0));
    note (effects::Radial::kName, "sd_radial_centre_mm", measured[1].mean (0));
  }

  /** Depth histogram on a frontal wall and the mean-error staircase on a tilted one. */
  void
  disparityQuantization ()
  {
    const double step = effects::DisparityQuantization::SimParameters ().step_px;
    const double z = 1.5;
    std::map<int, std::size_t> hist[2];
    std::size_t total[2] = {0, 0};
    for (int with = 0; with < 2; ++with)
    {
      SimulationSettings s = settings ();
      setEffectEnabled (s.effects, effects::DisparityQuantization::kName, with == 1);
      const KinectSimulator sim = simulator (planeSetup (z, 0, 0), s);
      for (const auto &f : frames (sim))
        for (const auto d : f.depth_mm)
          if (d > 0)
          {
            ++hist[with][d];
            ++total[with];
          }
    }
    const int zmm = static_cast<int> (std::lround (1000 * z));
    const int half = static_cast<int> (std::ceil (3.5 * 1000 * kernels::depthStep (z, step, fb_))) + 5;
    std::ostringstream out;
    out << "# depth_mm fraction_base fraction_quantised   (frontal wall at " << z << " m, all pixels and frames)\n";
    for (int d = zmm - half; d <= zmm + half; ++d)
    {
      const auto count = [&] (int w) {
        const auto it = hist[w].find (d);
        return it == hist[w].end () ? 0.0 : static_cast<double> (it->second) / total[w];
      };
      out << d << " " << num (count (0)) << " " << num (count (1)) << "\n";
    }
    write ("disparity_quantization_hist.dat", out.str ());
    std::ostringstream lattice;
    lattice << "# k depth_mm: the depths of disparity k * " << step << " px, 1000 f b / (k step), f b = " << num (fb_)
            << " px m\n";
    const int k0 = static_cast<int> (std::lround (kernels::disparityFromDepth (z, fb_) / step));
    for (int k = k0 - 4; k <= k0 + 4; ++k)
      lattice << k << " " << num (1000.0 * kernels::depthFromDisparity (k * step, fb_), 7) << "\n";
    write ("disparity_quantization_lattice.dat", lattice.str ());
    note (effects::DisparityQuantization::kName, "step_mm_at_1.5m", 1000.0 * kernels::depthStep (z, step, fb_));
    note (effects::DisparityQuantization::kName, "distinct_depths_base", static_cast<double> (hist[0].size ()), 6);
    note (effects::DisparityQuantization::kName, "distinct_depths_quantised", static_cast<double> (hist[1].size ()), 6);
    {
      std::size_t most = 0;
      for (const auto &kv : hist[1])
        most = std::max (most, kv.second);
      note (effects::DisparityQuantization::kName, "largest_bin_fraction_quantised", static_cast<double> (most) / total[1]);
    }

    // The staircase: mean reported minus true depth along the central row of a wall tilted 5 deg
    // (gently, so that one depth step spans tens of columns).
    PixelStats st[2];
    for (int with = 0; with < 2; ++with)
    {
      SimulationSettings s = settings ();
      setEffectEnabled (s.effects, effects::DisparityQuantization::kName, with == 1);
      const KinectSimulator sim = simulator (planeSetup (z, 0, 5), s);
      st[with] = pixelStats (sim, frames (sim));
    }
    const int row = static_cast<int> (std::lround (model_.cy));
    std::ostringstream stair;
    stair << "# true_depth_mm mean_error_base_mm mean_error_quantised_mm half_step_mm   (wall at " << z
          << " m tilted 5 deg about the image y axis, row " << row << ", mean over frames)\n";
    std::vector<double> errs;
    for (int u = 0; u < st[0].width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (row) * st[0].width + u;
      if (st[0].truth[i] <= 0)
        continue;
      stair << num (st[0].truth[i], 7) << " " << num (st[0].bias (i)) << " " << num (st[1].bias (i)) << " "
            << num (0.5 * 1000.0 * kernels::depthStep (1e-3 * st[0].truth[i], step, fb_)) << "\n";
      errs.push_back (std::fabs (st[1].bias (i)));
    }
    write ("disparity_quantization_staircase.dat", stair.str ());
    note (effects::DisparityQuantization::kName, "max_abs_mean_error_quantised_mm", *std::max_element (errs.begin (), errs.end ()));
  }

  /** SD and readings vs the wall's tilt, central window: base alone and base + incidence_angle. */
  void
  incidenceAngle ()
  {
    const effects::IncidenceAngle::SimParameters p;
    std::ostringstream out;
    out << "# tilt_deg sd_base_mm sd_incidence_mm model_base_mm model_incidence_mm valid_base valid_incidence   "
           "(wall at 1.5 m tilted about the image y axis; central window)\n"
        << "# model_incidence: sqrt((f(r,d) (1 + gain (1/cos(theta) - 1)))^2 + 1/12), gain " << p.gain
        << "; no reading beyond " << p.max_angle_deg << " deg\n";
    for (const double tilt : {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 75.0, 78.0, 82.0, 85.0})
    {
      double sd[2], model[2], valid[2];
      for (int with = 0; with < 2; ++with)
      {
        SimulationSettings s = settings ();
        setEffectEnabled (s.effects, effects::IncidenceAngle::kName, with == 1);
        const KinectSimulator sim = simulator (planeSetup (1.5, 0, tilt), s);
        const SensorTruth &t = sim.truth (0);
        const PixelStats st = pixelStats (sim, frames (sim));
        std::vector<double> measured, predicted;
        double readings = 0, pixels = 0;
        for (int v = 0; v < st.height; ++v)
          for (int u = 0; u < st.width; ++u)
            if (central (u, v))
            {
              const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
              const double factor = with ? effects::IncidenceAngle::factor (p, t.cos_incidence[i]) : 1.0;
              measured.push_back (st.sd (i));
              if (!(with && effects::IncidenceAngle::tooOblique (p, t.cos_incidence[i])))
                predicted.push_back (withRounding (factor * paperSigma (u, v, st.truth[i])));
              readings += st.n[i];
              pixels += static_cast<double> (st.frames);
            }
        sd[with] = meanOf (measured);
        model[with] = meanOf (predicted);
        valid[with] = readings / pixels;
      }
      out << num (tilt) << " " << num (sd[0]) << " " << num (sd[1]) << " " << num (model[0]) << " " << num (model[1])
          << " " << num (valid[0]) << " " << num (valid[1]) << "\n";
      for (const double at : {0.0, 30.0, 60.0, 78.0, 82.0})
        if (tilt == at)
        {
          note (effects::IncidenceAngle::kName, "sd_base_mm_at_" + num (at) + "deg", sd[0]);
          note (effects::IncidenceAngle::kName, "sd_incidence_mm_at_" + num (at) + "deg", sd[1]);
          note (effects::IncidenceAngle::kName, "model_incidence_mm_at_" + num (at) + "deg", model[1]);
          note (effects::IncidenceAngle::kName, "valid_incidence_at_" + num (at) + "deg", valid[1]);
        }
    }
    write ("incidence_angle.dat", out.str ());
  }

  /** Column means of one frame's residual, and the residual map: base alone and base + stripes. */
  void
  verticalStripes ()
  {
    const effects::VerticalStripes::SimParameters p;
    // Frame 0 and the first frame of the next layout.
    const std::uint32_t later = static_cast<std::uint32_t> (p.period_frames);
    std::vector<double> profile[3];
    std::vector<double> residual_map;
    for (int run = 0; run < 3; ++run)
    {
      SimulationSettings s = settings ();
      setEffectEnabled (s.effects, effects::VerticalStripes::kName, run > 0);
      const KinectSimulator sim = simulator (planeSetup (1.5, 0, 0), s);
      const SensorTruth &t = sim.truth (0);
      const DepthFrame f = sim.simulateFrame (0, run == 2 ? later : 0);
      profile[run].assign (f.width, kNaN);
      if (run == 1)
        residual_map.assign (f.depth_mm.size (), kNaN);
      for (int u = 0; u < f.width; ++u)
      {
        double sum = 0;
        int n = 0;
        for (int v = 0; v < f.height; ++v)
        {
          const std::size_t i = static_cast<std::size_t> (v) * f.width + u;
          if (f.depth_mm[i] == 0)
            continue;
          const double r = f.depth_mm[i] - 1000.0 * t.depth_m[i];
          sum += r;
          ++n;
          if (run == 1)
            residual_map[i] = r;
        }
        profile[run][u] = n > 0 ? sum / n : kNaN;
      }
    }
    std::ostringstream out;
    out << "# u_px column_mean_residual_mm: base_frame0 stripes_frame0 stripes_frame" << later
        << "   (frontal wall at 1.5 m; " << p.bands << " bands, offset SD " << p.offset_px << " px, a new layout every "
        << p.period_frames << " frames)\n";
    for (std::size_t u = 0; u < profile[0].size (); ++u)
      out << u << " " << num (profile[0][u]) << " " << num (profile[1][u]) << " " << num (profile[2][u]) << "\n";
    write ("vertical_stripes_profile.dat", out.str ());
    write ("vertical_stripes_map.dat", blockMap (residual_map, o_.width, o_.height, std::max (1, o_.width / 160)));
    const auto jump = [] (const std::vector<double> &c) {
      double m = 0;
      for (std::size_t u = 1; u < c.size (); ++u)
        if (std::isfinite (c[u]) && std::isfinite (c[u - 1]))
          m = std::max (m, std::fabs (c[u] - c[u - 1]));
      return m;
    };
    note (effects::VerticalStripes::kName, "column_mean_sd_base_mm", sdOf (profile[0]));
    note (effects::VerticalStripes::kName, "column_mean_sd_stripes_mm", sdOf (profile[1]));
    note (effects::VerticalStripes::kName, "largest_column_jump_base_mm", jump (profile[0]));
    note (effects::VerticalStripes::kName, "largest_column_jump_stripes_mm", jump (profile[1]));
    note (effects::VerticalStripes::kName, "band_offset_sd_model_mm", 1000.0 * kernels::depthSigmaFromDisparitySigma (p.offset_px, 1.5, fb_));
  }

  /** The static bias map at 1.5 m and its central-row profile at three depths. */
  void
  depthDistortion ()
  {
    const effects::DepthDistortion::SimParameters p;
    const std::vector<double> distances = {1.0, 1.5, 2.0};
    const double r_corner = std::sqrt (std::pow (std::max (model_.cx, model_.width - 1 - model_.cx), 2) +
                                       std::pow (std::max (model_.cy, model_.height - 1 - model_.cy), 2));
    const int row = static_cast<int> (std::lround (model_.cy));
    std::vector<std::vector<double>> measured (distances.size ()), predicted (distances.size ());
    for (std::size_t k = 0; k < distances.size (); ++k)
    {
      SimulationSettings s = settings ();
      setEffectEnabled (s.effects, effects::DepthDistortion::kName, true);
      const KinectSimulator sim = simulator (planeSetup (distances[k], 0, 0), s);
      const PixelStats st = pixelStats (sim, frames (sim));
      std::vector<double> bias (st.n.size ()), model (st.n.size ());
      double err2 = 0, model2 = 0;
      int n = 0;
      for (int v = 0; v < st.height; ++v)
        for (int u = 0; u < st.width; ++u)
        {
          const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
          bias[i] = st.bias (i);
          model[i] = offsetDepth (st.truth[i], effects::DepthDistortion::offset (p, o_.seed, 0, u, v, model_.cx, model_.cy,
                                                                          r_corner)) -
                     st.truth[i];
          if (std::isfinite (bias[i]))
          {
            err2 += (bias[i] - model[i]) * (bias[i] - model[i]);
            model2 += model[i] * model[i];
            ++n;
          }
        }
      note (effects::DepthDistortion::kName, "bias_rms_model_mm_at_" + num (distances[k]) + "m", std::sqrt (model2 / n));
      note (effects::DepthDistortion::kName, "measured_minus_model_rms_mm_at_" + num (distances[k]) + "m", std::sqrt (err2 / n));
      const std::size_t corner = 0;
      note (effects::DepthDistortion::kName, "model_bias_corner_mm_at_" + num (distances[k]) + "m", model[corner]);
      // The central row, averaged over the five rows around it.
      measured[k].assign (st.width, kNaN);
      predicted[k].assign (st.width, kNaN);
      for (int u = 0; u < st.width; ++u)
      {
        std::vector<double> b, m;
        for (int v = std::max (0, row - 2); v <= std::min (st.height - 1, row + 2); ++v)
        {
          b.push_back (bias[static_cast<std::size_t> (v) * st.width + u]);
          m.push_back (model[static_cast<std::size_t> (v) * st.width + u]);
        }
        measured[k][u] = meanOf (b);
        predicted[k][u] = meanOf (m);
      }
      if (distances[k] == 1.5)
      {
        write ("depth_distortion_map.dat", blockMap (bias, st.width, st.height, std::max (1, o_.width / 80)));
        write ("depth_distortion_model_map.dat", blockMap (model, st.width, st.height, std::max (1, o_.width / 80)));
      }
    }
    std::ostringstream out;
    out << "# u_px, then per depth: mean bias measured and model, mm   (rows " << row - 2 << ".." << row + 2
        << " of a frontal wall; bowl " << p.bowl_px << " px, ripple " << p.ripple_px << " px RMS, wavelength "
        << p.ripple_wavelength_px << " px)\n# u_px";
    for (const double d : distances)
      out << " bias_" << num (d) << "m model_" << num (d) << "m";
    out << "\n";
    for (int u = 0; u < o_.width; ++u)
    {
      out << u;
      for (std::size_t k = 0; k < distances.size (); ++k)
        out << " " << num (measured[k][u]) << " " << num (predicted[k][u]);
      out << "\n";
    }
    write ("depth_distortion_row.dat", out.str ());
  }

  /** Holes and SD vs the number of active projectors: a wall at 1.5 m seen by 1-3 sensors. */
  void
  interference ()
  {
    const effects::Interference::SimParameters p;
    std::ostringstream out;
    out << "# projectors sd_off_mm sd_on_mm model_sd_on_mm holes_off holes_on model_holes_on mean_load   "
           "(wall at 1.5 m, sensors 0.3 m apart aimed at its centre; sensor 0 recorded)\n"
        << "# holes: fraction of lit pixels without a reading; SD: central window; model: sqrt(1 + noise_gain L) and "
           "1 - exp(-dropout_rate L) with the foreign load L\n";
    for (int projectors = 1; projectors <= 3; ++projectors)
    {
      double sd[2], holes[2], model_sd = 0, model_holes = 0, load = 0;
      for (int with = 0; with < 2; ++with)
      {
        SimulationSettings s = settings ();
        setEffectEnabled (s.effects, effects::Interference::kName, with == 1);
        const KinectSimulator sim = simulator (planeSetup (1.5, 0, 0, projectors), s);
        const SensorTruth &t = sim.truth (0);
        const std::vector<DepthFrame> fr = frames (sim);
        const PixelStats st = pixelStats (sim, fr);
        std::vector<double> measured, predicted, loads, drop;
        double missing = 0, lit = 0;
        for (int v = 0; v < st.height; ++v)
          for (int u = 0; u < st.width; ++u)
          {
            const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
            if (!t.lit[i])
              continue;
            lit += static_cast<double> (fr.size ());
            missing += static_cast<double> (fr.size ()) - st.n[i];
            loads.push_back (t.foreign_load[i]);
            drop.push_back (effects::Interference::dropoutAt (p, t.foreign_load[i]));
            if (central (u, v))
            {
              measured.push_back (st.sd (i));
              predicted.push_back (
                  withRounding (effects::Interference::factor (p, t.foreign_load[i]) * paperSigma (u, v, st.truth[i])));
            }
          }
        sd[with] = meanOf (measured);
        holes[with] = missing / lit;
        if (with)
        {
          model_sd = meanOf (predicted);
          model_holes = meanOf (drop);
          load = meanOf (loads);
        }
        if (with && projectors == 3)
        {
          std::vector<double> hole_map (fr[0].depth_mm.size ());
          for (std::size_t i = 0; i < hole_map.size (); ++i)
            hole_map[i] = fr[0].depth_mm[i] == 0 ? 1.0 : 0.0;
          write ("interference_holes_map.dat", blockMap (hole_map, st.width, st.height, std::max (1, o_.width / 320)));
        }
      }
      out << projectors << " " << num (sd[0]) << " " << num (sd[1]) << " " << num (model_sd) << " " << num (holes[0])
          << " " << num (holes[1]) << " " << num (model_holes) << " " << num (load) << "\n";
      const std::string at = "_" + std::to_string (projectors) + "_projectors";
      note (effects::Interference::kName, "sd_off_mm" + at, sd[0]);
      note (effects::Interference::kName, "sd_on_mm" + at, sd[1]);
      note (effects::Interference::kName, "model_sd_on_mm" + at, model_sd);
      note (effects::Interference::kName, "holes_off" + at, holes[0]);
      note (effects::Interference::kName, "holes_on" + at, holes[1]);
      note (effects::Interference::kName, "model_holes_on" + at, model_holes);
      note (effects::Interference::kName, "mean_load" + at, load);
    }
    write ("interference.dat", out.str ());
  }

  /** Frame means of the residual vs frame index: base alone and base + temporal_drift. */
  void
  temporalDrift ()
  {
    const effects::TemporalDrift::SimParameters p;
    std::vector<double> mean[2];
    for (int with = 0; with < 2; ++with)
    {
      SimulationSettings s = settings ();
      setEffectEnabled (s.effects, effects::TemporalDrift::kName, with == 1);
      const KinectSimulator sim = simulator (planeSetup (1.5, 0, 0), s);
      const SensorTruth &t = sim.truth (0);
      for (const auto &f : frames (sim))
      {
        double sum = 0;
        int n = 0;
        for (std::size_t i = 0; i < f.depth_mm.size (); ++i)
          if (f.depth_mm[i] > 0)
          {
            sum += f.depth_mm[i] - 1000.0 * t.depth_m[i];
            ++n;
          }
        mean[with].push_back (sum / n);
      }
    }
    std::ostringstream out;
    out << "# frame mean_residual_base_mm mean_residual_drift_mm model_drift_mm   (frontal wall at 1.5 m; amplitude "
        << p.amplitude_px << " px, time constant " << p.time_constant_frames << " frames)\n"
        << "# model: 1000 (f b / (f b / z + amplitude exp(-frame / tau)) - z)\n";
    for (std::size_t k = 0; k < mean[0].size (); ++k)
    {
      const double model = offsetDepth (1500.0, effects::TemporalDrift::frameOffset (p, static_cast<std::uint32_t> (k))) - 1500.0;
      out << k << " " << num (mean[0][k]) << " " << num (mean[1][k]) << " " << num (model) << "\n";
      if (k == 0 || k == 10 || k + 1 == mean[0].size ())
      {
        note (effects::TemporalDrift::kName, "mean_residual_drift_mm_frame_" + std::to_string (k), mean[1][k]);
        note (effects::TemporalDrift::kName, "model_drift_mm_frame_" + std::to_string (k), model);
        note (effects::TemporalDrift::kName, "mean_residual_base_mm_frame_" + std::to_string (k), mean[0][k]);
      }
    }
    write ("temporal_drift.dat", out.str ());
  }

  /** Which side of a depth step each pixel reports, by column: base alone and base + lateral_noise. */
  void
  lateralNoise ()
  {
    const effects::LateralNoise::SimParameters p;
    const double z_front = 1.5, z_back = 1.8, z_split = 0.5 * (z_front + z_back);
    // A panel at 1.5 m over the left half of the view before a wall at 1.8 m: the projector,
    // to the camera's right, casts no visible shadow on this side of the panel.
    auto scene = std::make_shared<Scene> ();
    scene->add (std::make_shared<PlaneSurface> (Eigen::Vector3d (0, 0, z_back), Eigen::Vector3d (0, 0, -1)));
    scene->add (std::make_shared<RectangleSurface> (Eigen::Vector3d (-1.0, 0, z_front), Eigen::Vector3d (0, 0, -1),
                                                    Eigen::Vector3d::UnitX (), 1.0, 2.0));
    const int span = 6, window = 8;
    std::vector<double> front[2];
    std::vector<double> positions[2];
    std::vector<DepthFrame> fr[2];
    int edge = 0;
    for (int with = 0; with < 2; ++with)
    {
      SimulationSettings s = settings ();
      setEffectEnabled (s.effects, effects::LateralNoise::kName, with == 1);
      const KinectSimulator sim = simulator (scene, s);
      const SensorTruth &t = sim.truth (0);
      const int row = static_cast<int> (std::lround (model_.cy));
      edge = 0; // the first column of the central row on the back wall
      while (edge < t.width && t.depth_m[static_cast<std::size_t> (row) * t.width + edge] < z_split)
        ++edge;
      fr[with] = frames (sim);
      front[with].assign (2 * span, 0.0);
      for (const auto &f : fr[with])
        for (int v = 0; v < f.height; ++v)
        {
          const auto on_front = [&] (int u) {
            const std::uint16_t d = f.depth_mm[static_cast<std::size_t> (v) * f.width + u];
            return d > 0 && d < 1000.0 * z_split;
          };
          for (int k = 0; k < 2 * span; ++k)
          {
            const int u = edge - span + k;
            if (u >= 0 && u < f.width)
              front[with][k] += on_front (u) ? 1.0 : 0.0;
          }
          // The row's edge position: where a clean step with as many front pixels would be.
          int count = 0;
          for (int u = std::max (0, edge - window); u < std::min (f.width, edge + window); ++u)
            count += on_front (u) ? 1 : 0;
          positions[with].push_back (std::max (0, edge - window) + count - edge);
        }
      for (auto &x : front[with])
        x /= static_cast<double> (fr[with].size ()) * model_.height;
    }
    std::ostringstream out;
    out << "# column_minus_edge_px fraction_front_base fraction_front_lateral model_lateral   (panel at " << z_front
        << " m left of column " << edge << ", wall at " << z_back << " m; sigma " << p.sigma_px << " px)\n"
        << "# model: P(u + round(sigma g) < edge) = Phi((edge - 0.5 - u) / sigma)\n";
    for (int k = 0; k < 2 * span; ++k)
    {
      const int offset = k - span;
      out << offset << " " << num (front[0][k]) << " " << num (front[1][k]) << " "
          << num (normalCdf ((-0.5 - offset) / p.sigma_px)) << "\n";
    }
    write ("lateral_noise.dat", out.str ());
    std::ostringstream crop;
    const int row = static_cast<int> (std::lround (model_.cy)), half = std::max (2, o_.width / 32);
    crop << "# u_px v_px depth_mm: frame 0 with lateral noise, around the step at column " << edge << "\n";
    for (int v = std::max (0, row - half); v < std::min (o_.height, row + half); ++v)
    {
      for (int u = std::max (0, edge - half); u < std::min (o_.width, edge + half); ++u)
      {
        const std::uint16_t d = fr[1][0].depth_mm[static_cast<std::size_t> (v) * o_.width + u];
        crop << u << " " << v << " " << (d > 0 ? std::to_string (d) : std::string ("NaN")) << "\n";
      }
      crop << "\n";
    }
    write ("lateral_noise_crop.dat", crop.str ());
    // Away from the step the readings must be those of the base noise, byte for byte.
    std::size_t differ = 0, compared = 0;
    const int clear = static_cast<int> (std::ceil (6 * p.sigma_px)) + 1;
    for (std::size_t f = 0; f < fr[0].size (); ++f)
      for (int v = 0; v < o_.height; ++v)
        for (int u = 0; u < o_.width; ++u)
          if (std::abs (u - edge) > clear)
          {
            const std::size_t i = static_cast<std::size_t> (v) * o_.width + u;
            ++compared;
            differ += fr[0][f].depth_mm[i] != fr[1][f].depth_mm[i] ? 1 : 0;
          }
    note (effects::LateralNoise::kName, "edge_column", edge, 6);
    note (effects::LateralNoise::kName, "edge_position_sd_base_px", sdOf (positions[0]));
    note (effects::LateralNoise::kName, "edge_position_sd_lateral_px", sdOf (positions[1]));
    note (effects::LateralNoise::kName, "pixels_changed_away_from_edge", static_cast<double> (differ), 8);
    note (effects::LateralNoise::kName, "pixels_compared_away_from_edge", static_cast<double> (compared), 10);
  }

  /** Geometry back-projected with the labelled intrinsics: lateral error and fitted wall tilt. */
  void
  intrinsics ()
  {
    const effects::Intrinsics::SimParameters p;
    SimulationSettings s = settings ();
    setEffectEnabled (s.effects, effects::Intrinsics::kName, true);
    const auto cloud = [&] (const KinectSimulator &sim, const DepthFrame &f, const CameraModel &cam) {
      std::vector<Eigen::Vector3d> points (f.depth_mm.size (), Eigen::Vector3d::Constant (kNaN));
      for (int v = 0; v < f.height; ++v)
        for (int u = 0; u < f.width; ++u)
        {
          const std::size_t i = static_cast<std::size_t> (v) * f.width + u;
          if (f.depth_mm[i] == 0)
            continue;
          double x, y;
          cam.pixelToRay (u, v, x, y);
          const double z = 1e-3 * f.depth_mm[i];
          points[i] = Eigen::Vector3d (x * z, y * z, z);
        }
      (void) sim;
      return points;
    };
    const auto tiltOf = [] (const std::vector<Eigen::Vector3d> &points) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero ();
      int n = 0;
      for (const auto &q : points)
        if (q.allFinite ())
        {
          mean += q;
          ++n;
        }
      mean /= n;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero ();
      for (const auto &q : points)
        if (q.allFinite ())
          cov += (q - mean) * (q - mean).transpose ();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es (cov);
      const Eigen::Vector3d normal = es.eigenvectors ().col (0);
      return std::acos (std::min (1.0, std::fabs (normal.z ()))) * 180.0 / M_PI;
    };

    // Lateral error along the central row of a frontal wall.
    {
      const KinectSimulator sim = simulator (planeSetup (1.5, 0, 0), s);
      const PinholeModel labelled = PinholeModel::fromCameraInfo (sim.cameraInfo (0));
      const PinholeModel truth (model_.fx, model_.fy, model_.cx, model_.cy);
      const DepthFrame f = sim.simulateFrame (0, 0);
      const auto a = cloud (sim, f, labelled), b = cloud (sim, f, truth);
      const int row = static_cast<int> (std::lround (model_.cy));
      std::ostringstream out;
      out << "# u_px x_true_m x_labelled_m x_error_mm model_error_mm   (frontal wall at 1.5 m, row " << row
          << "; camera.yaml fx = " << num (labelled.fx ()) << " px, rendered with " << num (model_.fx) << " px)\n"
          << "# model: x (1 / focal_scale - 1)\n";
      double max_err = 0;
      for (int u = 0; u < f.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (row) * f.width + u;
        if (!a[i].allFinite ())
          continue;
        const double err = 1000.0 * (a[i].x () - b[i].x ());
        out << u << " " << num (b[i].x ()) << " " << num (a[i].x ()) << " " << num (err) << " "
            << num (1000.0 * b[i].x () * (1.0 / p.focal_scale - 1.0)) << "\n";
        max_err = std::max (max_err, std::fabs (err));
      }
      write ("intrinsics_row.dat", out.str ());
      note (effects::Intrinsics::kName, "labelled_fx_px", labelled.fx ());
      note (effects::Intrinsics::kName, "max_lateral_error_mm_at_1.5m", max_err);
      note (effects::Intrinsics::kName, "lateral_scale_percent", 100.0 * (1.0 / p.focal_scale - 1.0));
    }
    // The fitted tilt of walls turned about the image y axis.
    std::ostringstream out;
    out << "# tilt_deg fitted_true_intrinsics_deg fitted_labelled_deg model_labelled_deg   (wall at 1.5 m, frame 0; "
           "focal_scale "
        << p.focal_scale << ")\n# model: atan(focal_scale tan(tilt))\n";
    for (const double tilt : {0.0, 10.0, 20.0, 30.0, 40.0, 45.0, 50.0, 60.0, 70.0})
    {
      const KinectSimulator sim = simulator (planeSetup (1.5, 0, tilt), s);
      const PinholeModel labelled = PinholeModel::fromCameraInfo (sim.cameraInfo (0));
      const PinholeModel truth (model_.fx, model_.fy, model_.cx, model_.cy);
      const DepthFrame f = sim.simulateFrame (0, 0);
      const double fitted_true = tiltOf (cloud (sim, f, truth)), fitted_labelled = tiltOf (cloud (sim, f, labelled));
      const double model = std::atan (p.focal_scale * std::tan (tilt * M_PI / 180.0)) * 180.0 / M_PI;
      out << num (tilt) << " " << num (fitted_true) << " " << num (fitted_labelled) << " " << num (model) << "\n";
      if (tilt == 45.0)
      {
        note (effects::Intrinsics::kName, "fitted_tilt_true_deg_at_45", fitted_true);
        note (effects::Intrinsics::kName, "fitted_tilt_labelled_deg_at_45", fitted_labelled);
        note (effects::Intrinsics::kName, "model_tilt_labelled_deg_at_45", model);
      }
    }
    write ("intrinsics_tilt.dat", out.str ());
  }

  const Options &o_;
  fs::path out_;
  DepthSensor model_;
  double fb_ = 0;
  NoiseModel paper_ = NoiseModel::paper ();
  std::map<std::string, std::string> summary_;
};

int
run (int argc, char **argv)
{
  Options o;
  CLI::App app ("Measure what each physical effect of the simulator does to a simulated wall, beside the closed-form\n"
                "prediction, and write gnuplot data files (see docs/sensor_model.md and\n"
                "scripts/make_sensor_model_figures.sh, which draws them).",
                kName);
  std::string names;
  for (const auto &n : figureNames ())
    names += (names.empty () ? "" : ", ") + n;
  app.add_option ("OUTPUT", o.output, "folder for the data files (created if missing)");
  app.add_option ("--width", o.width, "image width, pixels (focal length 580 x width / 640)")->capture_default_str ();
  app.add_option ("--height", o.height, "image height, pixels")->capture_default_str ();
  app.add_option ("--frames", o.frames, "frames per simulated recording")->capture_default_str ();
  app.add_option ("--seed", o.seed, "random seed")->capture_default_str ();
  app.add_option ("--only", o.only, "make only these figures (repeatable): " + names)->allow_extra_args (false);
  app.add_option ("-j,--threads", o.threads, "threads (0: all)")->capture_default_str ();
  app.add_flag ("-q,--quiet", o.quiet, "no progress on stdout");
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv))
    return 0;

  if (o.output.empty ())
    throw InputError ("OUTPUT is required (the folder for the data files)");
  if (o.width < 32 || o.height < 24 || o.width > 4096 || o.height > 4096)
    throw InputError ("--width and --height must be between 32x24 and 4096x4096 (got " + std::to_string (o.width) +
                      "x" + std::to_string (o.height) + ")");
  if (o.frames < 2 || o.frames > 10000)
    throw InputError ("--frames must be between 2 and 10000 (got " + std::to_string (o.frames) +
                      "): a temporal SD needs two frames");
  if (o.threads > 1024)
    throw InputError ("--threads " + std::to_string (o.threads) + " is not a sensible thread count");
  std::vector<std::string> todo = o.only.empty () ? figureNames () : o.only;
  for (const auto &n : todo)
    if (std::find (figureNames ().begin (), figureNames ().end (), n) == figureNames ().end ())
      throw InputError ("--only: unknown figure '" + n + "' (known: " + names + ")");

  std::error_code ec;
  const fs::path out = fs::absolute (o.output, ec);
  if (fs::exists (out, ec) && !fs::is_directory (out, ec))
    throw InputError ("OUTPUT '" + o.output + "' exists and is not a folder");
  if (!fs::exists (out, ec))
  {
    if (!fs::is_directory (out.parent_path (), ec))
      throw InputError ("the folder that should hold OUTPUT '" + o.output + "' does not exist");
    if (!fs::create_directory (out, ec))
      throw InputError ("cannot create OUTPUT '" + o.output + "': " + ec.message ());
  }

  FigureMaker maker (o, out);
  for (std::size_t k = 0; k < todo.size (); ++k)
  {
    if (!o.quiet)
      std::cout << "[" << k + 1 << "/" << todo.size () << "] " << todo[k] << std::endl;
    maker.make (todo[k]);
  }
  maker.writeSummary ();
  if (!o.quiet)
    std::cout << "data files and summary.txt in " << o.output << std::endl;
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp (kName, run, argc, argv);
}
