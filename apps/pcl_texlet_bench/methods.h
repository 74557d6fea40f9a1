/*
 * pcl_texlet_bench: the normal estimators compared, each behind one interface so the harness
 * can time them interleaved and score them at the same centres.
 */
#pragma once

#include <pcl_texlet/camera/camera_model.h>
#include <pcl_texlet/features/texlet_parameters.h>
#include <pcl_texlet/noise/noise_model.h>

#include <pcl/pcl_base.h> // pcl::IndicesPtr
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace pcl_texlet_bench
{

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

enum class MethodKind
{
  Texlet,             ///< pcl::TexletEstimation (ours)
  NormalOmpDisc,      ///< pcl::NormalEstimationOMP over the texlet's pixel disc (PixelDiscSearch)
  NormalOmpOrganized, ///< pcl::NormalEstimationOMP with pcl::search::OrganizedNeighbor, k = disc size
  IntegralCovariance, ///< pcl::IntegralImageNormalEstimation, COVARIANCE_MATRIX, every pixel
  IntegralGradient    ///< pcl::IntegralImageNormalEstimation, AVERAGE_3D_GRADIENT, every pixel
};

struct MethodSpec
{
  std::string name; ///< short, unique: "texlet/none/pca", "pcl/ne_omp_disc", ...
  MethodKind kind = MethodKind::Texlet;
  pcl::texlet::UncertaintyMethod uncertainty = pcl::texlet::UncertaintyMethod::None;
  pcl::texlet::PlaneFitMethod fit = pcl::texlet::PlaneFitMethod::PCA;

  /** \brief What the method is, in words, for tables and the JSON. */
  std::string
  description (int radius, int samples) const;
};

/** \brief Settings every method shares. */
struct Setup
{
  int spacing = 6;
  int radius = 6;
  int iterations = 20;
  int samples = 50;
  unsigned threads = 2;
  double ransac_threshold_m = 0.0; ///< 0: from the noise model (the library's default)
  /** The texlets' depth noise model (--noise-model; the paper's by default): a model with shared
    * or windowed noise costs its propagation (docs/benchmarks.md). */
  pcl::texlet::NoiseModel noise = pcl::texlet::NoiseModel::paper ();
  /** Every texlet's window form by the windows' sums (--exact-window-form), not the whole disc's tables. */
  bool exact_window_form = false;
};

/** \brief What a method gave at each centre, after its last run. */
struct MethodOutput
{
  std::vector<Eigen::Vector3f> normal;   ///< unit normal; NaN where the method gave none
  std::vector<Eigen::Vector3f> position; ///< where the normal sits: P for texlets, the centre point for PCL
  std::vector<float> inlier_share;       ///< points used / valid disc pixels; NaN where not defined
  std::vector<int> centre_pixel;         ///< the centre the method reports (texlets: pixel_index)
};

/** \brief One method bound to one cloud. run() is the timed part: what a user does per frame
  * (set the cloud, compute); everything built once per program (objects, parameters, the
  * search object, the camera model) is made in the constructor.
  */
class MethodRunner
{
public:
  virtual ~MethodRunner () = default;
  virtual void
  run () = 0;
  virtual MethodOutput
  output () const = 0;
};

/** \param centres the hexagonal centres (PCL's estimators get them as indices; TexletEstimation
  *        makes the same grid itself)
  * \param valid_disc valid pixels in each centre's disc (for the inlier share)
  */
std::unique_ptr<MethodRunner>
makeRunner (const MethodSpec &spec, const Setup &setup, const Cloud::ConstPtr &cloud,
            const pcl::IndicesConstPtr &centres, const std::vector<int> &valid_disc,
            const pcl::texlet::CameraModel::ConstPtr &camera);

/** \brief Centres of the library's hexagonal grid (kernels/hex_grid.h), as cloud indices. */
pcl::IndicesPtr
hexCentres (int width, int height, int spacing);

/** \brief Valid pixels of each centre's disc, found by PixelDiscSearch. */
std::vector<int>
validDiscCounts (const Cloud::ConstPtr &cloud, const pcl::Indices &centres, int radius);

/** \brief Ours with every uncertainty x every fit in \a fits, then PCL's estimators. */
std::vector<MethodSpec>
comparisonMethods (const std::vector<pcl::texlet::PlaneFitMethod> &fits, bool organized_knn);

/** \brief Ours with one uncertainty method and fit. */
MethodSpec
texletMethod (pcl::texlet::UncertaintyMethod uncertainty, pcl::texlet::PlaneFitMethod fit);

/** \brief NormalEstimationOMP over the pixel disc: the reference of every ratio. */
MethodSpec
referenceMethod ();

/** \brief Result of checking that NormalEstimationOMP over PixelDiscSearch sees exactly the
  * points TexletEstimation sees: ours with PCA, no uncertainty and a RANSAC threshold so wide
  * that every valid disc pixel is an inlier must report support == the search's neighbour count
  * at every centre, and its normal must be the one NormalEstimationOMP computes from them.
  */
struct NeighbourhoodCheck
{
  std::size_t centres = 0;
  std::size_t compared = 0;         ///< centres where both made a normal
  std::size_t support_equal = 0;    ///< texlet support == neighbours found by the search
  std::size_t centre_equal = 0;     ///< texlet pixel_index == the hexagonal centre given to PCL
  double median_angle_deg = 0.0;    ///< between the two normals
  double p99_angle_deg = 0.0;
  double max_angle_deg = 0.0;
};

NeighbourhoodCheck
checkSameNeighbourhood (const Setup &setup, const Cloud::ConstPtr &cloud, const pcl::IndicesConstPtr &centres,
                        const std::vector<int> &valid_disc, const pcl::texlet::CameraModel::ConstPtr &camera);

} // namespace pcl_texlet_bench
