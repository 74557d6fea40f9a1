#include "studies.h"

#include "output_format.h"
#include "scenes.h"

#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

using nlohmann::json;
using pcl::texlet::PlaneFitMethod;
using pcl::texlet::UncertaintyMethod;

namespace pcl_texlet_bench
{

json
runFig8 (const Options &o, std::string &dat)
{
  const std::vector<double> sigmas_mm = {0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0};
  const std::vector<PlaneFitMethod> fits = {PlaneFitMethod::Averaging, PlaneFitMethod::PCA, PlaneFitMethod::SVD};
  const int w = 128, h = 128, spacing = 4 * o.setup.radius; // patches that do not share points
  json j;
  j["setup"] = "a plane 1 m away tilted 30 degrees, f = 525 px, Gaussian depth noise along each ray; " +
               std::to_string (o.fig8_runs) + " runs per noise level, the patches of a hexagonal grid of spacing " +
               std::to_string (spacing) + " px in a " + std::to_string (w) + "x" + std::to_string (h) +
               " image; radius " + std::to_string (o.setup.radius) +
               " px; no outlier rejection (RANSAC threshold 1 km), so the fits alone are compared";
  std::ostringstream d;
  d << "# sigma_mm  mean_deg_averaging var_deg2_averaging  mean_deg_pca var_deg2_pca  mean_deg_svd var_deg2_svd\n";
  std::cout << "\n== The paper's Fig. 8: normal angle error against added depth noise (degrees, degrees^2) ==\n"
            << std::setw (9) << "sigma mm" << std::setw (14) << "avg mean" << std::setw (12) << "avg var" << std::setw (12)
            << "pca mean" << std::setw (12) << "pca var" << std::setw (12) << "svd mean" << std::setw (12) << "svd var"
            << "\n";
  for (std::size_t l = 0; l < sigmas_mm.size (); ++l)
  {
    progress (o, "fig. 8: noise " + fmt (sigmas_mm[l]) + " mm (" + std::to_string (l + 1) + "/" +
                     std::to_string (sigmas_mm.size ()) + ")");
    std::vector<std::vector<double>> err (fits.size ());
    for (int run = 0; run < o.fig8_runs; ++run)
    {
      Eigen::Vector3f truth;
      const Cloud::Ptr cloud = noisyPlane (w, h, 1.0, 30.0, sigmas_mm[l] * 1e-3, 1000u * l + run, truth);
      for (std::size_t f = 0; f < fits.size (); ++f)
      {
        pcl::TexletEstimation<pcl::PointXYZ> est;
        pcl::texlet::TexletParameters p;
        p.spacing = spacing;
        p.radius = o.setup.radius;
        p.ransac_iterations = 1;
        p.ransac_threshold = 1e3;
        p.uncertainty = UncertaintyMethod::None;
        p.fit = fits[f];
        p.seed = run;
        est.setParameters (p);
        est.setNumberOfThreads (o.setup.threads);
        est.setCameraModel (std::make_shared<pcl::texlet::PinholeModel> (525.0, 525.0, 0.5 * (w - 1), 0.5 * (h - 1)));
        est.setInputCloud (cloud);
        pcl::PointCloud<pcl::Texlet> out;
        est.compute (out);
        for (const auto &t : out)
          if (t.support > 0)
          {
            const Eigen::Vector3d n (t.normal_x, t.normal_y, t.normal_z), g = truth.cast<double> ();
            err[f].push_back (std::atan2 (n.cross (g).norm (), std::fabs (n.dot (g))) * 180.0 / M_PI);
          }
      }
    }
    json row;
    row["sigma_mm"] = sigmas_mm[l];
    d << sigmas_mm[l];
    std::cout << std::setw (9) << fmt (sigmas_mm[l]);
    for (std::size_t f = 0; f < fits.size (); ++f)
    {
      const double mean = meanOf (err[f]);
      double var = 0;
      for (const double e : err[f])
        var += (e - mean) * (e - mean) / std::max<std::size_t> (1, err[f].size () - 1);
      row[pcl::texlet::toString (fits[f])] = {{"mean_deg", num (mean)}, {"var_deg2", num (var)}, {"n", err[f].size ()}};
      d << " " << mean << " " << var;
      std::cout << std::setw (f == 0 ? 14 : 12) << fmt (mean, 3) << std::setw (12) << fmt (var, 3);
    }
    d << "\n";
    std::cout << "\n";
    j["levels"].push_back (row);
  }
  dat = d.str ();
  return j;
}

} // namespace pcl_texlet_bench
