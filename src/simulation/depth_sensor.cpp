#include <pcl_texlet/simulation/depth_sensor.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{
namespace sim
{

DepthSensor
DepthSensor::kinect (int width, int height)
{
  DepthSensor s;
  s.width = width;
  s.height = height;
  s.fx = s.fy = 580.0 * width / 640.0;
  s.cx = 0.5 * (width - 1);
  s.cy = 0.5 * (height - 1);
  return s;
}

void
DepthSensor::validate () const
{
  std::ostringstream msg;
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    msg << "image size " << width << "x" << height << " must be positive and at most 16384x16384";
  else if (!(fx > 0) || !(fy > 0) || !std::isfinite (fx) || !std::isfinite (fy))
    msg << "focal lengths must be positive and finite (got fx " << fx << ", fy " << fy << ")";
  else if (!std::isfinite (cx) || !std::isfinite (cy))
    msg << "the principal point must be finite (got cx " << cx << ", cy " << cy << ")";
  else if (!(baseline_m > 0) || !std::isfinite (baseline_m))
    msg << "the baseline must be positive and finite (got " << baseline_m << " m)";
  else if (!(min_depth_m >= 0) || !(max_depth_m > min_depth_m) || !(max_depth_m <= 65.535))
    msg << "the depth range must satisfy 0 <= min < max <= 65.535 m (16-bit millimetres; got " << min_depth_m
        << " .. " << max_depth_m << " m)";
  else
  {
    const Eigen::Matrix3d r = pose.linear ();
    if (!pose.matrix ().allFinite () || !(r.transpose () * r).isIdentity (1e-9) || !(r.determinant () > 0) ||
        !pose.matrix ().row (3).isApprox (Eigen::RowVector4d (0, 0, 0, 1)))
      msg << "the pose must be a finite rigid transform (a rotation and a translation)";
    else
      return;
  }
  throw pcl::BadArgumentException ("depth sensor: " + msg.str ());
}

} // namespace sim
} // namespace texlet
} // namespace pcl
