#include "studies.h"

#include <pcl_texlet/noise/effects/temporal_drift.h>

void
pcl_texlet_sensor_figures::measureTemporalDrift (Figures &figures)
{
  const effects::TemporalDrift::SimParameters p;
  std::vector<double> mean[2];
  for (int with = 0; with < 2; ++with)
  {
    SimulationSettings s = figures.settings ();
    setEffectEnabled (s.effects, effects::TemporalDrift::kName, with == 1);
    const KinectSimulator sim = figures.simulator (planeSetup (1.5, 0, 0), s);
    const SensorTruth &t = sim.truth (0);
    for (const auto &f : figures.frames (sim))
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
    const double model =
        figures.offsetDepth (1500.0, effects::TemporalDrift::frameOffset (p, static_cast<std::uint32_t> (k))) - 1500.0;
    out << k << " " << num (mean[0][k]) << " " << num (mean[1][k]) << " " << num (model) << "\n";
    if (k == 0 || k == 10 || k + 1 == mean[0].size ())
    {
      figures.note (effects::TemporalDrift::kName, "mean_residual_drift_mm_frame_" + std::to_string (k), mean[1][k]);
      figures.note (effects::TemporalDrift::kName, "model_drift_mm_frame_" + std::to_string (k), model);
      figures.note (effects::TemporalDrift::kName, "mean_residual_base_mm_frame_" + std::to_string (k), mean[0][k]);
    }
  }
  figures.write ("temporal_drift.dat", out.str ());
}
