/*
 * pcl_texlet kernels: accumulating texlet relations (normal distance x angle) straight into a
 * 2D histogram and into inlier counts, without storing the pairs (the paper's Sect. 4, Fig. 10b
 * and Fig. 11).
 *
 * The unit of work is one row: texlet i against every texlet j > i, each unordered pair giving
 * both directed relations (n_ij, theta) and (n_ji, theta). A caller owns one RelationCounts per
 * thread (CPU) or per block (GPU) and sums them afterwards, so rows can run in any order.
 * Everything here is plain data behind raw pointers so the same code can move into a CUDA
 * kernel unchanged; the CPU driver is pcl::texlet::accumulateRelations (multi_sensor/).
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/texlet_relation.h>
#include <pcl_texlet/kernels/vec3.h>

#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Bins of the relation histogram: distance [0, distance_max) in distance_bins equal
  * bins, angle [0, 180] degrees in angle_bins equal bins (180 itself falls in the last one).
  */
struct HistogramAxes
{
  float distance_max = 0.3f; ///< upper edge of the distance axis, units of the centres (metres)
  int distance_bins = 150;   ///< bins along the distance axis (>= 1)
  int angle_bins = 180;      ///< bins along the angle axis, 0 to 180 degrees (>= 1)
};

/** \brief Flat index angle_bin * distance_bins + distance_bin of a relation, or -1 when the
  * distance is outside [0, distance_max) or either value is NaN.
  */
template <typename S> PCL_TEXLET_HD int
relationBin (const HistogramAxes &axes, S distance, S angle_deg)
{
  if (!(distance >= S (0)) || !(distance < S (axes.distance_max)) || !(angle_deg >= S (0)) || !(angle_deg <= S (180)))
    return -1;
  int db = static_cast<int> (distance * (S (axes.distance_bins) / S (axes.distance_max)));
  int ab = static_cast<int> (angle_deg * (S (axes.angle_bins) / S (180)));
  db = db < axes.distance_bins ? db : axes.distance_bins - 1; // rounding at the upper edge
  ab = ab < axes.angle_bins ? ab : axes.angle_bins - 1;       // 180 degrees exactly
  return ab * axes.distance_bins + db;
}

/** \brief An expected relation and its inlier box (the paper's Fig. 10b): relations within
  * angle_tol_deg of angle_deg and within distance_tol of [distance_min, distance_max] are inliers.
  * A point relation (Table 2's 0 deg / 240 mm) has distance_min == distance_max; a line
  * (orthogonal planes, 90 deg / 0-240 mm) has a range.
  */
struct RelationBox
{
  float angle_deg = 0.0f;      ///< expected angle, degrees
  float distance_min = 0.0f;   ///< expected normal distance, lower end (units of the centres)
  float distance_max = 0.0f;   ///< expected normal distance, upper end
  float angle_tol_deg = 10.0f; ///< half width of the box in angle, degrees (paper: 10)
  float distance_tol = 0.005f; ///< margin of the box in distance (paper: 5 mm)
};

/** \brief Whether (distance, angle) lies in \a box (edges included). */
template <typename S> PCL_TEXLET_HD bool
insideRelationBox (const RelationBox &box, S distance, S angle_deg)
{
  return angle_deg >= S (box.angle_deg) - S (box.angle_tol_deg) && angle_deg <= S (box.angle_deg) + S (box.angle_tol_deg) &&
         distance >= S (box.distance_min) - S (box.distance_tol) && distance <= S (box.distance_max) + S (box.distance_tol);
}

/** \brief Index of the first box of \a boxes holding (distance, angle), or -1 for an outlier. */
template <typename S> PCL_TEXLET_HD int
matchRelationBox (const RelationBox *boxes, int box_count, S distance, S angle_deg)
{
  for (int b = 0; b < box_count; ++b)
    if (insideRelationBox (boxes[b], distance, angle_deg))
      return b;
  return -1;
}

/** \brief The texlets whose relations are accumulated: unit normals, optional labels (e.g. the
  * face of a known object each texlet lies on; negative = unlabelled).
  */
template <typename S>
struct RelationInput
{
  const Vec3<S> *centre = nullptr;
  const Vec3<S> *normal = nullptr;
  const int *label = nullptr; ///< may be null: no per-label statistics
  int count = 0;
};

/** \brief What the relations are sorted into. */
struct RelationConfig
{
  HistogramAxes axes;
  const RelationBox *boxes = nullptr; ///< expected relations; may be null with box_count 0
  int box_count = 0;
  int label_count = 0;                ///< labels 0 .. label_count - 1 get a pair matrix
};

/** \brief One accumulator (per thread or block). Arrays are caller-owned and zeroed:
  * histogram[axes.distance_bins * axes.angle_bins], box_hits[box_count],
  * label_pairs[label_count^2], label_inliers[label_count^2] (the last two may be null when
  * label_count is 0). Counts are of directed relations.
  */
template <typename Count>
struct RelationCounts
{
  Count *histogram = nullptr;
  Count *box_hits = nullptr;
  Count *label_pairs = nullptr;   ///< [label_i * label_count + label_j]: directed relations
  Count *label_inliers = nullptr; ///< of those, the ones inside some box
  Count relations = 0;            ///< every directed relation seen
  Count inliers = 0;              ///< inside some box
  Count outside_histogram = 0;    ///< distance beyond the histogram's axis (still counted above)
};

/** \brief Sorts one directed relation of texlets with labels \a label_i, \a label_j. */
template <typename S, typename Count> PCL_TEXLET_HD void
addDirectedRelation (const RelationConfig &config, RelationCounts<Count> &counts, S distance, S angle_deg, int label_i,
                     int label_j)
{
  ++counts.relations;
  const int bin = relationBin (config.axes, distance, angle_deg);
  if (bin >= 0)
    ++counts.histogram[bin];
  else
    ++counts.outside_histogram;
  const int box = matchRelationBox (config.boxes, config.box_count, distance, angle_deg);
  if (box >= 0)
  {
    ++counts.inliers;
    ++counts.box_hits[box];
  }
  if (label_i >= 0 && label_j >= 0 && label_i < config.label_count && label_j < config.label_count)
  {
    const int cell = label_i * config.label_count + label_j;
    ++counts.label_pairs[cell];
    if (box >= 0)
      ++counts.label_inliers[cell];
  }
}

/** \brief Index of the lowest set bit of \a m (m != 0). */
PCL_TEXLET_HD int
lowestSetBit (unsigned m)
{
#if defined(__CUDA_ARCH__)
  return __ffs (static_cast<int> (m)) - 1;
#else
  return __builtin_ctz (m);
#endif
}

/** \brief Most expected relations a RelationConfig may hold (a bit mask per pair holds them). */
constexpr int kMaxRelationBoxes = 32;

/** \brief Row \a i: texlet i against every texlet j > i, both directions of each pair; the same
  * counts as addDirectedRelation on (n_ij, theta, label_i, label_j) and (n_ji, theta, label_j,
  * label_i) for every j > i.
  *
  * Why not simply call addDirectedRelation: the two directions share the angle, so the boxes'
  * angle tests are done once per pair (as a bit mask), and the scalar counters live in locals,
  * since stores through the histogram pointer could otherwise alias them and force a reload of
  * every counter per pair (this halves the instructions per pair). box_count must not exceed
  * kMaxRelationBoxes.
  */
template <typename S, typename Count> PCL_TEXLET_HD void
accumulateRelationRow (int i, const RelationInput<S> &in, const RelationConfig &config, RelationCounts<Count> &counts)
{
  const Vec3<S> p_i = in.centre[i], n_i = in.normal[i];
  const int label_i = in.label ? in.label[i] : -1;
  const int labels = config.label_count;
  const bool labelled_i = label_i >= 0 && label_i < labels;
  const int boxes = config.box_count < kMaxRelationBoxes ? config.box_count : kMaxRelationBoxes;
  Count *const histogram = counts.histogram;
  Count *const box_hits = counts.box_hits;
  // The boxes' limits in locals, computed as insideRelationBox computes them.
  S angle_lo[kMaxRelationBoxes], angle_hi[kMaxRelationBoxes], distance_lo[kMaxRelationBoxes],
      distance_hi[kMaxRelationBoxes];
  for (int b = 0; b < boxes; ++b)
  {
    const RelationBox &box = config.boxes[b];
    angle_lo[b] = S (box.angle_deg) - S (box.angle_tol_deg);
    angle_hi[b] = S (box.angle_deg) + S (box.angle_tol_deg);
    distance_lo[b] = S (box.distance_min) - S (box.distance_tol);
    distance_hi[b] = S (box.distance_max) + S (box.distance_tol);
  }
  Count inliers = 0, outside = 0;
  for (int j = i + 1; j < in.count; ++j)
  {
    const PairRelation<S> r = texletRelation (p_i, n_i, in.centre[j], in.normal[j]);
    // Boxes whose angle range holds theta.
    unsigned angle_ok = 0u;
    for (int b = 0; b < boxes; ++b)
      angle_ok |= static_cast<unsigned> (r.angle_deg >= angle_lo[b] && r.angle_deg <= angle_hi[b]) << b;
    const int label_j = in.label ? in.label[j] : -1;
    const bool labelled = labelled_i && label_j >= 0 && label_j < labels;
    for (int direction = 0; direction < 2; ++direction)
    {
      const S distance = direction == 0 ? r.distance_ij : r.distance_ji;
      const int bin = relationBin (config.axes, distance, r.angle_deg);
      if (bin >= 0)
        ++histogram[bin];
      else
        ++outside;
      int box = -1;
      for (unsigned m = angle_ok; m != 0u && box < 0; m &= m - 1u)
      {
        const int b = lowestSetBit (m); // the first match, as matchRelationBox
        if (distance >= distance_lo[b] && distance <= distance_hi[b])
          box = b;
      }
      if (box >= 0)
      {
        ++inliers;
        ++box_hits[box];
      }
      if (labelled)
      {
        const int cell = direction == 0 ? label_i * labels + label_j : label_j * labels + label_i;
        ++counts.label_pairs[cell];
        if (box >= 0)
          ++counts.label_inliers[cell];
      }
    }
  }
  const Count pairs = static_cast<Count> (in.count - 1 - i);
  counts.relations += 2 * pairs;
  counts.inliers += inliers;
  counts.outside_histogram += outside;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
