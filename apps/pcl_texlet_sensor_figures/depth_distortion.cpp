#include "studies.h"

#include <pcl_texlet/noise/effects/depth_distortion.h>

void
pcl_texlet_sensor_figures::measureDepthDistortion (Figures &figures)
{
  const effects::DepthDistortion::SimParameters p;
  const std::vector<double> distances = {1.0, 1.5, 2.0};
  const DepthSensor &sensor = figures.sensor ();
  const double r_corner = std::sqrt (std::pow (std::max (sensor.cx, sensor.width - 1 - sensor.cx), 2) +
                                     std::pow (std::max (sensor.cy, sensor.height - 1 - sensor.cy), 2));
  const int row = static_cast<int> (std::lround (sensor.cy));
  std::vector<std::vector<double>> measured (distances.size ()), predicted (distances.size ());
  for (std::size_t k = 0; k < distances.size (); ++k)
  {
    SimulationSettings s = figures.settings ();
    setEffectEnabled (s.effects, effects::DepthDistortion::kName, true);
    const KinectSimulator sim = figures.simulator (planeSetup (distances[k], 0, 0), s);
    const PixelStats st = pixelStats (sim, figures.frames (sim));
    std::vector<double> bias (st.n.size ()), model (st.n.size ());
    double err2 = 0, model2 = 0;
    int n = 0;
    for (int v = 0; v < st.height; ++v)
      for (int u = 0; u < st.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * st.width + u;
        bias[i] = st.bias (i);
        const double offset_px =
            effects::DepthDistortion::offset (p, figures.options ().seed, 0, u, v, sensor.cx, sensor.cy, r_corner);
        model[i] = figures.offsetDepth (st.truth[i], offset_px) - st.truth[i];
        if (std::isfinite (bias[i]))
        {
          err2 += (bias[i] - model[i]) * (bias[i] - model[i]);
          model2 += model[i] * model[i];
          ++n;
        }
      }
    figures.note (effects::DepthDistortion::kName, "bias_rms_model_mm_at_" + num (distances[k]) + "m",
                  std::sqrt (model2 / n));
    figures.note (effects::DepthDistortion::kName, "measured_minus_model_rms_mm_at_" + num (distances[k]) + "m",
                  std::sqrt (err2 / n));
    const std::size_t corner = 0;
    figures.note (effects::DepthDistortion::kName, "model_bias_corner_mm_at_" + num (distances[k]) + "m",
                  model[corner]);
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
      figures.write ("depth_distortion_map.dat",
                     blockMap (bias, st.width, st.height, std::max (1, figures.options ().width / 80)));
      figures.write ("depth_distortion_model_map.dat",
                     blockMap (model, st.width, st.height, std::max (1, figures.options ().width / 80)));
    }
  }
  std::ostringstream out;
  out << "# u_px, then per depth: mean bias measured and model, mm   (rows " << row - 2 << ".." << row + 2
      << " of a frontal wall; bowl " << p.bowl_px << " px, ripple " << p.ripple_px << " px RMS, wavelength "
      << p.ripple_wavelength_px << " px)\n# u_px";
  for (const double d : distances)
    out << " bias_" << num (d) << "m model_" << num (d) << "m";
  out << "\n";
  for (int u = 0; u < figures.options ().width; ++u)
  {
    out << u;
    for (std::size_t k = 0; k < distances.size (); ++k)
      out << " " << num (measured[k][u]) << " " << num (predicted[k][u]);
    out << "\n";
  }
  figures.write ("depth_distortion_row.dat", out.str ());
}
