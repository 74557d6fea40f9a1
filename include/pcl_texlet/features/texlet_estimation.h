/*
 * pcl_texlet: texlet extraction from organised clouds as a pcl::Feature.
 */
#pragma once

#include <pcl_texlet/camera/camera_model.h>
#include <pcl_texlet/noise/noise_model.h>
#include <pcl_texlet/features/point_types.h>
#include <pcl_texlet/features/texlet_parameters.h>

#include <pcl/features/feature.h>

#include <memory>
#include <vector>

namespace pcl
{

/** \brief Compute one texlet centred on pixel \a centre of an organised cloud: RANSAC over
  * the pixel disc, the plane fit, and the uncertainty chosen in \a params (see
  * TexletEstimation). Allocates scratch per call; TexletEstimation reuses it across texlets.
  * \param[in] cloud organised input cloud, metres
  * \param[in] centre index of the centre pixel in \a cloud
  * \param[in] params extraction settings (validated); the normal faces params.viewpoint
  * \param[in] camera camera model of the cloud (gives the noise model's radius)
  * \param[in] noise depth noise model (sigma in mm)
  * \param[out] texlet the texlet; NaN with support 0 where it could not be made
  * \return true if a texlet was made
  * \throws pcl::BadArgumentException for bad parameters or an out-of-range centre,
  *         pcl::UnorganizedPointCloudException for an unorganised cloud
  */
template <typename PointInT, typename PointOutT> bool
computeTexlet (const pcl::PointCloud<PointInT> &cloud, pcl::index_t centre, const texlet::TexletParameters &params,
               const texlet::CameraModel &camera, const texlet::NoiseModel &noise, PointOutT &texlet);

/** \brief TexletEstimation extracts texlets (surface patches with centre, normal, their
  * covariances, size and mean colour) from an organised point cloud of a depth camera, after
  * Olesen et al., "Real-time extraction of surface patches with associated uncertainties by
  * means of Kinect cameras".
  *
  * Centres lie on a hexagonal pixel grid (setSpacing) unless indices are set. Each texlet's
  * neighbourhood is the disc of pixels within setRadius pixels of its centre: the pixel
  * neighbourhood of the organised image, not a metric search, so setSearchMethod,
  * setRadiusSearch and setKSearch are not used. RANSAC with a fixed number of iterations
  * rejects outliers (default threshold: 3 depth SDs of the noise model at the patch), the
  * chosen plane fit gives P and N, and the chosen method propagates the noise model's depth
  * noise into Sigma_P and Sigma_N.
  *
  * The output holds one texlet per centre, in the order of the centres; a texlet that could
  * not be made (too few valid points, a degenerate neighbourhood) is NaN with support 0 and
  * the output is then not dense. Normals face the viewpoint: as in PCL's NormalEstimation the
  * input cloud's sensor_origin_ unless setViewPoint was called (useSensorOriginAsViewPoint).
  * Random draws come from Philox counters keyed by (seed, centre pixel, draw), so the output is
  * the same for the same seed whatever the number of threads.
  *
  * Input coordinates are in metres; the noise model works in millimetres.
  *
  * \author pcl_texlet developers
  * \ingroup features
  */
template <typename PointInT, typename PointOutT = pcl::Texlet>
class TexletEstimation : public Feature<PointInT, PointOutT>
{
public:
  using Ptr = shared_ptr<TexletEstimation<PointInT, PointOutT>>;
  using ConstPtr = shared_ptr<const TexletEstimation<PointInT, PointOutT>>;
  using PointCloudOut = typename Feature<PointInT, PointOutT>::PointCloudOut;
  using Feature<PointInT, PointOutT>::feature_name_;
  using Feature<PointInT, PointOutT>::input_;
  using Feature<PointInT, PointOutT>::indices_;

  /** \brief Empty constructor: the paper's settings and noise model. */
  TexletEstimation () : noise_ (texlet::NoiseModel::paper ()) { feature_name_ = "TexletEstimation"; }

  /** \brief Distance between hexagonal grid centres in a row, pixels (default 6). */
  void
  setSpacing (int pixels);
  int
  getSpacing () const { return params_.spacing; }

  /** \brief Radius of the neighbourhood disc, pixels (default 6). */
  void
  setRadius (int pixels);
  int
  getRadius () const { return params_.radius; }

  /** \brief RANSAC iterations (default 20). */
  void
  setRansacIterations (int iterations);
  int
  getRansacIterations () const { return params_.ransac_iterations; }

  /** \brief Point-to-plane inlier distance in metres; 0 (default) derives it per texlet as
    * getRansacThresholdSigmas() times the noise model's depth SD at the patch.
    */
  void
  setRansacThreshold (double metres);
  double
  getRansacThreshold () const { return params_.ransac_threshold; }

  /** \brief Multiple of the depth SD used as the automatic threshold (default 3). */
  void
  setRansacThresholdSigmas (double sigmas);
  double
  getRansacThresholdSigmas () const { return params_.threshold_sigmas; }

  /** \brief How far the automatic threshold widens where the patch's own noise is larger than
    * the model's (default 4): after RANSAC the inliers are refitted, and the threshold becomes the
    * larger of the model's and this many of the patch's own SDs (1.4826 times the median distance
    * to that plane of the disc's points within 4 model thresholds of it). 0: the paper's
    * threshold from the model alone. A fixed threshold (setRansacThreshold) is never widened.
    */
  void
  setRobustThresholdSigmas (double sigmas);
  double
  getRobustThresholdSigmas () const { return params_.robust_sigmas; }

  /** \brief Plane fit: PCA (default), SVD or Averaging. */
  void
  setPlaneFitMethod (texlet::PlaneFitMethod method);
  texlet::PlaneFitMethod
  getPlaneFitMethod () const { return params_.fit; }

  /** \brief The texlet's centre P: where the centre pixel's ray meets the fitted plane
    * (CentreRay, default), or the inliers' mean (InlierMean, the paper's). With CentreRay, P does
    * not move with which disc pixels are inliers in a frame, and Sigma_P (rank 1, along the ray)
    * holds how it does move; the inliers' mean moves sideways in a way Sigma_P does not hold.
    * Normal averaging's P is the centre pixel's point either way.
    */
  void
  setCentreDefinition (texlet::TexletCentre centre);
  texlet::TexletCentre
  getCentreDefinition () const { return params_.centre; }

  /** \brief Uncertainty propagation: MonteCarlo (default), Analytic or None. */
  void
  setUncertaintyMethod (texlet::UncertaintyMethod method);
  texlet::UncertaintyMethod
  getUncertaintyMethod () const { return params_.uncertainty; }

  /** \brief Monte Carlo samples per texlet (default 50, at least 2). */
  void
  setMonteCarloSamples (int samples);
  int
  getMonteCarloSamples () const { return params_.samples; }

  /** \brief Fewest RANSAC inliers that make a texlet (default 6, at least 3). */
  void
  setMinSupport (int points);
  int
  getMinSupport () const { return params_.min_support; }

  /** \brief Whether each reading's depth loses the noise model's bias before the fit (default
    * true): where a term moves the mean (a warm-up drift at the frame of setNoiseContext, a
    * distortion map), its bias at the reading is taken off along the pixel's ray, so that P and
    * N estimate the surface; false fits the readings as they are. A model of variance only (the
    * paper's) leaves the readings as they are either way.
    */
  void
  setRemoveModelBias (bool remove) { params_.remove_model_bias = remove; }
  bool
  getRemoveModelBias () const { return params_.remove_model_bias; }

  /** \brief Whether the covariances of noise shared over a window (a `spatial_correlation`
    * term) are formed by the windows' sums for every texlet (default false): otherwise a texlet
    * whose disc misses at most 8 readings or inliers, under a window of 6 px or more, takes the
    * window's form from tables made once per window width, on the quadratics of the pixel
    * offset (its error against the sums: docs/benchmarks.md, "Discs from tables").
    */
  void
  setExactWindowForm (bool exact) { params_.exact_window_form = exact; }
  bool
  getExactWindowForm () const { return params_.exact_window_form; }

  /** \brief Seed of the Philox streams (default 0). */
  void
  setSeed (std::uint32_t seed) { params_.seed = seed; }
  std::uint32_t
  getSeed () const { return params_.seed; }

  /** \brief Viewpoint the normals face; from now on it is used instead of the input cloud's
    * sensor origin (as in PCL's NormalEstimation).
    */
  void
  setViewPoint (float vpx, float vpy, float vpz);

  /** \brief The viewpoint the normals face: the one of setViewPoint, or else the input cloud's
    * sensor origin (the origin while there is no input).
    */
  void
  getViewPoint (float &vpx, float &vpy, float &vpz) const;

  /** \brief Normals face the input cloud's sensor_origin_ (the default), not a viewpoint set with
    * setViewPoint, as in PCL's NormalEstimation.
    */
  void
  useSensorOriginAsViewPoint () { use_sensor_origin_ = true; }

  /** \brief Depth noise model (default: the paper's polynomial). */
  void
  setNoiseModel (const texlet::NoiseModel &model) { noise_ = model; }
  const texlet::NoiseModel &
  getNoiseModel () const { return noise_; }

  /** \brief Covariates of the noise model that a cloud does not carry and that are the same for
    * every pixel of a frame: `frame` (index since power-on, for drift; NaN: steady state),
    * `fb_px_m` (focal length in px times baseline in m, which converts the disparity-defined
    * terms to depth; default 580 x 0.075, Kinect v1 at VGA) and `active_projectors`. The
    * per-pixel covariates (u, v, radius, depth) are filled in for each pixel, and the incidence
    * angle for each texlet from its normal and viewing ray.
    */
  void
  setNoiseContext (const texlet::PixelContext &context) { noise_context_ = context; }
  const texlet::PixelContext &
  getNoiseContext () const { return noise_context_; }

  /** \brief Camera model of the input. If none is set, a pinhole is estimated from the
    * organised cloud itself (u = fx x/z + cx, v = fy y/z + cy) at each compute().
    */
  void
  setCameraModel (const texlet::CameraModel::ConstPtr &camera) { camera_ = camera; }
  texlet::CameraModel::ConstPtr
  getCameraModel () const { return camera_; }

  /** \brief All settings at once (validated). A viewpoint other than the one held so far counts
    * as set with setViewPoint; an unchanged one leaves the sensor origin in use if it was.
    */
  void
  setParameters (const texlet::TexletParameters &params);
  const texlet::TexletParameters &
  getParameters () const { return params_; }

  /** \brief OpenMP threads; 0 (default) uses all processors. */
  void
  setNumberOfThreads (unsigned int threads) { threads_ = threads; }

protected:
  /** \brief Checks the input (organised, indices in range) and builds the hexagonal grid
    * of centres when the user set no indices. \throws on bad input.
    */
  bool
  initCompute () override;

  /** \brief Computes one texlet per centre into \a output. */
  void
  computeFeature (PointCloudOut &output) override;

private:
  /** \brief The viewpoint in use (getViewPoint). */
  void
  viewPoint (float vp[3]) const;

  texlet::TexletParameters params_;
  bool use_sensor_origin_ = true; // normals face input_->sensor_origin_, not params_.viewpoint
  texlet::NoiseModel noise_;
  texlet::PixelContext noise_context_;
  texlet::CameraModel::ConstPtr camera_;
  unsigned int threads_ = 0;
  std::vector<double> sigma_image_; // per-pixel depth SD in metres, reused across frames
  pcl::PointCloud<PointInT> unbiased_cloud_; // the input less the model's bias, where it has one
  // Per-pixel distance from the principal point (the noise model's r), kept while the camera
  // object, the image size and the distances at five probe pixels stay the same.
  std::vector<double> radius_image_;
  texlet::CameraModel::ConstPtr radius_camera_;
  std::uint32_t radius_width_ = 0, radius_height_ = 0;
  double radius_probe_[5] = {0, 0, 0, 0, 0};

public:
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

} // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl_texlet/features/impl/texlet_estimation.hpp>
#endif
