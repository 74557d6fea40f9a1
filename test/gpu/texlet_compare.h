/*
 * pcl_texlet GPU tests: comparing two texlet sets of the same frame, texlet by texlet.
 *
 * Normals are compared by angle, covariances relative to the larger diagonal entry of the
 * reference (off-diagonal terms near zero have no meaningful relative error of their own).
 * Texlets whose RANSAC support differs (an inlier decision flipped by rounding at the
 * threshold) are counted, not compared.
 */
#pragma once

#include <pcl_texlet/gpu/frame_texlet.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <ostream>
#include <vector>

namespace pcl_texlet_test
{

struct TexletComparison
{
  std::size_t compared = 0;          ///< texlets made by both with equal support
  std::size_t made_mismatch = 0;     ///< made by one side only
  std::size_t support_mismatch = 0;  ///< made by both, different support
  std::size_t pixel_mismatch = 0;    ///< different centre pixel (must be 0)
  double max_normal_rad = 0;         ///< largest angle between normals
  double max_centre_m = 0;           ///< largest distance between centres
  double max_cov_p_rel = 0, max_cov_n_rel = 0; ///< largest relative covariance differences
  std::size_t rgba_mismatch = 0;
  std::size_t normal_over = 0, cov_over = 0; ///< texlets beyond the issue's tolerances (1e-4 rad, 1e-3)
};

inline double
relativeDifference (const float *a, const float *b, int n, const int *diag, int ndiag)
{
  double scale = 0;
  for (int i = 0; i < ndiag; ++i)
    scale = std::max (scale, std::fabs (static_cast<double> (b[diag[i]])));
  double worst = 0;
  for (int i = 0; i < n; ++i)
  {
    if (std::isnan (a[i]) != std::isnan (b[i]))
      return INFINITY;
    if (std::isnan (b[i]))
      continue;
    const double d = std::fabs (static_cast<double> (a[i]) - b[i]);
    worst = std::max (worst, scale > 0 ? d / scale : d);
  }
  return worst;
}

/** \brief Compares \a a (under test) with \a ref, texlet by texlet (same grid, same order). */
template <typename TexletA, typename TexletB> TexletComparison
compareTexlets (const std::vector<TexletA> &a, const std::vector<TexletB> &ref)
{
  TexletComparison c;
  const std::size_t n = std::min (a.size (), ref.size ());
  for (std::size_t i = 0; i < n; ++i)
  {
    const TexletA &x = a[i];
    const TexletB &y = ref[i];
    if (x.pixel_index != y.pixel_index)
      ++c.pixel_mismatch;
    const bool mx = x.support > 0, my = y.support > 0;
    if (mx != my)
    {
      ++c.made_mismatch;
      continue;
    }
    if (!mx)
      continue;
    if (x.support != y.support)
    {
      ++c.support_mismatch;
      continue;
    }
    ++c.compared;
    const double dot = static_cast<double> (x.normal_x) * y.normal_x + static_cast<double> (x.normal_y) * y.normal_y +
                       static_cast<double> (x.normal_z) * y.normal_z;
    // atan2 of |cross| and dot is accurate for tiny angles, unlike acos.
    const double cx = static_cast<double> (x.normal_y) * y.normal_z - static_cast<double> (x.normal_z) * y.normal_y;
    const double cy = static_cast<double> (x.normal_z) * y.normal_x - static_cast<double> (x.normal_x) * y.normal_z;
    const double cz = static_cast<double> (x.normal_x) * y.normal_y - static_cast<double> (x.normal_y) * y.normal_x;
    const double angle = std::atan2 (std::sqrt (cx * cx + cy * cy + cz * cz), dot);
    c.max_normal_rad = std::max (c.max_normal_rad, angle);
    const double dx = x.x - y.x, dy = x.y - y.y, dz = x.z - y.z;
    c.max_centre_m = std::max (c.max_centre_m, std::sqrt (dx * dx + dy * dy + dz * dz));
    const float pa[6] = {x.cov_p_xx, x.cov_p_xy, x.cov_p_xz, x.cov_p_yy, x.cov_p_yz, x.cov_p_zz};
    const float pb[6] = {y.cov_p_xx, y.cov_p_xy, y.cov_p_xz, y.cov_p_yy, y.cov_p_yz, y.cov_p_zz};
    const float na[3] = {x.cov_n_11, x.cov_n_12, x.cov_n_22};
    const float nb[3] = {y.cov_n_11, y.cov_n_12, y.cov_n_22};
    const int dp[3] = {0, 3, 5}, dn[2] = {0, 2};
    const double rp = relativeDifference (pa, pb, 6, dp, 3), rn = relativeDifference (na, nb, 3, dn, 2);
    c.max_cov_p_rel = std::max (c.max_cov_p_rel, rp);
    c.max_cov_n_rel = std::max (c.max_cov_n_rel, rn);
    c.normal_over += angle > 1e-4 ? 1 : 0;
    c.cov_over += (rp > 1e-3 || rn > 1e-3) ? 1 : 0;
    if (x.rgba != y.rgba)
      ++c.rgba_mismatch;
  }
  c.made_mismatch += std::max (a.size (), ref.size ()) - n;
  return c;
}

inline std::ostream &
operator<< (std::ostream &os, const TexletComparison &c)
{
  return os << c.compared << " compared, " << c.made_mismatch << " made by one side only, " << c.support_mismatch
            << " with different support, max normal angle " << c.max_normal_rad << " rad, max centre distance "
            << c.max_centre_m << " m, max relative Sigma_P difference " << c.max_cov_p_rel << ", Sigma_N "
            << c.max_cov_n_rel << ", " << c.rgba_mismatch << " colours differ, " << c.normal_over
            << " normals beyond 1e-4 rad, " << c.cov_over << " covariances beyond 1e-3";
}

} // namespace pcl_texlet_test
