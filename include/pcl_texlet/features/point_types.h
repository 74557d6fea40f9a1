/*
 * pcl_texlet: the texlet point type, pcl::Texlet (its fields: the README, "What a texlet is").
 */
#pragma once

#include <pcl/point_types.h>
#include <pcl/register_point_struct.h>

#include <pcl_texlet/kernels/tangent_frame.h>

#include <Eigen/Core>

#include <cstdint>
#include <ostream>

namespace pcl
{

struct EIGEN_ALIGN16 _Texlet
{
  PCL_ADD_POINT4D;  // centre P, metres
  PCL_ADD_NORMAL4D; // unit normal N, facing the viewpoint
  union
  {
    struct
    {
      PCL_ADD_UNION_RGB; // mean colour of the inliers (0 when the input has none)
      float curvature;   // l0 / (l0 + l1 + l2), PCL's surface variation
    };
    float data_c[4];
  };
  float radius;            // radius of the patch, metres: sqrt(2 (l1 + l2))
  std::uint32_t support;   // RANSAC inliers the texlet was fitted to
  float cov_p_xx, cov_p_xy, cov_p_xz, cov_p_yy, cov_p_yz, cov_p_zz; // Sigma_P, m^2
  float cov_n_11, cov_n_12, cov_n_22; // Sigma_N in the tangent frame (t1, t2) of N, rad^2
  std::uint32_t pixel_index; // index of the centre pixel in the organised input
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

/** \brief A texlet: a local surface patch with centre P, normal N, their covariances, size,
  * support and mean colour (Olesen et al., "Real-time extraction of surface patches with
  * associated uncertainties by means of Kinect cameras").
  *
  * Sigma_N is the 2x2 covariance of N's deviation along the tangents t1, t2 returned by
  * tangentFrame(): a fixed function of N (Duff et al. 2017) for which (t1, t2, N) is
  * right-handed and, for a surface facing the camera, t1 points right and t2 up in the image.
  * A texlet that could not be computed has NaN coordinates and support 0.
  */
struct Texlet : public _Texlet
{
  inline Texlet ()
  {
    x = y = z = 0.0f;
    data[3] = 1.0f;
    normal_x = normal_y = normal_z = data_n[3] = 0.0f;
    rgba = 0;
    curvature = 0.0f;
    data_c[2] = data_c[3] = 0.0f; // padding: zeroed so that equal texlets are equal bytes
    radius = 0.0f;
    support = 0;
    cov_p_xx = cov_p_xy = cov_p_xz = cov_p_yy = cov_p_yz = cov_p_zz = 0.0f;
    cov_n_11 = cov_n_12 = cov_n_22 = 0.0f;
    pixel_index = 0;
  }

  inline Texlet (const _Texlet &p) : _Texlet (p) {}

  /** \brief Sigma_P as a matrix (m^2). */
  inline Eigen::Matrix3f
  covarianceP () const
  {
    Eigen::Matrix3f c;
    c << cov_p_xx, cov_p_xy, cov_p_xz, cov_p_xy, cov_p_yy, cov_p_yz, cov_p_xz, cov_p_yz, cov_p_zz;
    return c;
  }

  /** \brief Sets Sigma_P from a symmetric matrix (m^2); its upper triangle is kept. */
  inline void
  setCovarianceP (const Eigen::Matrix3f &c)
  {
    cov_p_xx = c (0, 0);
    cov_p_xy = c (0, 1);
    cov_p_xz = c (0, 2);
    cov_p_yy = c (1, 1);
    cov_p_yz = c (1, 2);
    cov_p_zz = c (2, 2);
  }

  /** \brief Sigma_N as a matrix (rad^2) in the frame of tangentFrame(). */
  inline Eigen::Matrix2f
  covarianceN () const
  {
    Eigen::Matrix2f c;
    c << cov_n_11, cov_n_12, cov_n_12, cov_n_22;
    return c;
  }

  /** \brief Sets Sigma_N (rad^2, in the frame of tangentFrame()); the off-diagonal is the mean
    * of the two, so a product that rounds asymmetrically stays a covariance.
    */
  inline void
  setCovarianceN (const Eigen::Matrix2f &c)
  {
    cov_n_11 = c (0, 0);
    cov_n_12 = 0.5f * (c (0, 1) + c (1, 0));
    cov_n_22 = c (1, 1);
  }

  /** \brief The tangents (t1, t2) in which Sigma_N is expressed, as the columns of a 3x2 matrix. */
  inline Eigen::Matrix<float, 3, 2>
  tangentFrame () const
  {
    texlet::kernels::Vec3<float> t1, t2;
    texlet::kernels::tangentFrame (texlet::kernels::Vec3<float>{normal_x, normal_y, normal_z}, t1, t2);
    Eigen::Matrix<float, 3, 2> t;
    t << t1.x, t2.x, t1.y, t2.y, t1.z, t2.z;
    return t;
  }

  PCL_MAKE_ALIGNED_OPERATOR_NEW
};

inline std::ostream &
operator<< (std::ostream &os, const Texlet &t)
{
  os << "(" << t.x << "," << t.y << "," << t.z << " - " << t.normal_x << "," << t.normal_y << ","
     << t.normal_z << " - " << static_cast<int> (t.r) << "," << static_cast<int> (t.g) << ","
     << static_cast<int> (t.b) << " - r " << t.radius << " support " << t.support << " pixel "
     << t.pixel_index << ")";
  return os;
}

} // namespace pcl

POINT_CLOUD_REGISTER_POINT_STRUCT (pcl::_Texlet,
    (float, x, x)
    (float, y, y)
    (float, z, z)
    (float, normal_x, normal_x)
    (float, normal_y, normal_y)
    (float, normal_z, normal_z)
    (float, rgb, rgb)
    (float, curvature, curvature)
    (float, radius, radius)
    (std::uint32_t, support, support)
    (float, cov_p_xx, cov_p_xx)
    (float, cov_p_xy, cov_p_xy)
    (float, cov_p_xz, cov_p_xz)
    (float, cov_p_yy, cov_p_yy)
    (float, cov_p_yz, cov_p_yz)
    (float, cov_p_zz, cov_p_zz)
    (float, cov_n_11, cov_n_11)
    (float, cov_n_12, cov_n_12)
    (float, cov_n_22, cov_n_22)
    (std::uint32_t, pixel_index, pixel_index)
)
POINT_CLOUD_REGISTER_POINT_WRAPPER (pcl::Texlet, pcl::_Texlet)
