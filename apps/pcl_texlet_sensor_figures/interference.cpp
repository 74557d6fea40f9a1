#include "studies.h"

#include <pcl_texlet/noise/effects/interference.h>

void
pcl_texlet_sensor_figures::measureInterference (Figures &figures)
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
      SimulationSettings s = figures.settings ();
      setEffectEnabled (s.effects, effects::Interference::kName, with == 1);
      const KinectSimulator sim = figures.simulator (planeSetup (1.5, 0, 0, projectors), s);
      const SensorTruth &t = sim.truth (0);
      const std::vector<DepthFrame> fr = figures.frames (sim);
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
          if (figures.central (u, v))
          {
            measured.push_back (st.sd (i));
            predicted.push_back (withRounding (effects::Interference::factor (p, t.foreign_load[i]) *
                                               figures.paperSigma (u, v, st.truth[i])));
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
        figures.write ("interference_holes_map.dat",
                       blockMap (hole_map, st.width, st.height, std::max (1, figures.options ().width / 320)));
      }
    }
    out << projectors << " " << num (sd[0]) << " " << num (sd[1]) << " " << num (model_sd) << " " << num (holes[0])
        << " " << num (holes[1]) << " " << num (model_holes) << " " << num (load) << "\n";
    const std::string at = "_" + std::to_string (projectors) + "_projectors";
    figures.note (effects::Interference::kName, "sd_off_mm" + at, sd[0]);
    figures.note (effects::Interference::kName, "sd_on_mm" + at, sd[1]);
    figures.note (effects::Interference::kName, "model_sd_on_mm" + at, model_sd);
    figures.note (effects::Interference::kName, "holes_off" + at, holes[0]);
    figures.note (effects::Interference::kName, "holes_on" + at, holes[1]);
    figures.note (effects::Interference::kName, "model_holes_on" + at, model_holes);
    figures.note (effects::Interference::kName, "mean_load" + at, load);
  }
  figures.write ("interference.dat", out.str ());
}
