#include "studies.h"

#include <pcl_texlet/noise/effects/incidence_angle.h>

void
pcl_texlet_sensor_figures::measureIncidenceAngle (Figures &figures)
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
      SimulationSettings s = figures.settings ();
      setEffectEnabled (s.effects, effects::IncidenceAngle::kName, with == 1);
      const KinectSimulator sim = figures.simulator (planeSetup (1.5, 0, tilt), s);
      const SensorTruth &t = sim.truth (0);
      const PixelStats st = pixelStats (sim, figures.frames (sim));
      std::vector<double> measured, predicted;
      double readings = 0, pixels = 0;
      for (int v = 0; v < st.height; ++v)
        for (int u = 0; u < st.width; ++u)
          if (figures.central (u, v))
          {
            const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
            const double factor = with ? effects::IncidenceAngle::factor (p, t.cos_incidence[i]) : 1.0;
            measured.push_back (st.sd (i));
            if (!(with && effects::IncidenceAngle::tooOblique (p, t.cos_incidence[i])))
              predicted.push_back (withRounding (factor * figures.paperSigma (u, v, st.truth[i])));
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
        figures.note (effects::IncidenceAngle::kName, "sd_base_mm_at_" + num (at) + "deg", sd[0]);
        figures.note (effects::IncidenceAngle::kName, "sd_incidence_mm_at_" + num (at) + "deg", sd[1]);
        figures.note (effects::IncidenceAngle::kName, "model_incidence_mm_at_" + num (at) + "deg", model[1]);
        figures.note (effects::IncidenceAngle::kName, "valid_incidence_at_" + num (at) + "deg", valid[1]);
      }
  }
  figures.write ("incidence_angle.dat", out.str ());
}
