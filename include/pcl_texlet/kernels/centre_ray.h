/*
 * pcl_texlet kernels: the texlet's centre P where the centre pixel's viewing ray meets the
 * fitted plane (TexletCentre::CentreRay).
 *
 * The inliers' mean moves sideways, by a good part of the disc, with which disc pixels are valid
 * and inliers in a frame, which no propagation of depth noise holds. The ray's intersection
 * moves only with the plane, along a fixed ray, so its covariance is var(t) r r^T, rank 1
 * (docs/texlet_covariances.md).
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/plane_fit.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief The texlet's centre and what its propagation needs. With on = false, P is the
  * inliers' mean (the fit's P).
  */
template <typename S>
struct TexletCentrePoint
{
  bool on = false;            ///< P is on the centre ray
  Vec3<S> P;                  ///< the texlet's centre
  Vec3<S> ray;                ///< the centre ray (z = 1)
  Vec3<S> mean_offset;        ///< the inliers' mean minus P (in the plane)
  S inv_n_ray = S (0);        ///< 1 / (N_fit . ray)
  Vec3<S> N0, t1, t2;         ///< the texlet's normal and tangents: a sample's a1, a2 refer to them
};

/** \brief Planes seen this close to edge-on (|cos| of the angle between the ray and the plane's
  * normal below it) keep the inliers' mean: the intersection runs off along the ray.
  */
template <typename S> PCL_TEXLET_HD S
minRayCosine () { return S (0.05); }

/** \brief The centre of the texlet fitted as \a fit (normal \a N, tangents \a t1, \a t2) by the
  * settings' \a definition: on nb's centre ray for CentreRay (PCA and SVD fits, where the ray is
  * known and not edge-on), else the fit's P. Normal averaging's P is the centre pixel's point
  * already, and its own propagation holds it.
  */
template <typename S> PCL_TEXLET_HD TexletCentrePoint<S>
texletCentre (const Neighbourhood<S> &nb, const PlaneFit<S> &fit, const Vec3<S> &N, const Vec3<S> &t1,
              const Vec3<S> &t2, TexletCentre definition, PlaneFitMethod method)
{
  TexletCentrePoint<S> c;
  c.P = fit.P;
  c.ray = nb.centre_ray;
  c.N0 = N;
  c.t1 = t1;
  c.t2 = t2;
  if (definition != TexletCentre::CentreRay || method == PlaneFitMethod::Averaging || !nb.has_centre_ray)
    return c;
  const S n_ray = dot (fit.N, nb.centre_ray);
  if (!(std::abs (n_ray) >= minRayCosine<S> () * norm (nb.centre_ray)))
    return c;
  c.inv_n_ray = S (1) / n_ray;
  c.P = (dot (fit.N, fit.P) * c.inv_n_ray) * nb.centre_ray;
  c.mean_offset = fit.P - c.P;
  c.on = true;
  return c;
}

/** \brief A perturbed fit's centre minus \a c.P, from its inliers' mean minus the measured mean
  * (\a dM) and its normal's components \a a1, \a a2 along c.t1, c.t2: \a dM itself when the
  * centre is the mean, else the step along the ray to the perturbed plane.
  */
template <typename S> PCL_TEXLET_HD Vec3<S>
centreShift (const TexletCentrePoint<S> &c, const Vec3<S> &dM, S a1, S a2)
{
  if (!c.on)
    return dM;
  const S a = a1 * a1 + a2 * a2;
  const Vec3<S> n = (a < S (1) ? std::sqrt (S (1) - a) : S (0)) * c.N0 + a1 * c.t1 + a2 * c.t2;
  const S n_ray = dot (n, c.ray);
  if (n_ray == S (0))
    return dM;
  return (dot (n, c.mean_offset + dM) / n_ray) * c.ray;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
