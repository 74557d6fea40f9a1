/*
 * pcl_texlet_bench: the estimators compared (see methods.h).
 */
#include "methods.h"
#include "pixel_disc_search.h"

#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/features/integral_image_normal.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/search/organized.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace pcl_texlet_bench
{
namespace
{

const float kNaN = std::numeric_limits<float>::quiet_NaN ();

Eigen::Vector3f
nanVector ()
{
  return Eigen::Vector3f::Constant (kNaN);
}

/** PCL's estimators attach the normal to the centre point itself. */
MethodOutput
pclOutput (const pcl::PointCloud<pcl::Normal> &normals, const Cloud &cloud, const pcl::Indices &centres,
           bool per_centre, const std::vector<int> &valid_disc, bool share_defined, int k)
{
  MethodOutput out;
  const std::size_t n = centres.size ();
  out.normal.resize (n);
  out.position.resize (n);
  out.inlier_share.assign (n, kNaN);
  out.centre_pixel.assign (centres.begin (), centres.end ());
  for (std::size_t i = 0; i < n; ++i)
  {
    const pcl::Normal &q = normals[per_centre ? i : static_cast<std::size_t> (centres[i])];
    const Eigen::Vector3f nv (q.normal_x, q.normal_y, q.normal_z);
    const bool ok = nv.allFinite () && nv.squaredNorm () > 0.5f;
    out.normal[i] = ok ? nv : nanVector ();
    out.position[i] = ok ? cloud[centres[i]].getVector3fMap () : nanVector ();
    if (ok && share_defined && valid_disc[i] > 0)
      out.inlier_share[i] = k > 0 ? std::min (1.0f, static_cast<float> (k) / valid_disc[i]) : 1.0f;
  }
  return out;
}

class TexletRunner : public MethodRunner
{
public:
  TexletRunner (const MethodSpec &spec, const Setup &setup, const Cloud::ConstPtr &cloud,
                const std::vector<int> &valid_disc, const pcl::texlet::CameraModel::ConstPtr &camera)
    : cloud_ (cloud), valid_disc_ (valid_disc)
  {
    pcl::texlet::TexletParameters p;
    p.spacing = setup.spacing;
    p.radius = setup.radius;
    p.ransac_iterations = setup.iterations;
    p.ransac_threshold = setup.ransac_threshold_m;
    p.samples = setup.samples;
    p.uncertainty = spec.uncertainty;
    p.fit = spec.fit;
    p.exact_window_form = setup.exact_window_form;
    est_.setParameters (p);
    est_.setNumberOfThreads (setup.threads);
    est_.setCameraModel (camera);
    est_.setNoiseModel (setup.noise);
  }

  void
  run () override
  {
    est_.setInputCloud (cloud_);
    est_.compute (texlets_);
  }

  MethodOutput
  output () const override
  {
    MethodOutput out;
    const std::size_t n = texlets_.size ();
    out.normal.resize (n);
    out.position.resize (n);
    out.inlier_share.assign (n, kNaN);
    out.centre_pixel.resize (n);
    for (std::size_t i = 0; i < n; ++i)
    {
      const pcl::Texlet &t = texlets_[i];
      const bool ok = t.support > 0 && std::isfinite (t.normal_x);
      out.normal[i] = ok ? Eigen::Vector3f (t.normal_x, t.normal_y, t.normal_z) : nanVector ();
      out.position[i] = ok ? Eigen::Vector3f (t.x, t.y, t.z) : nanVector ();
      out.centre_pixel[i] = static_cast<int> (t.pixel_index);
      if (ok && i < valid_disc_.size () && valid_disc_[i] > 0)
        out.inlier_share[i] = static_cast<float> (t.support) / valid_disc_[i];
    }
    return out;
  }

private:
  Cloud::ConstPtr cloud_;
  const std::vector<int> &valid_disc_;
  pcl::TexletEstimation<pcl::PointXYZ> est_;
  pcl::PointCloud<pcl::Texlet> texlets_;
};

class NormalOmpRunner : public MethodRunner
{
public:
  NormalOmpRunner (bool disc, const Setup &setup, const Cloud::ConstPtr &cloud, const pcl::IndicesConstPtr &centres,
                   const std::vector<int> &valid_disc)
    : disc_ (disc), cloud_ (cloud), centres_ (centres), valid_disc_ (valid_disc),
      k_ (pcl::texlet::kernels::pixelDiscSize (setup.radius))
  {
    if (disc)
      search_ = std::make_shared<PixelDiscSearch<pcl::PointXYZ>> (setup.radius);
    else
      search_ = std::make_shared<pcl::search::OrganizedNeighbor<pcl::PointXYZ>> ();
    ne_.setSearchMethod (search_);
    ne_.setKSearch (k_);
    ne_.setIndices (centres);
    ne_.setNumberOfThreads (setup.threads);
  }

  void
  run () override
  {
    // A new frame is a new cloud: OrganizedNeighbor re-estimates its projection for it.
    search_->setInputCloud (cloud_);
    ne_.setInputCloud (cloud_);
    ne_.compute (normals_);
  }

  MethodOutput
  output () const override
  {
    return pclOutput (normals_, *cloud_, *centres_, true, valid_disc_, true, disc_ ? 0 : k_);
  }

private:
  bool disc_;
  Cloud::ConstPtr cloud_;
  pcl::IndicesConstPtr centres_;
  const std::vector<int> &valid_disc_;
  int k_;
  pcl::search::Search<pcl::PointXYZ>::Ptr search_;
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> ne_;
  pcl::PointCloud<pcl::Normal> normals_;
};

class IntegralImageRunner : public MethodRunner
{
public:
  IntegralImageRunner (bool covariance, const Setup &setup, const Cloud::ConstPtr &cloud,
                       const pcl::IndicesConstPtr &centres, const std::vector<int> &valid_disc)
    : cloud_ (cloud), centres_ (centres), valid_disc_ (valid_disc)
  {
    using II = pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal>;
    ii_.setNormalEstimationMethod (covariance ? II::COVARIANCE_MATRIX : II::AVERAGE_3D_GRADIENT);
    // The rectangle that circumscribes the disc: 2 r + 1 pixels a side, centred on the pixel.
    // PCL sets the rectangle per pixel to min(normal smoothing size, distance to a depth
    // change), so the smoothing size is the rectangle size; no depth-dependent growth.
    ii_.setNormalSmoothingSize (static_cast<float> (2 * setup.radius + 1));
    ii_.setDepthDependentSmoothing (false);
    ii_.setMaxDepthChangeFactor (0.02f); // PCL's default and tutorial value
  }

  void
  run () override
  {
    ii_.setInputCloud (cloud_);
    ii_.compute (normals_);
  }

  MethodOutput
  output () const override
  {
    return pclOutput (normals_, *cloud_, *centres_, false, valid_disc_, false, 0);
  }

private:
  Cloud::ConstPtr cloud_;
  pcl::IndicesConstPtr centres_;
  const std::vector<int> &valid_disc_;
  pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal> ii_;
  pcl::PointCloud<pcl::Normal> normals_;
};

double
percentile (std::vector<double> v, double q)
{
  if (v.empty ())
    return std::nan ("");
  std::sort (v.begin (), v.end ());
  const double pos = q * (v.size () - 1);
  const std::size_t lo = static_cast<std::size_t> (std::floor (pos));
  const std::size_t hi = std::min (lo + 1, v.size () - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

} // namespace

std::string
MethodSpec::description (int radius, int samples) const
{
  std::ostringstream s;
  const int disc = pcl::texlet::kernels::pixelDiscSize (radius);
  const int side = 2 * radius + 1;
  switch (kind)
  {
  case MethodKind::Texlet:
    s << "TexletEstimation, uncertainty " << pcl::texlet::toString (uncertainty);
    if (uncertainty == pcl::texlet::UncertaintyMethod::MonteCarlo)
      s << " (" << samples << " samples)";
    s << ", fit " << pcl::texlet::toString (fit);
    break;
  case MethodKind::NormalOmpDisc:
    s << "NormalEstimationOMP, the texlet's pixel disc (" << disc << " px) via PixelDiscSearch";
    break;
  case MethodKind::NormalOmpOrganized:
    s << "NormalEstimationOMP, OrganizedNeighbor k=" << disc << " (metric kNN, not the same neighbours)";
    break;
  case MethodKind::IntegralCovariance:
    s << "IntegralImageNormalEstimation COVARIANCE_MATRIX, " << side << "x" << side << " px, all pixels";
    break;
  case MethodKind::IntegralGradient:
    s << "IntegralImageNormalEstimation AVERAGE_3D_GRADIENT, " << side << "x" << side << " px, all pixels";
    break;
  }
  return s.str ();
}

std::unique_ptr<MethodRunner>
makeRunner (const MethodSpec &spec, const Setup &setup, const Cloud::ConstPtr &cloud,
            const pcl::IndicesConstPtr &centres, const std::vector<int> &valid_disc,
            const pcl::texlet::CameraModel::ConstPtr &camera)
{
  switch (spec.kind)
  {
  case MethodKind::Texlet:
    return std::make_unique<TexletRunner> (spec, setup, cloud, valid_disc, camera);
  case MethodKind::NormalOmpDisc:
  case MethodKind::NormalOmpOrganized:
    return std::make_unique<NormalOmpRunner> (spec.kind == MethodKind::NormalOmpDisc, setup, cloud, centres,
                                              valid_disc);
  case MethodKind::IntegralCovariance:
  case MethodKind::IntegralGradient:
    return std::make_unique<IntegralImageRunner> (spec.kind == MethodKind::IntegralCovariance, setup, cloud, centres,
                                                  valid_disc);
  }
  return nullptr;
}

pcl::IndicesPtr
hexCentres (int width, int height, int spacing)
{
  const auto grid = pcl::texlet::kernels::makeHexGrid (width, height, spacing);
  auto centres = std::make_shared<pcl::Indices> (grid.size ());
  for (int i = 0; i < grid.size (); ++i)
  {
    int u, v;
    pcl::texlet::kernels::hexCentre (grid, i, u, v);
    (*centres)[i] = static_cast<pcl::index_t> (v) * width + u;
  }
  return centres;
}

std::vector<int>
validDiscCounts (const Cloud::ConstPtr &cloud, const pcl::Indices &centres, int radius)
{
  PixelDiscSearch<pcl::PointXYZ> search (radius);
  search.setInputCloud (cloud);
  std::vector<int> counts (centres.size ());
  pcl::Indices idx;
  std::vector<float> d;
  for (std::size_t i = 0; i < centres.size (); ++i)
    counts[i] = search.disc (*cloud, centres[i], idx, d);
  return counts;
}

MethodSpec
texletMethod (pcl::texlet::UncertaintyMethod uncertainty, pcl::texlet::PlaneFitMethod fit)
{
  MethodSpec m;
  m.kind = MethodKind::Texlet;
  m.uncertainty = uncertainty;
  m.fit = fit;
  m.name = "texlet/" + pcl::texlet::toString (uncertainty) + "/" + pcl::texlet::toString (fit);
  return m;
}

MethodSpec
referenceMethod ()
{
  MethodSpec m;
  m.kind = MethodKind::NormalOmpDisc;
  m.name = "pcl/ne_omp_disc";
  return m;
}

std::vector<MethodSpec>
comparisonMethods (const std::vector<pcl::texlet::PlaneFitMethod> &fits, bool organized_knn)
{
  using pcl::texlet::UncertaintyMethod;
  std::vector<MethodSpec> m;
  for (const UncertaintyMethod u : {UncertaintyMethod::None, UncertaintyMethod::Analytic, UncertaintyMethod::MonteCarlo})
    for (const auto f : fits)
      m.push_back (texletMethod (u, f));
  m.push_back (referenceMethod ());
  if (organized_knn)
  {
    MethodSpec k;
    k.kind = MethodKind::NormalOmpOrganized;
    k.name = "pcl/ne_omp_organized_knn";
    m.push_back (k);
  }
  MethodSpec c;
  c.kind = MethodKind::IntegralCovariance;
  c.name = "pcl/integral_covariance";
  m.push_back (c);
  MethodSpec g;
  g.kind = MethodKind::IntegralGradient;
  g.name = "pcl/integral_average_3d_gradient";
  m.push_back (g);
  return m;
}

NeighbourhoodCheck
checkSameNeighbourhood (const Setup &setup, const Cloud::ConstPtr &cloud, const pcl::IndicesConstPtr &centres,
                        const std::vector<int> &valid_disc, const pcl::texlet::CameraModel::ConstPtr &camera)
{
  Setup wide = setup;
  wide.ransac_threshold_m = 1e3; // every valid disc pixel is an inlier of any hypothesis
  const auto ours = makeRunner (texletMethod (pcl::texlet::UncertaintyMethod::None, pcl::texlet::PlaneFitMethod::PCA),
                                wide, cloud, centres, valid_disc, camera);
  const auto pcl_ne = makeRunner (referenceMethod (), wide, cloud, centres, valid_disc, camera);
  ours->run ();
  pcl_ne->run ();
  const MethodOutput a = ours->output (), b = pcl_ne->output ();

  NeighbourhoodCheck c;
  c.centres = centres->size ();
  std::vector<double> angles;
  for (std::size_t i = 0; i < c.centres && i < a.normal.size (); ++i)
  {
    if (a.centre_pixel[i] == (*centres)[i])
      ++c.centre_equal;
    // support == valid disc pixels <=> inlier share exactly 1; no texlet only where the disc
    // has fewer valid pixels than the minimum support.
    const bool made = a.normal[i].allFinite ();
    if ((made && a.inlier_share[i] == 1.0f) || (!made && valid_disc[i] < pcl::texlet::TexletParameters ().min_support))
      ++c.support_equal;
    if (made && b.normal[i].allFinite ())
    {
      ++c.compared;
      const Eigen::Vector3d na = a.normal[i].cast<double> (), nb = b.normal[i].cast<double> ();
      angles.push_back (std::atan2 (na.cross (nb).norm (), std::fabs (na.dot (nb))) * 180.0 / M_PI);
    }
  }
  c.median_angle_deg = percentile (angles, 0.5);
  c.p99_angle_deg = percentile (angles, 0.99);
  c.max_angle_deg = angles.empty () ? std::nan ("") : *std::max_element (angles.begin (), angles.end ());
  return c;
}

} // namespace pcl_texlet_bench
