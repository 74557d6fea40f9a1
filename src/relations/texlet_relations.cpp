#include <pcl_texlet/relations/texlet_merge.h>
#include <pcl_texlet/relations/texlet_relations.h>

#include <pcl/exceptions.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl
{
namespace texlet
{

namespace
{

double
percent (std::uint64_t part, std::uint64_t whole)
{
  return whole == 0 ? std::numeric_limits<double>::quiet_NaN () : 100.0 * static_cast<double> (part) / whole;
}

/** One thread's counts, owning the arrays RelationCounts points into. */
struct ThreadCounts
{
  std::vector<std::uint64_t> histogram, box_hits, label_pairs, label_inliers;
  kernels::RelationCounts<std::uint64_t> counts;

  ThreadCounts (std::size_t bins, std::size_t boxes, std::size_t label_cells)
    : histogram (bins, 0), box_hits (boxes, 0), label_pairs (label_cells, 0), label_inliers (label_cells, 0)
  {
    counts.histogram = histogram.data ();
    counts.box_hits = box_hits.data ();
    counts.label_pairs = label_pairs.empty () ? nullptr : label_pairs.data ();
    counts.label_inliers = label_inliers.empty () ? nullptr : label_inliers.data ();
  }
};

void
addInto (std::vector<std::uint64_t> &sum, const std::vector<std::uint64_t> &part)
{
  for (std::size_t i = 0; i < sum.size (); ++i)
    sum[i] += part[i];
}

} // namespace

double
RelationStatistics::inlierPercent () const
{
  return percent (inliers, relation_count);
}

double
RelationStatistics::labelPairInlierPercent (int a, int b) const
{
  const int n = static_cast<int> (labels.size ());
  if (a < 0 || b < 0 || a >= n || b >= n)
    return std::numeric_limits<double>::quiet_NaN ();
  std::uint64_t pairs = label_pairs[a * n + b], in = label_inliers[a * n + b];
  if (a != b)
  {
    pairs += label_pairs[b * n + a];
    in += label_inliers[b * n + a];
  }
  return percent (in, pairs);
}

double
RelationStatistics::labelInlierPercent (int a) const
{
  const int n = static_cast<int> (labels.size ());
  if (a < 0 || a >= n)
    return std::numeric_limits<double>::quiet_NaN ();
  std::uint64_t pairs = 0, in = 0;
  for (int b = 0; b < n; ++b)
  {
    pairs += label_pairs[a * n + b];
    in += label_inliers[a * n + b];
  }
  return percent (in, pairs);
}

RelationPeak
RelationStatistics::peakNear (double distance_m, double angle_deg, double window_m, double window_deg) const
{
  RelationPeak best;
  double best_offset = std::numeric_limits<double>::infinity ();
  bool found = false;
  for (int a = 0; a < axes.angle_bins; ++a)
  {
    const double ac = angleBinCentre (a);
    if (std::fabs (ac - angle_deg) > window_deg)
      continue;
    for (int d = 0; d < axes.distance_bins; ++d)
    {
      const double dc = distanceBinCentre (d);
      if (std::fabs (dc - distance_m) > window_m)
        continue;
      const std::uint64_t c = count (d, a);
      const double offset = std::hypot ((dc - distance_m) / window_m, (ac - angle_deg) / window_deg);
      if (!found || c > best.count || (c == best.count && offset < best_offset))
      {
        best = {dc, ac, c};
        best_offset = offset;
        found = true;
      }
    }
  }
  return best;
}

RelationStatistics
accumulateRelations (const pcl::PointCloud<pcl::Texlet> &texlets, const KnownObject &object,
                     const RelationParameters &params, const std::vector<int> &labels)
{
  const kernels::HistogramAxes &axes = params.axes;
  if (!(axes.distance_max > 0) || !std::isfinite (axes.distance_max) || axes.distance_bins < 1 || axes.angle_bins < 1)
    throw pcl::BadArgumentException ("accumulateRelations: the histogram needs a positive distance range and at "
                                     "least one bin per axis");
  if (axes.distance_bins > 100000 || axes.angle_bins > 100000)
    throw pcl::BadArgumentException ("accumulateRelations: more than 100000 bins along an axis");
  if (object.relations.empty ())
    throw pcl::BadArgumentException ("accumulateRelations: the object '" + object.name + "' has no expected relations");
  if (object.relations.size () > static_cast<std::size_t> (kernels::kMaxRelationBoxes))
    throw pcl::BadArgumentException ("accumulateRelations: more than " + std::to_string (kernels::kMaxRelationBoxes) +
                                     " expected relations");
  if (!labels.empty () && labels.size () != texlets.size ())
    throw pcl::BadArgumentException ("accumulateRelations: " + std::to_string (labels.size ()) + " labels for " +
                                     std::to_string (texlets.size ()) + " texlets");
  const int label_count = labels.empty () ? 0 : static_cast<int> (object.faces.size ());
  for (int l : labels)
    if (l >= label_count)
      throw pcl::BadArgumentException ("accumulateRelations: label " + std::to_string (l) + " but the object has " +
                                       std::to_string (label_count) + " faces");

  // Compact the valid texlets into the kernel's plain arrays.
  std::vector<kernels::Vec3<float>> centre, normal;
  std::vector<int> label;
  centre.reserve (texlets.size ());
  normal.reserve (texlets.size ());
  for (std::size_t i = 0; i < texlets.size (); ++i)
  {
    const pcl::Texlet &t = texlets[i];
    if (!isValidTexlet (t))
      continue;
    const float len = std::sqrt (t.normal_x * t.normal_x + t.normal_y * t.normal_y + t.normal_z * t.normal_z);
    if (!(len > 0))
      continue;
    centre.push_back ({t.x, t.y, t.z});
    normal.push_back ({t.normal_x / len, t.normal_y / len, t.normal_z / len});
    if (!labels.empty ())
      label.push_back (labels[i]);
  }
  if (centre.size () > static_cast<std::size_t> (std::numeric_limits<int>::max ()))
    throw pcl::BadArgumentException ("accumulateRelations: too many texlets");

  std::vector<kernels::RelationBox> boxes;
  for (const auto &r : object.relations)
  {
    kernels::RelationBox b;
    b.angle_deg = static_cast<float> (r.angle_deg);
    b.distance_min = static_cast<float> (r.distance_min_m);
    b.distance_max = static_cast<float> (r.distance_max_m);
    b.angle_tol_deg = static_cast<float> (object.angle_tol_deg);
    b.distance_tol = static_cast<float> (object.distance_tol_m);
    boxes.push_back (b);
  }

  kernels::RelationInput<float> in;
  in.centre = centre.data ();
  in.normal = normal.data ();
  in.label = label.empty () ? nullptr : label.data ();
  in.count = static_cast<int> (centre.size ());
  kernels::RelationConfig config;
  config.axes = axes;
  config.boxes = boxes.data ();
  config.box_count = static_cast<int> (boxes.size ());
  config.label_count = label_count;

  const std::size_t bins = static_cast<std::size_t> (axes.distance_bins) * axes.angle_bins;
  const std::size_t cells = static_cast<std::size_t> (label_count) * label_count;

  RelationStatistics out;
  out.axes = axes;
  out.histogram.assign (bins, 0);
  out.relations = object.relations;
  out.angle_tol_deg = object.angle_tol_deg;
  out.distance_tol_m = object.distance_tol_m;
  out.relation_hits.assign (boxes.size (), 0);
  if (label_count > 0)
    for (const auto &f : object.faces)
      out.labels.push_back (f.name);
  out.label_pairs.assign (cells, 0);
  out.label_inliers.assign (cells, 0);
  out.texlets = centre.size ();

  if (params.backend)
  {
    // Another backend (the GPU): it adds into the output's zeroed arrays.
    kernels::RelationCounts<std::uint64_t> counts;
    counts.histogram = out.histogram.data ();
    counts.box_hits = out.relation_hits.data ();
    counts.label_pairs = cells ? out.label_pairs.data () : nullptr;
    counts.label_inliers = cells ? out.label_inliers.data () : nullptr;
    params.backend (in, config, counts);
    out.relation_count = counts.relations;
    out.inliers = counts.inliers;
    out.outside_histogram = counts.outside_histogram;
    return out;
  }

  const int threads = params.threads > 0 ? static_cast<int> (params.threads) : omp_get_max_threads ();
#pragma omp parallel num_threads (threads)
  {
    ThreadCounts mine (bins, boxes.size (), cells);
    // Row i holds n - 1 - i pairs: dynamic scheduling in small chunks evens the load.
#pragma omp for schedule (dynamic, 16) nowait
    for (int i = 0; i < in.count; ++i)
      kernels::accumulateRelationRow (i, in, config, mine.counts);
#pragma omp critical (pcl_texlet_relations_merge)
    {
      addInto (out.histogram, mine.histogram);
      addInto (out.relation_hits, mine.box_hits);
      addInto (out.label_pairs, mine.label_pairs);
      addInto (out.label_inliers, mine.label_inliers);
      out.relation_count += mine.counts.relations;
      out.inliers += mine.counts.inliers;
      out.outside_histogram += mine.counts.outside_histogram;
    }
  }
  return out;
}

void
TexletRelations::compute (RelationStatistics &out) const
{
  if (!input_)
    throw pcl::BadArgumentException ("TexletRelations: no input cloud set");
  out = accumulateRelations (*input_, object_, params_, labels_);
}

std::vector<int>
labelTexlets (const pcl::PointCloud<pcl::Texlet> &texlets, const KnownObject &object, double max_plane_distance_m,
              double margin_m)
{
  std::vector<int> labels (texlets.size (), -1);
  for (std::size_t i = 0; i < texlets.size (); ++i)
    if (isValidTexlet (texlets[i]))
      labels[i] = labelPoint (object, texlets[i].getVector3fMap ().cast<double> (), max_plane_distance_m, margin_m);
  return labels;
}

std::vector<FaceQuality>
faceQuality (const pcl::PointCloud<pcl::Texlet> &texlets, const std::vector<int> &labels, const KnownObject &object)
{
  if (labels.size () != texlets.size ())
    throw pcl::BadArgumentException ("faceQuality: " + std::to_string (labels.size ()) + " labels for " +
                                     std::to_string (texlets.size ()) + " texlets");
  std::vector<FaceQuality> out (object.faces.size ());
  std::vector<double> sum_d2 (out.size (), 0.0), sum_a2 (out.size (), 0.0);
  std::vector<std::vector<double>> angles (out.size ());
  for (std::size_t f = 0; f < out.size (); ++f)
    out[f].name = object.faces[f].name;
  for (std::size_t i = 0; i < texlets.size (); ++i)
  {
    const int f = labels[i];
    if (f < 0 || f >= static_cast<int> (out.size ()) || !isValidTexlet (texlets[i]))
      continue;
    const ObjectFace &face = object.faces[f];
    const Eigen::Vector3d p = texlets[i].getVector3fMap ().cast<double> ();
    const Eigen::Vector3d n = texlets[i].getNormalVector3fMap ().cast<double> ().normalized ();
    const double d = face.normal.dot (p - face.centre);
    const double a = std::acos (std::clamp (n.dot (face.normal), -1.0, 1.0)) * 180.0 / M_PI;
    sum_d2[f] += d * d;
    sum_a2[f] += a * a;
    angles[f].push_back (a);
    ++out[f].texlets;
  }
  for (std::size_t f = 0; f < out.size (); ++f)
    if (out[f].texlets > 0)
    {
      out[f].rms_distance_mm = 1000.0 * std::sqrt (sum_d2[f] / out[f].texlets);
      out[f].rms_angle_deg = std::sqrt (sum_a2[f] / out[f].texlets);
      auto &v = angles[f];
      std::nth_element (v.begin (), v.begin () + v.size () / 2, v.end ());
      out[f].median_angle_deg = v[v.size () / 2];
    }
    else
      out[f].rms_distance_mm = out[f].rms_angle_deg = out[f].median_angle_deg =
          std::numeric_limits<double>::quiet_NaN ();
  return out;
}

} // namespace texlet
} // namespace pcl
