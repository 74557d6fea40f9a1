#include "studies.h"

#include <Eigen/Core>

#include <memory>

void
pcl_texlet_sensor_figures::measureProjectorShadows (Figures &figures)
{
  const double z_front = 1.5;
  const std::vector<double> backs = {1.6, 1.8, 2.0, 2.5, 3.0};
  std::ostringstream widths;
  widths << "# z_back_m width_measured_px width_model_px   (front: a panel at " << z_front
         << " m covering x > 0, its edge on the optical axis)\n"
         << "# model: f b (1/z_front - 1/z_back), the disparity difference across the step\n";
  for (const double zb : backs)
  {
    for (const bool shadows : {true, false})
    {
      auto scene = std::make_shared<Scene> ();
      scene->add (std::make_shared<PlaneSurface> (Eigen::Vector3d (0, 0, zb), Eigen::Vector3d (0, 0, -1)));
      scene->add (std::make_shared<RectangleSurface> (Eigen::Vector3d (1.0, 0, z_front), Eigen::Vector3d (0, 0, -1),
                                                      Eigen::Vector3d::UnitX (), 1.0, 2.0));
      SimulationSettings s = figures.settings ();
      s.projector_shadows = shadows;
      const KinectSimulator sim = figures.simulator (scene, s);
      const SensorTruth &t = sim.truth (0);
      // The step: the first column of the central row on the front panel.
      const int row = static_cast<int> (std::lround (figures.sensor ().cy));
      int edge = 0;
      while (edge < t.width && !(t.depth_m[static_cast<std::size_t> (row) * t.width + edge] < 0.5 * (z_front + zb)))
        ++edge;
      const std::vector<DepthFrame> fr = figures.frames (sim);
      // Shadow width: pixels without a reading left of the step, averaged over rows and frames.
      double missing = 0;
      for (const auto &f : fr)
        for (int v = 0; v < f.height; ++v)
          for (int u = 0; u < edge; ++u)
            missing += f.depth_mm[static_cast<std::size_t> (v) * f.width + u] == 0 ? 1 : 0;
      const double width = missing / (static_cast<double> (fr.size ()) * t.height);
      const double model = figures.fb () * (1.0 / z_front - 1.0 / zb);
      if (shadows)
      {
        widths << num (zb) << " " << num (width) << " " << num (model) << "\n";
        figures.note ("projector_shadows", "width_px_at_" + num (zb) + "m", width);
        figures.note ("projector_shadows", "model_px_at_" + num (zb) + "m", model);
      }
      else
        figures.note ("projector_shadows", "width_px_without_shadows_at_" + num (zb) + "m", width);
      if (zb == 1.8)
      {
        std::ostringstream row_out;
        row_out << "# u_px depth_mm (frame 0, row " << row << "; 0 = no reading), back wall " << zb
                << " m, panel " << z_front << " m from column " << edge << ", shadows "
                << (shadows ? "on" : "off") << "\n";
        for (int u = std::max (0, edge - 30); u < std::min (t.width, edge + 15); ++u)
          row_out << u << " " << fr[0].depth_mm[static_cast<std::size_t> (row) * t.width + u] << "\n";
        figures.write (std::string ("projector_shadows_row_") + (shadows ? "on" : "off") + ".dat", row_out.str ());
        figures.note ("projector_shadows", "edge_column", edge, 6);
      }
    }
  }
  figures.write ("projector_shadows.dat", widths.str ());
}
