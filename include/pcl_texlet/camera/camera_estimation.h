/*
 * pcl_texlet: recover a pinhole camera from an organised cloud.
 *
 * An organised cloud made by back-projection keeps u = fx x/z + cx and v = fy y/z + cy for
 * every valid pixel; a least-squares line per axis gives the intrinsics back. Used when the
 * user sets no camera, so the noise model's radius is measured from the right centre.
 */
#pragma once

#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/camera/valid_point.h>

#include <pcl/exceptions.h>
#include <pcl/point_cloud.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{

/** \throws pcl::UnorganizedPointCloudException for an unorganised cloud,
  *         pcl::BadArgumentException with fewer than 16 valid points or degenerate geometry.
  */
template <typename PointT> PinholeModel
estimatePinholeModel (const pcl::PointCloud<PointT> &cloud)
{
  if (cloud.height <= 1 || cloud.width * cloud.height != cloud.size ())
    throw pcl::UnorganizedPointCloudException ("estimatePinholeModel: the cloud is not organised");
  // Sums for the two regressions u ~ a x/z + b and v ~ c y/z + d.
  double n = 0, sx = 0, sxx = 0, su = 0, sxu = 0, sy = 0, syy = 0, sv = 0, syv = 0;
  const int step = cloud.size () > 20000 ? 3 : 1;
  for (std::uint32_t v = 0; v < cloud.height; v += step)
    for (std::uint32_t u = 0; u < cloud.width; u += step)
    {
      const PointT &p = cloud (u, v);
      if (!isValidDepthPoint (p))
        continue;
      const double a = p.x / p.z, b = p.y / p.z;
      n += 1; sx += a; sxx += a * a; su += u; sxu += a * u;
      sy += b; syy += b * b; sv += v; syv += b * v;
    }
  const double dx = n * sxx - sx * sx, dy = n * syy - sy * sy;
  if (n < 16 || !(dx > 0) || !(dy > 0))
  {
    std::ostringstream msg;
    msg << "estimatePinholeModel: cannot recover intrinsics from " << n
        << " valid points; set the camera explicitly";
    throw pcl::BadArgumentException (msg.str ());
  }
  const double fx = (n * sxu - sx * su) / dx, cx = (su - fx * sx) / n;
  const double fy = (n * syv - sy * sv) / dy, cy = (sv - fy * sy) / n;
  if (!(fx > 0) || !(fy > 0))
    throw pcl::BadArgumentException ("estimatePinholeModel: the cloud's points do not follow a pinhole projection; set the camera explicitly");
  return PinholeModel (fx, fy, cx, cy);
}

} // namespace texlet
} // namespace pcl
