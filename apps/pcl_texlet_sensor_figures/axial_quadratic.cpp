#include "studies.h"

#include <pcl_texlet/noise/effects/axial_quadratic.h>

void
pcl_texlet_sensor_figures::measureAxialQuadratic (Figures &figures)
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
      SimulationSettings s = figures.settings ();
      setEffectEnabled (s.effects, effects::AxialQuadratic::kName, with == 1);
      const KinectSimulator sim = figures.simulator (planeSetup (z, 0, 0), s);
      const PixelStats st = pixelStats (sim, figures.frames (sim));
      std::vector<double> measured, predicted;
      for (int v = 0; v < st.height; ++v)
        for (int u = 0; u < st.width; ++u)
          if (figures.central (u, v))
          {
            const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
            const double base = figures.paperSigma (u, v, st.truth[i]);
            const double axial =
                with ? 1000.0 * kernels::depthSigmaFromDisparitySigma (sigma_px, z, figures.fb ()) : 0.0;
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
        figures.note (effects::AxialQuadratic::kName, "sd_base_mm_at_" + num (at) + "m", sd[0]);
        figures.note (effects::AxialQuadratic::kName, "sd_axial_mm_at_" + num (at) + "m", sd[1]);
        figures.note (effects::AxialQuadratic::kName, "model_axial_mm_at_" + num (at) + "m", model[1]);
        figures.note (effects::AxialQuadratic::kName, "axial_term_mm_at_" + num (at) + "m",
              1000.0 * kernels::depthSigmaFromDisparitySigma (sigma_px, at, figures.fb ()));
      }
  }
  figures.write ("axial_quadratic.dat", out.str ());
}
