#include <pcl_texlet/relations/texlet_merge.h>

#include <cmath>

namespace pcl
{
namespace texlet
{

bool
isValidTexlet (const pcl::Texlet &t)
{
  return t.support > 0 && std::isfinite (t.x) && std::isfinite (t.y) && std::isfinite (t.z) &&
         std::isfinite (t.normal_x) && std::isfinite (t.normal_y) && std::isfinite (t.normal_z);
}

void
transformTexlet (const pcl::Texlet &in, const Eigen::Isometry3d &pose, pcl::Texlet &out)
{
  out = in;
  if (!isValidTexlet (in))
    return;
  const Eigen::Matrix3f r = pose.linear ().cast<float> ();
  const Eigen::Vector3f p = (pose * in.getVector3fMap ().cast<double> ()).cast<float> ();
  const Eigen::Vector3f n = (r * in.getNormalVector3fMap ()).normalized ();
  out.getVector3fMap () = p;
  out.getNormalVector3fMap () = n;

  out.setCovarianceP (r * in.covarianceP () * r.transpose ());

  // The tangent frame is a function of N alone, so the rotated old frame is not the new one:
  // express the rotated deviations in the new frame.
  const Eigen::Matrix<float, 3, 2> t_old = in.tangentFrame (), t_new = out.tangentFrame ();
  const Eigen::Matrix2f m = t_new.transpose () * r * t_old;
  out.setCovarianceN (m * in.covarianceN () * m.transpose ());
}

void
transformTexlets (const pcl::PointCloud<pcl::Texlet> &in, const Eigen::Isometry3d &pose,
                  pcl::PointCloud<pcl::Texlet> &out)
{
  pcl::PointCloud<pcl::Texlet> result;
  result.header = in.header;
  result.width = in.width;
  result.height = in.height;
  result.is_dense = in.is_dense;
  result.resize (in.size ());
  for (std::size_t i = 0; i < in.size (); ++i)
    transformTexlet (in[i], pose, result[i]);
  out = std::move (result);
}

void
MergedTexlets::add (const pcl::PointCloud<pcl::Texlet> &cloud, const Eigen::Isometry3d &pose,
                    std::uint16_t sensor_index)
{
  texlets.reserve (texlets.size () + cloud.size ());
  for (const auto &t : cloud)
  {
    if (!isValidTexlet (t))
    {
      ++dropped;
      continue;
    }
    pcl::Texlet moved;
    transformTexlet (t, pose, moved);
    texlets.push_back (moved); // push_back keeps width = size, height = 1
    sensor.push_back (sensor_index);
  }
  texlets.is_dense = true;
}

std::size_t
MergedTexlets::countFrom (std::uint16_t sensor_index) const
{
  std::size_t n = 0;
  for (auto s : sensor)
    n += s == sensor_index ? 1 : 0;
  return n;
}

} // namespace texlet
} // namespace pcl
