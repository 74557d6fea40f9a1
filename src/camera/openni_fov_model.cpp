#include <pcl_texlet/camera/openni_fov_model.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>

namespace pcl
{
namespace texlet
{

OpenNIFovModel::OpenNIFovModel (int width, int height, double hfov, double vfov)
  : width_ (width), height_ (height), hfov_ (hfov), vfov_ (vfov), tan_h_ (std::tan (hfov / 2)), tan_v_ (std::tan (vfov / 2))
{
  if (width <= 0 || height <= 0 || !(hfov > 0 && hfov < M_PI) || !(vfov > 0 && vfov < M_PI))
  {
    std::ostringstream msg;
    msg << "OpenNIFovModel: resolution must be positive and fields of view in (0, pi) radians (got " << width << "x"
        << height << ", hfov " << hfov << ", vfov " << vfov << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
}

namespace
{
/** Field of view of a focal length \a f over \a pixels. */
double
fov (double pixels, double f) { return 2 * std::atan (pixels / (2 * f)); }

constexpr double kKinectIrFocalVga = 120.0 / (2 * 0.1052); // PS1080: ZPD / (2 ZPPS), pixels at 640 wide
constexpr double kKinectRgbFocalVga = 525.0;
} // namespace

OpenNIFovModel
OpenNIFovModel::kinectIr (int width, int height)
{
  const double f = kKinectIrFocalVga * width / 640.0;
  return OpenNIFovModel (width, height, fov (width, f), fov (height, f));
}

OpenNIFovModel
OpenNIFovModel::kinectRgb (int width, int height)
{
  const double f = kKinectRgbFocalVga * width / 640.0;
  return OpenNIFovModel (width, height, fov (width, f), fov (height, f));
}

void
OpenNIFovModel::pixelToRay (double u, double v, double &x, double &y) const
{
  x = 2 * (u / width_ - 0.5) * tan_h_;  // Eq. 1 and 2
  y = 2 * (v / height_ - 0.5) * tan_v_; // Eq. 1 and 3, y down
}

void
OpenNIFovModel::project (double X, double Y, double Z, double &u, double &v) const
{
  u = width_ * (0.5 + X / (2 * Z * tan_h_));
  v = height_ * (0.5 + Y / (2 * Z * tan_v_));
}

double
OpenNIFovModel::principalPointDistance (double u, double v) const
{
  return std::hypot (u - 0.5 * width_, v - 0.5 * height_);
}

double
OpenNIFovModel::equivalentFx () const { return width_ / (2 * tan_h_); }

double
OpenNIFovModel::equivalentFy () const { return height_ / (2 * tan_v_); }

} // namespace texlet
} // namespace pcl
