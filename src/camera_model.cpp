#include <pcl_texlet/camera_model.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{

PinholeCamera::PinholeCamera (double fx, double fy, double cx, double cy) : fx_ (fx), fy_ (fy), cx_ (cx), cy_ (cy)
{
  if (!(fx > 0) || !(fy > 0) || !std::isfinite (fx) || !std::isfinite (fy) || !std::isfinite (cx) || !std::isfinite (cy))
  {
    std::ostringstream msg;
    msg << "PinholeCamera: focal lengths must be positive and all intrinsics finite (got fx " << fx << ", fy " << fy
        << ", cx " << cx << ", cy " << cy << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
}

double
PinholeCamera::principalPointDistance (double u, double v) const
{
  return std::hypot (u - cx_, v - cy_);
}

} // namespace texlet
} // namespace pcl
