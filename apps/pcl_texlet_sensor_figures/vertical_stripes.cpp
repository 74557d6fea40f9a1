#include "studies.h"

#include <pcl_texlet/noise/effects/vertical_stripes.h>

void
pcl_texlet_sensor_figures::measureVerticalStripes (Figures &figures)
{
  const effects::VerticalStripes::SimParameters p;
  // Frame 0 and the first frame of the next layout.
  const std::uint32_t later = static_cast<std::uint32_t> (p.period_frames);
  std::vector<double> profile[3];
  std::vector<double> residual_map;
  for (int run = 0; run < 3; ++run)
  {
    SimulationSettings s = figures.settings ();
    setEffectEnabled (s.effects, effects::VerticalStripes::kName, run > 0);
    const KinectSimulator sim = figures.simulator (planeSetup (1.5, 0, 0), s);
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
  figures.write ("vertical_stripes_profile.dat", out.str ());
  figures.write ("vertical_stripes_map.dat",
                 blockMap (residual_map, figures.options ().width, figures.options ().height,
                           std::max (1, figures.options ().width / 160)));
  const auto jump = [] (const std::vector<double> &c) {
    double m = 0;
    for (std::size_t u = 1; u < c.size (); ++u)
      if (std::isfinite (c[u]) && std::isfinite (c[u - 1]))
        m = std::max (m, std::fabs (c[u] - c[u - 1]));
    return m;
  };
  figures.note (effects::VerticalStripes::kName, "column_mean_sd_base_mm", sdOf (profile[0]));
  figures.note (effects::VerticalStripes::kName, "column_mean_sd_stripes_mm", sdOf (profile[1]));
  figures.note (effects::VerticalStripes::kName, "largest_column_jump_base_mm", jump (profile[0]));
  figures.note (effects::VerticalStripes::kName, "largest_column_jump_stripes_mm", jump (profile[1]));
  figures.note (effects::VerticalStripes::kName, "band_offset_sd_model_mm",
                1000.0 * kernels::depthSigmaFromDisparitySigma (p.offset_px, 1.5, figures.fb ()));
}
