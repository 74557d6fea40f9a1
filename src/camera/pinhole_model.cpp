#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/kernels/pinhole_ray.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{

PinholeModel::PinholeModel (double fx, double fy, double cx, double cy, const kernels::PlumbBob &d)
  : fx_ (fx), fy_ (fy), cx_ (cx), cy_ (cy), d_ (d)
{
  const bool finite = std::isfinite (fx) && std::isfinite (fy) && std::isfinite (cx) && std::isfinite (cy) &&
                      std::isfinite (d.k1) && std::isfinite (d.k2) && std::isfinite (d.p1) && std::isfinite (d.p2) &&
                      std::isfinite (d.k3);
  if (!(fx > 0) || !(fy > 0) || !finite)
  {
    std::ostringstream msg;
    msg << "PinholeModel: focal lengths must be positive and all intrinsics finite (got fx " << fx << ", fy " << fy
        << ", cx " << cx << ", cy " << cy << ", k1 k2 p1 p2 k3 " << d.k1 << " " << d.k2 << " " << d.p1 << " " << d.p2
        << " " << d.k3 << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
}

PinholeModel
PinholeModel::fromCameraInfo (const CameraInfo &info)
{
  kernels::PlumbBob d;
  if (info.distortion_model == "plumb_bob" && info.D.size () == 5)
    d = {info.D[0], info.D[1], info.D[2], info.D[3], info.D[4]};
  else
    for (const double c : info.D)
      if (c != 0)
        throw pcl::BadArgumentException ("PinholeModel: distortion model '" + info.distortion_model +
                                         "' is not supported (only plumb_bob with 5 coefficients)");
  return PinholeModel (info.fx (), info.fy (), info.cx (), info.cy (), d);
}

bool
PinholeModel::hasDistortion () const
{
  return kernels::hasDistortion (d_);
}

void
PinholeModel::pixelToRay (double u, double v, double &x, double &y) const
{
  kernels::pinholeRay (fx_, fy_, cx_, cy_, d_, u, v, x, y);
}

void
PinholeModel::project (double X, double Y, double Z, double &u, double &v) const
{
  double xd, yd;
  kernels::distortPlumbBob (d_, X / Z, Y / Z, xd, yd);
  u = fx_ * xd + cx_;
  v = fy_ * yd + cy_;
}

double
PinholeModel::principalPointDistance (double u, double v) const
{
  return std::hypot (u - cx_, v - cy_);
}

} // namespace texlet
} // namespace pcl
