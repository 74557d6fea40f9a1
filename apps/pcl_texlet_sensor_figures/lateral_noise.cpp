#include "studies.h"

#include <pcl_texlet/noise/effects/lateral_noise.h>

#include <Eigen/Core>

#include <memory>

void
pcl_texlet_sensor_figures::measureLateralNoise (Figures &figures)
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
    SimulationSettings s = figures.settings ();
    setEffectEnabled (s.effects, effects::LateralNoise::kName, with == 1);
    const KinectSimulator sim = figures.simulator (scene, s);
    const SensorTruth &t = sim.truth (0);
    const int row = static_cast<int> (std::lround (figures.sensor ().cy));
    edge = 0; // the first column of the central row on the back wall
    while (edge < t.width && t.depth_m[static_cast<std::size_t> (row) * t.width + edge] < z_split)
      ++edge;
    fr[with] = figures.frames (sim);
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
      x /= static_cast<double> (fr[with].size ()) * figures.sensor ().height;
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
  figures.write ("lateral_noise.dat", out.str ());
  std::ostringstream crop;
  const int row = static_cast<int> (std::lround (figures.sensor ().cy)),
            half = std::max (2, figures.options ().width / 32);
  crop << "# u_px v_px depth_mm: frame 0 with lateral noise, around the step at column " << edge << "\n";
  for (int v = std::max (0, row - half); v < std::min (figures.options ().height, row + half); ++v)
  {
    for (int u = std::max (0, edge - half); u < std::min (figures.options ().width, edge + half); ++u)
    {
      const std::uint16_t d = fr[1][0].depth_mm[static_cast<std::size_t> (v) * figures.options ().width + u];
      crop << u << " " << v << " " << (d > 0 ? std::to_string (d) : std::string ("NaN")) << "\n";
    }
    crop << "\n";
  }
  figures.write ("lateral_noise_crop.dat", crop.str ());
  // Away from the step the readings must be those of the base noise, byte for byte.
  std::size_t differ = 0, compared = 0;
  const int clear = static_cast<int> (std::ceil (6 * p.sigma_px)) + 1;
  for (std::size_t f = 0; f < fr[0].size (); ++f)
    for (int v = 0; v < figures.options ().height; ++v)
      for (int u = 0; u < figures.options ().width; ++u)
        if (std::abs (u - edge) > clear)
        {
          const std::size_t i = static_cast<std::size_t> (v) * figures.options ().width + u;
          ++compared;
          differ += fr[0][f].depth_mm[i] != fr[1][f].depth_mm[i] ? 1 : 0;
        }
  figures.note (effects::LateralNoise::kName, "edge_column", edge, 6);
  figures.note (effects::LateralNoise::kName, "edge_position_sd_base_px", sdOf (positions[0]));
  figures.note (effects::LateralNoise::kName, "edge_position_sd_lateral_px", sdOf (positions[1]));
  figures.note (effects::LateralNoise::kName, "pixels_changed_away_from_edge", static_cast<double> (differ), 8);
  figures.note (effects::LateralNoise::kName, "pixels_compared_away_from_edge", static_cast<double> (compared), 10);
}
