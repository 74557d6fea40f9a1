/*
 * One texlet extraction of the real 640x480 frame (spacing 6, radius 6, 20 RANSAC iterations,
 * 50 Monte Carlo samples), for profiling under callgrind and for comparing results before and
 * after a change:
 *
 *   valgrind --tool=callgrind texlet_profile_run mc 1
 *   texlet_profile_run mc 2 --save before.pcd          (then, after the change)
 *   texlet_profile_run mc 2 --compare before.pcd       (largest differences per field)
 *   texlet_profile_run mc 1 --frames 3                 (3 extractions of the frame with one
 *                                                       estimator: what is kept across frames)
 *   texlet_profile_run analytic 1 --noise-model M.yaml (the texlets' noise model from a YAML
 *                                                       file, e.g. one with spatial_correlation)
 *   texlet_profile_run analytic 2 --noise-model M.yaml --exact-window 1 (every window form by
 *                                                       the windows' sums, not the whole disc's tables)
 *
 * method: none | analytic | mc. Exit code 2 and one line on stderr for bad arguments or files.
 */
#include <pcl_texlet/features/texlet_estimation.h>
#include <pcl_texlet/io/noise_model_io.h>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{

using Cloud = pcl::PointCloud<pcl::PointXYZRGBA>;

pcl::texlet::UncertaintyMethod
parseMethod (const std::string &s)
{
  if (s == "none") return pcl::texlet::UncertaintyMethod::None;
  if (s == "analytic") return pcl::texlet::UncertaintyMethod::Analytic;
  if (s == "mc") return pcl::texlet::UncertaintyMethod::MonteCarlo;
  throw std::invalid_argument ("method '" + s + "' is not one of none, analytic, mc");
}

/** Largest, median and 99th percentile of ||A - B|| / ||B|| (Frobenius) over texlets made in
  * both, NaN-free ones only. */
void
compare (const pcl::PointCloud<pcl::Texlet> &a, const pcl::PointCloud<pcl::Texlet> &b)
{
  if (a.size () != b.size ())
    throw std::invalid_argument ("the reference has " + std::to_string (b.size ()) + " texlets, this run " +
                                 std::to_string (a.size ()));
  double max_angle = 0, max_p = 0, max_cp = 0, max_cn = 0, max_curv = 0, max_radius = 0;
  std::size_t made_differs = 0, support_differs = 0, colour_differs = 0, compared = 0;
  std::vector<double> rel_p, rel_n;
  for (std::size_t i = 0; i < a.size (); ++i)
  {
    const pcl::Texlet &x = a[i], &y = b[i];
    if ((x.support == 0) != (y.support == 0))
    {
      ++made_differs;
      continue;
    }
    if (x.support == 0)
      continue;
    ++compared;
    support_differs += x.support != y.support;
    colour_differs += x.rgba != y.rgba;
    const Eigen::Vector3d na (x.normal_x, x.normal_y, x.normal_z), nb (y.normal_x, y.normal_y, y.normal_z);
    max_angle = std::max (max_angle, std::atan2 (na.cross (nb).norm (), na.dot (nb)));
    max_p = std::max (max_p, (x.getVector3fMap () - y.getVector3fMap ()).cast<double> ().norm ());
    max_curv = std::max (max_curv, static_cast<double> (std::fabs (x.curvature - y.curvature)));
    max_radius = std::max (max_radius, static_cast<double> (std::fabs (x.radius - y.radius)));
    if (std::isfinite (y.cov_p_xx))
    {
      rel_p.push_back ((x.covarianceP () - y.covarianceP ()).norm () / y.covarianceP ().norm ());
      rel_n.push_back ((x.covarianceN () - y.covarianceN ()).norm () / y.covarianceN ().norm ());
      max_cp = std::max (max_cp, rel_p.back ());
      max_cn = std::max (max_cn, rel_n.back ());
    }
    else if (std::isfinite (x.cov_p_xx))
      ++made_differs;
  }
  std::printf ("compared %zu texlets: made differs %zu, support differs %zu, colour differs %zu\n", compared,
               made_differs, support_differs, colour_differs);
  std::printf ("max normal angle %.3g rad, max |dP| %.3g m, max |d curvature| %.3g, max |d radius| %.3g m\n",
               max_angle, max_p, max_curv, max_radius);
  std::printf ("max relative covariance difference: Sigma_P %.3g, Sigma_N %.3g\n", max_cp, max_cn);
  const auto quantile = [] (std::vector<double> v, double q) {
    if (v.empty ())
      return std::nan ("");
    const auto k = static_cast<std::size_t> (q * static_cast<double> (v.size () - 1));
    std::nth_element (v.begin (), v.begin () + k, v.end ());
    return v[k];
  };
  std::printf ("median, 99th percentile: Sigma_P %.3g, %.3g; Sigma_N %.3g, %.3g\n", quantile (rel_p, 0.5),
               quantile (rel_p, 0.99), quantile (rel_n, 0.5), quantile (rel_n, 0.99));
}

int
run (int argc, char **argv)
{
  if (argc < 3)
    throw std::invalid_argument ("usage: texlet_profile_run none|analytic|mc THREADS [--save F.pcd | --compare F.pcd] "
                                 "[--frames N] [--noise-model M.yaml] [--exact-window 0|1]");
  const auto method = parseMethod (argv[1]);
  const int threads = std::atoi (argv[2]);
  if (threads < 1)
    throw std::invalid_argument (std::string ("threads '") + argv[2] + "' is not a positive number");
  std::string save, reference, noise_model;
  bool exact_window = false;
  int frames = 1;
  for (int i = 3; i < argc; i += 2)
  {
    const std::string option = argv[i];
    if (i + 1 >= argc)
      throw std::invalid_argument ("option '" + option + "' needs a value");
    const std::string value = argv[i + 1];
    if (option == "--save")
      save = value;
    else if (option == "--compare")
      reference = value;
    else if (option == "--noise-model")
      noise_model = value;
    else if (option == "--exact-window")
      exact_window = value == "1";
    else if (option == "--frames")
    {
      frames = std::atoi (value.c_str ());
      if (frames < 1)
        throw std::invalid_argument ("frames '" + value + "' is not a positive number");
    }
    else
      throw std::invalid_argument ("unknown option '" + option + "'");
  }
  auto cloud = std::make_shared<Cloud> ();
  const std::string path = std::string (DATA_DIR) + "/kinect/milk_cartoon_all_small_clorox.pcd";
  if (pcl::io::loadPCDFile (path, *cloud) != 0)
    throw std::invalid_argument ("cannot read " + path);

  pcl::TexletEstimation<pcl::PointXYZRGBA> est;
  est.setInputCloud (cloud);
  est.setSpacing (6);
  est.setRadius (6);
  est.setRansacIterations (20);
  est.setUncertaintyMethod (method);
  est.setMonteCarloSamples (50);
  est.setNumberOfThreads (static_cast<unsigned> (threads));
  est.setExactWindowForm (exact_window);
  if (!noise_model.empty ())
    est.setNoiseModel (pcl::texlet::loadNoiseModelYaml (noise_model));
  pcl::PointCloud<pcl::Texlet> out;
  for (int f = 0; f < frames; ++f)
    est.compute (out);
  std::printf ("%zu texlets\n", out.size ());

  if (!save.empty () && pcl::io::savePCDFileBinary (save, out) != 0)
    throw std::invalid_argument ("cannot write " + save);
  if (!reference.empty ())
  {
    pcl::PointCloud<pcl::Texlet> ref;
    if (pcl::io::loadPCDFile (reference, ref) != 0)
      throw std::invalid_argument ("cannot read " + reference);
    compare (out, ref);
  }
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  try
  {
    return run (argc, argv);
  }
  catch (const std::exception &e)
  {
    std::fprintf (stderr, "texlet_profile_run: %s\n", e.what ());
    return 2;
  }
}
