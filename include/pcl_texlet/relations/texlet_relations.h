/*
 * pcl_texlet multi-sensor: every texlet pair's relation (normal distance n_ij, angle theta;
 * the paper's Sect. 4, Fig. 9) accumulated into a 2D histogram and inlier counts against the
 * expected relations of a known object (Fig. 10b, 11, 13), without storing the pairs.
 *
 * The paper relates "each texlet to all other extracted texlets", so all n (n - 1) directed
 * relations are taken: O(n^2), rows in parallel with OpenMP, one histogram per thread summed at
 * the end. The per-pair math is the header-only kernel kernels/relation_histogram.h, kept
 * free of PCL so that the CUDA backend (pcl::texlet::gpu::accumulateRelations,
 * gpu/texlet_relations.h) runs it unchanged; RelationParameters::backend selects it.
 */
#pragma once

#include <pcl_texlet/kernels/relation_histogram.h>
#include <pcl_texlet/relations/known_object.h>
#include <pcl_texlet/features/point_types.h>

#include <pcl/point_cloud.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Where the pairs of the valid texlets are accumulated: a function that adds every
  * relation of \a in into \a counts (zeroed host arrays, sized as kernels::RelationCounts
  * says). Empty: OpenMP on the CPU. pcl::texlet::gpu::accumulateRelations
  * (gpu/texlet_relations.h, in the pcl_texlet_gpu library of builds with CUDA) is the CUDA
  * backend:
  * \code
  * params.backend = [] (const auto &in, const auto &config, auto &counts) {
  *   pcl::texlet::gpu::accumulateRelations (in, config, counts);
  * };
  * \endcode
  */
using RelationBackend = std::function<void (const kernels::RelationInput<float> &in, const kernels::RelationConfig &config,
                                            kernels::RelationCounts<std::uint64_t> &counts)>;

/** \brief The histogram's axes, the thread count (0: OpenMP's default) and the backend. */
struct RelationParameters
{
  kernels::HistogramAxes axes; ///< default: 0-300 mm in 2 mm bins x 0-180 degrees in 1 degree bins
  unsigned threads = 0;        ///< OpenMP threads of the CPU backend
  RelationBackend backend;     ///< empty: the CPU (OpenMP); see RelationBackend
};

/** \brief A histogram bin with the most counts in some window. */
struct RelationPeak
{
  double distance_m = 0.0; ///< bin centre
  double angle_deg = 0.0;  ///< bin centre
  std::uint64_t count = 0;
};

/** \brief Everything accumulated over the pairs of one texlet set. Counts are of directed
  * relations (each unordered pair counts twice, once per direction).
  */
struct RelationStatistics
{
  kernels::HistogramAxes axes;
  std::vector<std::uint64_t> histogram; ///< [angle_bin * distance_bins + distance_bin]
  std::vector<ExpectedRelation> relations;
  double angle_tol_deg = 10.0;
  double distance_tol_m = 0.005;
  std::vector<std::uint64_t> relation_hits; ///< inliers per expected relation (first match)
  std::vector<std::string> labels;          ///< face names, when texlets were labelled
  std::vector<std::uint64_t> label_pairs;   ///< [label_i * labels + label_j]
  std::vector<std::uint64_t> label_inliers; ///< of those, inliers
  std::size_t texlets = 0;
  std::uint64_t relation_count = 0;    ///< n (n - 1)
  std::uint64_t inliers = 0;           ///< within some expected relation's box
  std::uint64_t outside_histogram = 0; ///< distance beyond the axis

  /** \brief 100 inliers / relations (NaN without relations). */
  double
  inlierPercent () const;

  /** \brief Inlier percentage of the relations between faces \a a and \a b (both directions;
    * NaN if there are none).
    */
  double
  labelPairInlierPercent (int a, int b) const;

  /** \brief Inlier percentage of all relations involving face \a a (NaN if none). */
  double
  labelInlierPercent (int a) const;

  /** \brief Count of bin (distance_bin, angle_bin). */
  std::uint64_t
  count (int distance_bin, int angle_bin) const
  {
    return histogram[static_cast<std::size_t> (angle_bin) * axes.distance_bins + distance_bin];
  }

  /** \brief Centre of distance bin \a b, metres. */
  double
  distanceBinCentre (int b) const { return (b + 0.5) * axes.distance_max / axes.distance_bins; }

  /** \brief Centre of angle bin \a b, degrees. */
  double
  angleBinCentre (int b) const { return (b + 0.5) * 180.0 / axes.angle_bins; }

  /** \brief The fullest bin whose centre lies within \a window_m and \a window_deg of
    * (distance_m, angle_deg); ties go to the bin nearest that point.
    */
  RelationPeak
  peakNear (double distance_m, double angle_deg, double window_m, double window_deg) const;
};

/** \brief Accumulates the relations of every pair of \a texlets (valid ones: see
  * isValidTexlet; the others are skipped) against \a object's expected relations.
  * \param labels one face index of \a object per texlet (negative: none), or empty
  * \throws pcl::BadArgumentException for bad axes, a label count that does not match, a label
  *         beyond the object's faces, or an object without relations.
  */
RelationStatistics
accumulateRelations (const pcl::PointCloud<pcl::Texlet> &texlets, const KnownObject &object,
                     const RelationParameters &params = RelationParameters (), const std::vector<int> &labels = {});

/** \brief The same computation as a PCL-style class: set the input and the object, compute. */
class TexletRelations
{
public:
  /** \brief The texlets whose pairs are related (one reference frame). */
  void
  setInputCloud (const pcl::PointCloud<pcl::Texlet>::ConstPtr &cloud) { input_ = cloud; }

  /** \brief The object whose expected relations define inliers (default paperBoxObject ()). */
  void
  setKnownObject (const KnownObject &object) { object_ = object; }

  /** \brief Face labels, one per texlet (see labelPoint); empty for none. */
  void
  setLabels (const std::vector<int> &labels) { labels_ = labels; }

  /** \brief Histogram axes. */
  void
  setHistogramAxes (const kernels::HistogramAxes &axes) { params_.axes = axes; }

  /** \brief OpenMP threads (0: OpenMP's default); results do not depend on it. */
  void
  setNumberOfThreads (unsigned threads) { params_.threads = threads; }

  /** \brief Where the pairs are accumulated (empty: OpenMP on the CPU); see RelationBackend. */
  void
  setBackend (const RelationBackend &backend) { params_.backend = backend; }

  /** \brief Runs accumulateRelations on the input.
    * \throws pcl::BadArgumentException without input, or as accumulateRelations.
    */
  void
  compute (RelationStatistics &out) const;

private:
  pcl::PointCloud<pcl::Texlet>::ConstPtr input_;
  KnownObject object_ = paperBoxObject ();
  std::vector<int> labels_;
  RelationParameters params_;
};

/** \brief The face (labelPoint) of every texlet of \a texlets; -1 for invalid texlets. */
std::vector<int>
labelTexlets (const pcl::PointCloud<pcl::Texlet> &texlets, const KnownObject &object,
              double max_plane_distance_m = 0.02, double margin_m = 0.01);

/** \brief How well the texlets on one face of the known object fit it. */
struct FaceQuality
{
  std::string name;
  std::size_t texlets = 0;
  double rms_distance_mm = 0.0; ///< RMS distance of the centres from the face's plane
  double rms_angle_deg = 0.0;   ///< RMS angle between the normals and the face's normal
  double median_angle_deg = 0.0; ///< median of those angles: robust to texlets straddling an edge
};

/** \brief FaceQuality of every face of \a object from \a texlets labelled by \a labels. */
std::vector<FaceQuality>
faceQuality (const pcl::PointCloud<pcl::Texlet> &texlets, const std::vector<int> &labels, const KnownObject &object);

} // namespace texlet
} // namespace pcl
