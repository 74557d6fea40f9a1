#include "studies.h"

#include <pcl_texlet/noise/effects/radial.h>

void
pcl_texlet_sensor_figures::measureRadial (Figures &figures)
{
  const effects::Radial::SimParameters p;
  RadialProfile measured[2], predicted[2];
  for (int with = 0; with < 2; ++with)
  {
    SimulationSettings s = figures.settings ();
    setEffectEnabled (s.effects, effects::Radial::kName, with == 1);
    const KinectSimulator sim = figures.simulator (planeSetup (1.5, 0, 0), s);
    const PixelStats st = pixelStats (sim, figures.frames (sim));
    measured[with].bin_px = predicted[with].bin_px = figures.radialBin ();
    for (int v = 0; v < st.height; ++v)
      for (int u = 0; u < st.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
        const double factor = with ? effects::Radial::factor (p, figures.radius (u, v)) : 1.0;
        measured[with].add (figures.radius (u, v), st.sd (i));
        predicted[with].add (figures.radius (u, v), withRounding (factor * figures.paperSigma (u, v, st.truth[i])));
      }
  }
  std::ostringstream out;
  out << "# radius_px sd_base_mm sd_radial_mm model_base_mm model_radial_mm   (wall at 1.5 m; gain " << p.gain
      << ", reference radius " << p.reference_radius_px << " px)\n"
      << "# model_radial: sqrt((f(r,d) (1 + gain (r/r_ref)^2))^2 + 1/12)\n";
  for (std::size_t b = 0; b < measured[0].sum.size (); ++b)
    out << num (measured[0].centre (b)) << " " << num (measured[0].mean (b)) << " " << num (measured[1].mean (b))
        << " " << num (predicted[0].mean (b)) << " " << num (predicted[1].mean (b)) << "\n";
  figures.write ("radial.dat", out.str ());
  const std::size_t outer = measured[0].sum.size () - 1;
  figures.note (effects::Radial::kName, "outer_radius_px", measured[0].centre (outer));
  figures.note (effects::Radial::kName, "sd_base_outer_mm", measured[0].mean (outer));
  figures.note (effects::Radial::kName, "sd_radial_outer_mm", measured[1].mean (outer));
  figures.note (effects::Radial::kName, "model_radial_outer_mm", predicted[1].mean (outer));
  figures.note (effects::Radial::kName, "sd_base_centre_mm", measured[0].mean (0));
  figures.note (effects::Radial::kName, "sd_radial_centre_mm", measured[1].mean (0));
}
