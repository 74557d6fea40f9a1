/*
 * pcl_texlet_bench: a pcl::search::Search that answers with a texlet's pixel neighbourhood.
 *
 * PCL's feature estimators find neighbours through a search object. To give
 * pcl::NormalEstimationOMP exactly the points TexletEstimation uses, this search returns, for
 * a query by index, the valid pixels of the disc of `radius` pixels around that pixel, in disc
 * order: kernels::forEachDiscPoint, the very gather of the texlet stages, before RANSAC. The k
 * or radius that the estimator passes is ignored: the disc is the neighbourhood.
 */
#pragma once

#include <pcl_texlet/features/cloud_points.h>
#include <pcl_texlet/kernels/pixel_disc.h>

#include <pcl/exceptions.h>
#include <pcl/search/search.h>

#include <string>
#include <vector>

namespace pcl_texlet_bench
{

template <typename PointT>
class PixelDiscSearch : public pcl::search::Search<PointT>
{
public:
  using PointCloud = typename pcl::search::Search<PointT>::PointCloud;
  using PointCloudConstPtr = typename pcl::search::Search<PointT>::PointCloudConstPtr;
  using IndicesConstPtr = pcl::IndicesConstPtr;
  using pcl::search::Search<PointT>::nearestKSearch;
  using pcl::search::Search<PointT>::radiusSearch;

  /** \param radius disc radius in pixels (>= 1) */
  explicit PixelDiscSearch (int radius) : pcl::search::Search<PointT> ("PixelDiscSearch", false), radius_ (radius)
  {
    if (radius < 1)
      throw pcl::BadArgumentException ("PixelDiscSearch: radius " + std::to_string (radius) + " px is not positive");
    const int n = pcl::texlet::kernels::pixelDiscSize (radius);
    du_.resize (n);
    dv_.resize (n);
    pcl::texlet::kernels::pixelDiscOffsets (radius, du_.data (), dv_.data (), n);
  }

  /** \brief Pixels in the full disc (valid or not). */
  int
  discSize () const { return static_cast<int> (du_.size ()); }

  void
  setInputCloud (const PointCloudConstPtr &cloud, const IndicesConstPtr &indices = IndicesConstPtr ()) override
  {
    if (!cloud || !cloud->isOrganized ())
      throw pcl::UnorganizedPointCloudException ("PixelDiscSearch needs an organised cloud");
    this->input_ = cloud;
    this->indices_ = indices;
  }

  /** \brief The disc's valid pixels around pixel \a centre of \a cloud, with their squared
    * metric distances to the centre point (0 when the centre itself is invalid).
    */
  int
  disc (const PointCloud &cloud, pcl::index_t centre, pcl::Indices &indices, std::vector<float> &sqr_distances) const
  {
    indices.clear ();
    sqr_distances.clear ();
    const pcl::texlet::detail::CloudPoints<PointT> frame (cloud);
    pcl::texlet::kernels::PixelDisc disc;
    disc.du = du_.data ();
    disc.dv = dv_.data ();
    disc.size = discSize ();
    disc.radius = radius_;
    const PointT &c = cloud[centre];
    const bool centre_valid = frame.valid (c);
    const int w = frame.width ();
    pcl::texlet::kernels::forEachDiscPoint (frame, disc, static_cast<int> (centre % w), static_cast<int> (centre / w),
                                            [&] (const PointT &p, int index) {
                                              indices.push_back (index);
                                              const float dx = p.x - c.x, dy = p.y - c.y, dz = p.z - c.z;
                                              sqr_distances.push_back (centre_valid ? dx * dx + dy * dy + dz * dz
                                                                                    : 0.0f);
                                            });
    return static_cast<int> (indices.size ());
  }

  int
  nearestKSearch (const PointCloud &cloud, pcl::index_t index, int, pcl::Indices &k_indices,
                  std::vector<float> &k_sqr_distances) const override
  {
    return disc (cloud, index, k_indices, k_sqr_distances);
  }

  int
  radiusSearch (const PointCloud &cloud, pcl::index_t index, double, pcl::Indices &k_indices,
                std::vector<float> &k_sqr_distances, unsigned int = 0) const override
  {
    return disc (cloud, index, k_indices, k_sqr_distances);
  }

  /** A bare point carries no pixel position: only queries by index are answered. */
  int
  nearestKSearch (const PointT &, int, pcl::Indices &, std::vector<float> &) const override
  {
    throw pcl::PCLException ("PixelDiscSearch answers queries by pixel index only");
  }

  int
  radiusSearch (const PointT &, double, pcl::Indices &, std::vector<float> &, unsigned int = 0) const override
  {
    throw pcl::PCLException ("PixelDiscSearch answers queries by pixel index only");
  }

private:
  int radius_;
  std::vector<int> du_, dv_;
};

} // namespace pcl_texlet_bench
