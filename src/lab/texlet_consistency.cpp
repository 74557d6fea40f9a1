/*
 * pcl_texlet model lab: texlet NEES across frames (see texlet_consistency.h).
 */
#include <pcl_texlet/lab/texlet_consistency.h>

#include <pcl_texlet/camera/depth_image.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/exceptions.h>
#include <pcl/point_types.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace pcl
{
namespace texlet
{
namespace lab
{

namespace
{

bool
validTexlet (const pcl::Texlet &t)
{
  return t.support > 0 && std::isfinite (t.x) && std::isfinite (t.normal_x) && std::isfinite (t.cov_p_zz) &&
         std::isfinite (t.cov_n_11);
}

/** x^T C^-1 x for a symmetric positive definite C (double, LDLT); NaN when C is not. */
template <int D> double
mahalanobis2 (const Eigen::Matrix<double, D, D> &c, const Eigen::Matrix<double, D, 1> &x)
{
  const Eigen::LDLT<Eigen::Matrix<double, D, D>> ldlt (c);
  if (ldlt.info () != Eigen::Success || !ldlt.isPositive () || (ldlt.vectorD ().array () <= 0).any ())
    return std::numeric_limits<double>::quiet_NaN ();
  return x.dot (ldlt.solve (x));
}

/** Median of chi-square with 1, 2, 3 degrees of freedom (index = dof). */
constexpr double kChiSquareMedian[4] = {0.0, 0.454936, 1.386294, 2.365974};

/** x^T C^+ x over the eigendirections of a symmetric C whose eigenvalues are above 1e-6 of the
  * largest (\a rank of them): a P on its centre ray has a rank-1 Sigma_P along it (stored in
  * float, whose rounding leaves about 1e-7 in the other directions). NaN when C has none or a
  * clearly negative eigenvalue.
  */
double
neesOnRange (const Eigen::Matrix3d &c, const Eigen::Vector3d &x, int &rank)
{
  rank = 0;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig (c);
  if (eig.info () != Eigen::Success)
    return std::numeric_limits<double>::quiet_NaN ();
  const Eigen::Vector3d l = eig.eigenvalues ();
  const double top = l (2);
  if (!(top > 0) || l (0) < -1e-5 * top)
    return std::numeric_limits<double>::quiet_NaN ();
  double nees = 0;
  for (int i = 0; i < 3; ++i)
    if (l (i) > 1e-6 * top)
    {
      nees += std::pow (eig.eigenvectors ().col (i).dot (x), 2) / l (i);
      ++rank;
    }
  return nees;
}

/** The frames of \a rec the comparison may use (settings.frame_parity), in order. */
std::vector<int>
eligibleFrames (const RecordingMeasurement &rec, const TexletConsistencySettings &settings)
{
  std::vector<int> frames;
  for (int t = 0; t < rec.frames; ++t)
    if (settings.frame_parity < 0 || t % 2 == settings.frame_parity)
      frames.push_back (t);
  return frames;
}

/** The texlets of \a used_frames frames of \a rec evenly spaced over \a eligible, from PointT
  * clouds (with the recording's grey level when PointT has colour). The default hexagonal grid
  * depends only on the image size, so texlet k is the same centre pixel in every frame. */
template <typename PointT>
std::vector<pcl::PointCloud<pcl::Texlet>>
frameTexlets (const RecordingMeasurement &rec, const NoiseModel &model, const TexletConsistencySettings &settings,
              const std::vector<int> &eligible, int used_frames)
{
  pcl::TexletEstimation<PointT, pcl::Texlet> estimation;
  estimation.setNoiseModel (model);
  estimation.setUncertaintyMethod (settings.uncertainty);
  estimation.setRadius (settings.radius_px);
  estimation.setNumberOfThreads (settings.threads);
  estimation.setRansacThreshold (settings.ransac_threshold_m);
  estimation.setCentreDefinition (settings.centre);
  CameraInfo info = rec.camera;
  info.width = rec.width;
  info.height = rec.height;
  estimation.setCameraModel (std::make_shared<PinholeModel> (PinholeModel::fromCameraInfo (info)));
  estimation.setSpacing (settings.spacing_px > 0 ? settings.spacing_px : std::max (2, rec.width / 32));
  // What the recording knows beyond its frames: f b (disparity-defined terms at this
  // resolution) and the active projectors; the frame index is set per frame below.
  PixelContext context = rec.noiseContexts ().shared ();

  std::vector<pcl::PointCloud<pcl::Texlet>> texlets (used_frames);
  DepthFrame frame;
  frame.width = rec.width;
  frame.height = rec.height;
  const std::size_t n_px = static_cast<std::size_t> (rec.width) * rec.height;
  for (const float grey : rec.intensity) // back to the 8-bit grey whose greyLevel() it is
    frame.rgb.insert (frame.rgb.end (), 3,
                      static_cast<std::uint8_t> (std::lround (255.0f * std::min (1.0f, std::max (0.0f, grey)))));
  auto cloud = std::make_shared<pcl::PointCloud<PointT>> ();
  for (int f = 0; f < used_frames; ++f)
  {
    const int last = static_cast<int> (eligible.size ()) - 1;
    const int t = eligible[used_frames > 1 ? static_cast<std::size_t> (std::lround (static_cast<double> (f) * last /
                                                                                 (used_frames - 1)))
                                           : 0];
    frame.name = rec.name + " frame " + std::to_string (t);
    frame.depth_mm.assign (rec.depth_mm.begin () + static_cast<std::ptrdiff_t> (t * n_px),
                           rec.depth_mm.begin () + static_cast<std::ptrdiff_t> ((t + 1) * n_px));
    depthToCloud (frame, *estimation.getCameraModel (), *cloud);
    context.frame = t;
    estimation.setNoiseContext (context);
    estimation.setInputCloud (cloud);
    try
    {
      estimation.compute (texlets[f]);
    }
    catch (const pcl::ComputeFailedException &)
    {
      texlets[f].clear (); // a frame without a valid point: no texlet
    }
  }
  return texlets;
}

} // namespace

TexletConsistency
texletConsistency (const std::vector<RecordingMeasurement::ConstPtr> &recordings, const NoiseModel &model,
                   const TexletConsistencySettings &settings)
{
  if (recordings.empty ())
    throw pcl::BadArgumentException ("texletConsistency: no recording given");
  if (settings.max_frames < 3 || settings.min_frames < 2 || settings.radius_px < 1 || settings.spacing_px < 0 ||
      settings.frame_parity < -1 || settings.frame_parity > 1)
    throw pcl::BadArgumentException ("texletConsistency: max_frames must be >= 3, min_frames >= 2, radius_px >= 1, "
                                     "spacing_px >= 0 and frame_parity -1, 0 or 1");

  double sum_p = 0, sum_n = 0, sum_pn = 0, ideal_sum = 0; // ideal_sum: sum over centres of (n - 1)
  double ideal_sum_p = 0; // sum over pairs of rank(Sigma_P) (n - 1) / n
  TexletConsistency out;
  // Per pair: NEES of P over its chi-square median, NEES of N, and (n - 1) / n.
  std::vector<double> all_p, all_n, shrink;
  for (const auto &rec : recordings)
  {
    if (!rec)
      throw pcl::BadArgumentException ("texletConsistency: null recording");
    const std::vector<int> eligible = eligibleFrames (*rec, settings);
    if (static_cast<int> (eligible.size ()) < settings.min_frames)
      continue;
    const int used_frames = std::min (settings.max_frames, static_cast<int> (eligible.size ()));
    // Colour points where the recording has colour frames, so that a term of the grey level
    // (covariate:intensity) sees it; points without colour have no grey level.
    const std::vector<pcl::PointCloud<pcl::Texlet>> texlets =
        rec->intensity.empty () ? frameTexlets<pcl::PointXYZ> (*rec, model, settings, eligible, used_frames)
                                : frameTexlets<pcl::PointXYZRGBA> (*rec, model, settings, eligible, used_frames);
    out.frames += used_frames;

    std::size_t centres = 0;
    for (const auto &c : texlets)
      centres = std::max (centres, c.size ());
    for (std::size_t k = 0; k < centres; ++k)
    {
      int n = 0;
      Eigen::Vector3d mean_p = Eigen::Vector3d::Zero (), mean_n = Eigen::Vector3d::Zero ();
      for (const auto &c : texlets)
        if (k < c.size () && validTexlet (c[k]))
        {
          mean_p += c[k].getVector3fMap ().cast<double> ();
          mean_n += c[k].getNormalVector3fMap ().cast<double> ();
          ++n;
        }
      if (n < settings.min_frames || mean_n.norm () == 0)
        continue;
      mean_p /= n;
      mean_n.normalize ();
      double centre_p = 0, centre_n = 0, centre_pn = 0, centre_ideal_p = 0;
      bool ok = true;
      const std::size_t first = all_p.size ();
      for (const auto &c : texlets)
        if (k < c.size () && validTexlet (c[k]))
        {
          const pcl::Texlet &tx = c[k];
          const Eigen::Vector3d dp = tx.getVector3fMap ().cast<double> () - mean_p;
          const Eigen::Matrix<double, 3, 2> frame_t = tx.tangentFrame ().cast<double> ();
          const Eigen::Vector2d dn = frame_t.transpose () * (tx.getNormalVector3fMap ().cast<double> () - mean_n);
          int rank_p = 0;
          const double ep = neesOnRange (tx.covarianceP ().cast<double> (), dp, rank_p);
          const double en = mahalanobis2<2> (tx.covarianceN ().cast<double> (), dn);
          if (!std::isfinite (ep) || !std::isfinite (en))
          {
            ok = false; // a degenerate covariance: leave the centre out rather than divide by ~0
            break;
          }
          centre_p += ep;
          centre_ideal_p += rank_p * (n - 1.0) / n;
          all_p.push_back (ep / kChiSquareMedian[rank_p]);
          all_n.push_back (en);
          shrink.push_back ((n - 1.0) / n);
          const double var_normal = mean_n.dot (tx.covarianceP ().cast<double> () * mean_n);
          centre_pn += mean_n.dot (dp) * mean_n.dot (dp) / var_normal;
          centre_n += en;
        }
      if (!ok)
      {
        all_p.resize (first);
        all_n.resize (first);
        shrink.resize (first);
        continue;
      }
      sum_p += centre_p;
      ideal_sum_p += centre_ideal_p;
      sum_n += centre_n;
      sum_pn += centre_pn;
      ideal_sum += n - 1;
      out.samples += n;
      out.texlets += 1;
    }
  }
  if (out.samples > 0)
  {
    out.nees_p = sum_p / out.samples;
    out.nees_n = sum_n / out.samples;
    out.ideal_p = ideal_sum_p / out.samples;
    out.ideal_n = 2.0 * ideal_sum / out.samples;
    out.nees_p_normal = sum_pn / out.samples;
    out.ideal_p_normal = ideal_sum / out.samples;
    auto median = [] (std::vector<double> v) {
      const auto mid = v.begin () + static_cast<std::ptrdiff_t> (v.size () / 2);
      std::nth_element (v.begin (), mid, v.end ());
      return *mid;
    };
    out.median_p = kChiSquareMedian[3] * median (all_p); // in 3-dof terms, whatever each pair's rank
    out.median_n = median (all_n);
    const double m = median (shrink);
    out.ideal_median_p = kChiSquareMedian[3] * m;
    out.ideal_median_n = kChiSquareMedian[2] * m;
  }
  return out;
}

} // namespace lab
} // namespace texlet
} // namespace pcl
