/*
 * Camera models on scenes rendered through a known calibrated camera with distortion: the
 * pinhole model reconstructs them within 0.1 mm; the OpenNI model's errors (principal point at
 * the image centre, wrong field of view after registration) are measured and match their
 * closed-form predictions.
 */
#include "support/synthetic_scene.h"

#include <pcl_texlet/camera/openni_fov_model.h>
#include <pcl_texlet/camera/pinhole_model.h>

#include <pcl/exceptions.h>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

using namespace pcl_texlet_test;
using pcl::texlet::OpenNIFovModel;
using pcl::texlet::PinholeModel;
using pcl::texlet::kernels::PlumbBob;

namespace
{

/** A Kinect-like RGB camera after calibration: principal point off the centre, real distortion. */
const double kFx = 525.0, kFy = 527.0, kCx = 316.2, kCy = 247.9;
const PlumbBob kDistortion = {0.18, -0.42, 0.0011, -0.0007, 0.29};

/** Undistortion by OpenCV's fixed-point iteration (many steps): independent of the model's
  * Newton solver, so the rendering does not share code with what it tests.
  */
void
referenceRay (const PlumbBob &d, double u, double v, double &x, double &y)
{
  const double xd = (u - kCx) / kFx, yd = (v - kCy) / kFy;
  x = xd;
  y = yd;
  for (int i = 0; i < 60; ++i) // contracts by ~0.2 a step here: 60 steps reach double precision
  {
    const double r2 = x * x + y * y;
    const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double dx = 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x);
    const double dy = d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y;
    x = (xd - dx) / radial;
    y = (yd - dy) / radial;
  }
}

struct DepthRender
{
  int width = 640, height = 480;
  std::vector<double> z;               // depth along the optical axis, metres (NaN: no hit)
  std::vector<Eigen::Vector3d> truth;  // true 3D points
  std::vector<Eigen::Vector3d> normal; // true surface normals (to tell the surfaces apart)
};

/** Depth image of \a scene through the calibrated camera with lens distortion \a d (float
  * depth: no quantisation).
  */
DepthRender
renderCalibrated (const Scene &scene, const PlumbBob &d)
{
  DepthRender r;
  r.z.assign (r.width * r.height, std::nan (""));
  r.truth.assign (r.z.size (), Eigen::Vector3d::Constant (std::nan ("")));
  r.normal.assign (r.z.size (), Eigen::Vector3d::Zero ());
  for (int v = 0; v < r.height; ++v)
    for (int u = 0; u < r.width; ++u)
    {
      double x, y;
      referenceRay (d, u, v, x, y);
      const Eigen::Vector3d ray (x, y, 1);
      Hit hit;
      for (const auto &s : scene.surfaces)
        s->intersect (ray, hit);
      if (!std::isfinite (hit.t))
        continue;
      const std::size_t i = static_cast<std::size_t> (v) * r.width + u;
      r.z[i] = hit.t;
      r.truth[i] = hit.t * ray;
      r.normal[i] = hit.normal;
    }
  return r;
}

Eigen::Vector3d
backProject (const pcl::texlet::CameraModel &m, int u, int v, double z)
{
  double x, y;
  m.pixelToRay (u, v, x, y);
  return {x * z, y * z, z};
}

/** Unit normal of the least-squares plane through \a pts, facing the camera. */
Eigen::Vector3d
planeNormal (const std::vector<Eigen::Vector3d> &pts)
{
  Eigen::Vector3d mean = Eigen::Vector3d::Zero ();
  for (const auto &p : pts)
    mean += p;
  mean /= pts.size ();
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero ();
  for (const auto &p : pts)
    c += (p - mean) * (p - mean).transpose ();
  const Eigen::Vector3d n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> (c).eigenvectors ().col (0);
  return n.dot (mean) < 0 ? n : Eigen::Vector3d (-n);
}

/** Two walls meeting at 90 degrees in a vertical fold 1.2 m away: a V opening to the camera. */
Scene
vWalls ()
{
  Scene s;
  auto left = std::make_shared<PlaneSurface> (Eigen::Vector3d (1, 0, -1), Eigen::Vector3d (0, 0, 1.2));
  left->side = Eigen::Vector3d (-1, 0, 0);
  auto right = std::make_shared<PlaneSurface> (Eigen::Vector3d (-1, 0, -1), Eigen::Vector3d (0, 0, 1.2));
  right->side = Eigen::Vector3d (1, 0, 0);
  s.surfaces = {left, right};
  return s;
}

struct ModelErrors
{
  double angle_error_deg;   // measured angle between the V's walls minus 90 degrees
  double scale_error;       // lateral scale on a frontal wall, minus 1
  double offset_x_mm;       // lateral shift of the wall's centre point at 1 m, x
  double offset_y_mm;       // and y
  double max_error_mm;      // largest 3D error over the frontal wall at 1 m
};

/** Errors of model \a m on depth rendered through the calibrated camera with distortion \a d. */
ModelErrors
measure (const pcl::texlet::CameraModel &m, const PlumbBob &d)
{
  ModelErrors e;
  {
    const DepthRender r = renderCalibrated (vWalls (), d);
    std::vector<Eigen::Vector3d> left, right;
    for (int v = 0; v < r.height; ++v)
      for (int u = 0; u < r.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * r.width + u;
        if (std::isfinite (r.z[i]))
          (r.normal[i].x () > 0 ? left : right).push_back (backProject (m, u, v, r.z[i]));
      }
    // The walls' camera-facing normals are 90 degrees apart in truth.
    e.angle_error_deg = std::acos (planeNormal (left).dot (planeNormal (right))) * 180 / M_PI - 90;
  }
  {
    Scene frontal;
    frontal.add<PlaneSurface> (Eigen::Vector3d (0, 0, -1), Eigen::Vector3d (0, 0, 1.0));
    const DepthRender r = renderCalibrated (frontal, d);
    // Least squares x_rec = s x_true + t over the wall; the largest 3D error.
    double n = 0, sx = 0, sxx = 0, sy = 0, sxy = 0, max_err = 0;
    for (int v = 0; v < r.height; ++v)
      for (int u = 0; u < r.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t> (v) * r.width + u;
        const Eigen::Vector3d p = backProject (m, u, v, r.z[i]);
        const double xt = r.truth[i].x ();
        n += 1; sx += xt; sxx += xt * xt; sy += p.x (); sxy += xt * p.x ();
        max_err = std::max (max_err, (p - r.truth[i]).norm ());
      }
    e.scale_error = (n * sxy - sx * sy) / (n * sxx - sx * sx) - 1;
    e.max_error_mm = 1e3 * max_err;
    // The point straight ahead of the calibrated camera, where distortion vanishes.
    const int u0 = static_cast<int> (std::lround (kCx)), v0 = static_cast<int> (std::lround (kCy));
    const std::size_t i0 = static_cast<std::size_t> (v0) * r.width + u0;
    const Eigen::Vector3d p0 = backProject (m, u0, v0, r.z[i0]);
    e.offset_x_mm = 1e3 * (p0.x () - r.truth[i0].x ());
    e.offset_y_mm = 1e3 * (p0.y () - r.truth[i0].y ());
  }
  return e;
}

} // namespace

TEST (PinholeModel, DistortionRoundTripAcrossTheImage)
{
  const PinholeModel m (kFx, kFy, kCx, kCy, kDistortion);
  EXPECT_TRUE (m.hasDistortion ());
  double worst = 0;
  for (int v = 0; v < 480; v += 7)
    for (int u = 0; u < 640; u += 7)
    {
      double x, y, uu, vv;
      m.pixelToRay (u, v, x, y);
      ASSERT_TRUE (std::isfinite (x) && std::isfinite (y)) << u << "," << v;
      m.project (x, y, 1.0, uu, vv);
      worst = std::max (worst, std::hypot (uu - u, vv - v));
    }
  EXPECT_LT (worst, 1e-9) << "pixels";
}

TEST (PinholeModel, ReconstructsACalibratedSceneWithinATenthOfAMillimetre)
{
  const PinholeModel m (kFx, kFy, kCx, kCy, kDistortion);
  Scene scene;
  scene.add<BoxSurface> (Eigen::Vector3d (-0.064, -0.12, 0.9), Eigen::Vector3d (0.064, 0.12, 1.012));
  scene.add<PlaneSurface> (Eigen::Vector3d (0.2, 0.3, -1), Eigen::Vector3d (0, 0, 1.6));
  const DepthRender r = renderCalibrated (scene, kDistortion);
  double worst = 0;
  std::size_t n = 0;
  for (int v = 0; v < r.height; ++v)
    for (int u = 0; u < r.width; ++u)
    {
      const std::size_t i = static_cast<std::size_t> (v) * r.width + u;
      if (!std::isfinite (r.z[i]))
        continue;
      worst = std::max (worst, (backProject (m, u, v, r.z[i]) - r.truth[i]).norm ());
      ++n;
    }
  EXPECT_GT (n, 300000u);
  EXPECT_LT (worst, 1e-4) << "metres";
  const ModelErrors e = measure (m, kDistortion);
  EXPECT_LT (std::fabs (e.angle_error_deg), 1e-6);
  EXPECT_LT (std::fabs (e.scale_error), 1e-9);
  EXPECT_LT (e.max_error_mm, 1e-6);
}

TEST (OpenNIFovModel, IsThePaperEquationsAndAPinholeInDisguise)
{
  const OpenNIFovModel m = OpenNIFovModel::kinectIr ();
  EXPECT_NEAR (m.equivalentFx (), 570.342205, 1e-5); // 120 / (2 x 0.1052)
  EXPECT_NEAR (m.hfov () * 180 / M_PI, 58.59, 0.01);
  EXPECT_NEAR (m.vfov () * 180 / M_PI, 45.64, 0.01);
  // Eq. 1-3 at a corner pixel: x_norm = 2 (0/640 - 0.5) = -1, y_norm = 2 (480/480 - 0.5) = 1.
  double x, y;
  m.pixelToRay (0, 480, x, y);
  EXPECT_NEAR (x, -std::tan (m.hfov () / 2), 1e-15);
  EXPECT_NEAR (y, std::tan (m.vfov () / 2), 1e-15);
  m.pixelToRay (320, 240, x, y); // the assumed principal point
  EXPECT_EQ (x, 0.0);
  EXPECT_EQ (y, 0.0);
  double u, v;
  m.project (0.3, -0.2, 1.5, u, v);
  m.pixelToRay (u, v, x, y);
  EXPECT_NEAR (x * 1.5, 0.3, 1e-12);
  EXPECT_NEAR (y * 1.5, -0.2, 1e-12);
  EXPECT_THROW (OpenNIFovModel (640, 480, 0.0, 1.0), pcl::BadArgumentException);
  EXPECT_THROW (OpenNIFovModel (0, 480, 1.0, 1.0), pcl::BadArgumentException);
}

TEST (OpenNIFovModel, ErrorsOnRegisteredDepthMatchTheirPredictions)
{
  // Depth registered to the calibrated RGB camera, back-projected with OpenNI's model. Without
  // lens distortion the errors have closed forms; with it, distortion adds its own.
  const OpenNIFovModel ir = OpenNIFovModel::kinectIr (), rgb = OpenNIFovModel::kinectRgb ();
  const PlumbBob none;
  const ModelErrors flaw = measure (ir, none), fov_fixed = measure (rgb, none);

  // Wrong field of view: x and y shrink by f_true / f_IR, depth does not.
  const double s_pred = kFx / ir.equivalentFx () - 1;
  EXPECT_NEAR (flaw.scale_error, s_pred, 0.001) << "predicted " << s_pred;
  EXPECT_NEAR (fov_fixed.scale_error, kFx / rgb.equivalentFx () - 1, 0.001);
  // The shrink steepens the 45-degree walls: each turns to atan(1 / (1 + s)).
  const double angle_pred = 2 * (std::atan (1 / (1 + s_pred)) * 180 / M_PI - 45);
  EXPECT_NEAR (flaw.angle_error_deg, angle_pred, 0.1) << "predicted " << angle_pred;
  EXPECT_LT (std::fabs (fov_fixed.angle_error_deg), 0.1);
  // Principal point at the image centre: at pixel (u0, v0) OpenNI's ray is (u0 - 320) / f',
  // the true one (u0 - cx) / fx: at 1 m they differ by about (cx - 320) / fx.
  const double u0 = std::lround (kCx), v0 = std::lround (kCy);
  EXPECT_NEAR (fov_fixed.offset_x_mm, 1e3 * ((u0 - 320) / rgb.equivalentFx () - (u0 - kCx) / kFx), 0.01);
  EXPECT_NEAR (fov_fixed.offset_y_mm, 1e3 * ((v0 - 240) / rgb.equivalentFy () - (v0 - kCy) / kFy), 0.01);
  EXPECT_GT (flaw.max_error_mm, 20.0); // centimetres at the image border at 1 m

  // With the lens's distortion as well (reported in docs/camera_models.md).
  const ModelErrors flaw_d = measure (ir, kDistortion), fov_fixed_d = measure (rgb, kDistortion);
  const ModelErrors pinhole_d = measure (PinholeModel (kFx, kFy, kCx, kCy, kDistortion), kDistortion);
  EXPECT_GT (fov_fixed_d.max_error_mm, fov_fixed.max_error_mm);
  EXPECT_LT (pinhole_d.max_error_mm, 1e-6);

  std::cout << "calibrated camera: fx " << kFx << ", fy " << kFy << ", cx " << kCx << ", cy " << kCy
            << ", k1 k2 p1 p2 k3 " << kDistortion.k1 << " " << kDistortion.k2 << " " << kDistortion.p1 << " "
            << kDistortion.p2 << " " << kDistortion.k3 << "\n"
            << "model                  lens         angle error  lateral scale  offset x, y at 1 m  max 3D error at 1 m\n";
  const std::pair<const char *, ModelErrors> rows[] = {
      {"OpenNI, IR FOV (flaw)  no distortion", flaw},     {"OpenNI, RGB FOV        no distortion", fov_fixed},
      {"OpenNI, IR FOV (flaw)  distortion   ", flaw_d},   {"OpenNI, RGB FOV        distortion   ", fov_fixed_d},
      {"PinholeModel           distortion   ", pinhole_d}};
  for (const auto &[name, e] : rows)
    std::printf ("%s %+8.3f deg  %+9.3f %%  %+7.2f, %+6.2f mm  %10.2f mm\n", name, e.angle_error_deg,
                 100 * e.scale_error, e.offset_x_mm, e.offset_y_mm, e.max_error_mm);
}

TEST (PinholeModel, FromCameraInfoAndBadIntrinsics)
{
  pcl::texlet::CameraInfo info;
  info.width = 640;
  info.height = 480;
  const double K[9] = {kFx, 0, kCx, 0, kFy, kCy, 0, 0, 1};
  std::copy (K, K + 9, info.K);
  info.D = {kDistortion.k1, kDistortion.k2, kDistortion.p1, kDistortion.p2, kDistortion.k3};
  const PinholeModel m = PinholeModel::fromCameraInfo (info);
  EXPECT_EQ (m.fy (), kFy);
  EXPECT_EQ (m.distortion ().k3, kDistortion.k3);
  info.distortion_model = "rational_polynomial";
  info.D = {0.1, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_THROW (PinholeModel::fromCameraInfo (info), pcl::BadArgumentException);
  info.D.assign (8, 0.0);
  EXPECT_FALSE (PinholeModel::fromCameraInfo (info).hasDistortion ());
  EXPECT_THROW (PinholeModel (-1, 500, 320, 240), pcl::BadArgumentException);
  EXPECT_THROW (PinholeModel (500, 500, 320, 240, {std::nan (""), 0, 0, 0, 0}), pcl::BadArgumentException);
}
