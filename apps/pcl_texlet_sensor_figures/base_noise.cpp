#include "studies.h"

void
pcl_texlet_sensor_figures::measureBaseNoise (Figures &figures)
{
  const std::vector<double> distances = {0.8, 1.2, 1.6};
  std::vector<RadialProfile> measured (distances.size ()), predicted (distances.size ());
  for (std::size_t k = 0; k < distances.size (); ++k)
  {
    const KinectSimulator sim = figures.simulator (planeSetup (distances[k], 0, 0), figures.settings ());
    const PixelStats st = pixelStats (sim, figures.frames (sim));
    measured[k].bin_px = predicted[k].bin_px = figures.radialBin ();
    for (int v = 0; v < st.height; ++v)
      for (int u = 0; u < st.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
        measured[k].add (figures.radius (u, v), st.sd (i));
        predicted[k].add (figures.radius (u, v), withRounding (figures.paperSigma (u, v, st.truth[i])));
      }
    figures.note ("base_noise", "sd_centre_mm_at_" + num (distances[k]) + "m", measured[k].mean (0));
    figures.note ("base_noise", "model_centre_mm_at_" + num (distances[k]) + "m", predicted[k].mean (0));
    const std::size_t outer = measured[k].sum.size () - 1;
    figures.note ("base_noise", "sd_outer_mm_at_" + num (distances[k]) + "m", measured[k].mean (outer));
    figures.note ("base_noise", "model_outer_mm_at_" + num (distances[k]) + "m", predicted[k].mean (outer));
  }
  figures.note ("base_noise", "outer_radius_px", measured[0].centre (measured[0].sum.size () - 1));
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
  figures.write ("base_noise_radius.dat", out.str ());

  const KinectSimulator sim = figures.simulator (planeSetup (1.5, 0, 0), figures.settings ());
  const PixelStats st = pixelStats (sim, figures.frames (sim));
  std::vector<double> sd (st.n.size ());
  for (std::size_t i = 0; i < sd.size (); ++i)
    sd[i] = st.sd (i);
  figures.write ("base_noise_map.dat",
                 blockMap (sd, st.width, st.height, std::max (1, figures.options ().width / 160)));
  figures.note ("base_noise", "sd_mean_mm_at_1.5m", meanOf (sd));
}
