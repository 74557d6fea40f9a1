#include "studies.h"

#include <pcl_texlet/noise/effects/disparity_quantization.h>

#include <map>

void
pcl_texlet_sensor_figures::measureDisparityQuantization (Figures &figures)
{
  const double step = effects::DisparityQuantization::SimParameters ().step_px;
  const double z = 1.5;
  std::map<int, std::size_t> hist[2];
  std::size_t total[2] = {0, 0};
  for (int with = 0; with < 2; ++with)
  {
    SimulationSettings s = figures.settings ();
    setEffectEnabled (s.effects, effects::DisparityQuantization::kName, with == 1);
    const KinectSimulator sim = figures.simulator (planeSetup (z, 0, 0), s);
    for (const auto &f : figures.frames (sim))
      for (const auto d : f.depth_mm)
        if (d > 0)
        {
          ++hist[with][d];
          ++total[with];
        }
  }
  const int zmm = static_cast<int> (std::lround (1000 * z));
  const int half = static_cast<int> (std::ceil (3.5 * 1000 * kernels::depthStep (z, step, figures.fb ()))) + 5;
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
  figures.write ("disparity_quantization_hist.dat", out.str ());
  std::ostringstream lattice;
  lattice << "# k depth_mm: the depths of disparity k * " << step
          << " px, 1000 f b / (k step), f b = " << num (figures.fb ()) << " px m\n";
  const int k0 = static_cast<int> (std::lround (kernels::disparityFromDepth (z, figures.fb ()) / step));
  for (int k = k0 - 4; k <= k0 + 4; ++k)
    lattice << k << " " << num (1000.0 * kernels::depthFromDisparity (k * step, figures.fb ()), 7) << "\n";
  figures.write ("disparity_quantization_lattice.dat", lattice.str ());
  figures.note (effects::DisparityQuantization::kName, "step_mm_at_1.5m",
                1000.0 * kernels::depthStep (z, step, figures.fb ()));
  figures.note (effects::DisparityQuantization::kName, "distinct_depths_base", static_cast<double> (hist[0].size ()),
                6);
  figures.note (effects::DisparityQuantization::kName, "distinct_depths_quantised",
                static_cast<double> (hist[1].size ()), 6);
  {
    std::size_t most = 0;
    for (const auto &kv : hist[1])
      most = std::max (most, kv.second);
    figures.note (effects::DisparityQuantization::kName, "largest_bin_fraction_quantised",
                  static_cast<double> (most) / total[1]);
  }

  // The staircase: mean reported minus true depth along the central row of a wall tilted 5 deg
  // (gently, so that one depth step spans tens of columns).
  PixelStats st[2];
  for (int with = 0; with < 2; ++with)
  {
    SimulationSettings s = figures.settings ();
    setEffectEnabled (s.effects, effects::DisparityQuantization::kName, with == 1);
    const KinectSimulator sim = figures.simulator (planeSetup (z, 0, 5), s);
    st[with] = pixelStats (sim, figures.frames (sim));
  }
  const int row = static_cast<int> (std::lround (figures.sensor ().cy));
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
          << num (0.5 * 1000.0 * kernels::depthStep (1e-3 * st[0].truth[i], step, figures.fb ())) << "\n";
    errs.push_back (std::fabs (st[1].bias (i)));
  }
  figures.write ("disparity_quantization_staircase.dat", stair.str ());
  figures.note (effects::DisparityQuantization::kName, "max_abs_mean_error_quantised_mm",
                *std::max_element (errs.begin (), errs.end ()));
}
