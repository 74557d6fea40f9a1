/*
 * pcl_texlet kernels: closed-form terms of the depth noise model.
 *
 * Sigma is in millimetres of depth; r is the distance in pixels from the principal point and
 * d the depth in millimetres, as in the paper's Eq. 4.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief Coefficients of f(r, d) = p00 + p10 r + p01 d + p20 r^2 + p11 r d + p02 d^2. */
struct PolynomialCoefficients
{
  double p00, p10, p01, p20, p11, p02;
};

/** \brief The paper's fit (Eq. 4): 700-1750 mm, wall tilts up to 30 degrees. */
PCL_TEXLET_HD PolynomialCoefficients
paperPolynomial ()
{
  return {2.344, -1.202e-2, -2.734e-3, 1.818e-5, 6.516e-6, 1.233e-6};
}

/** \brief f(r, d) in mm (may be <= 0 far outside the fitted range: callers clamp). */
PCL_TEXLET_HD double
evaluatePolynomial (const PolynomialCoefficients &c, double r_px, double d_mm)
{
  return c.p00 + c.p10 * r_px + c.p01 * d_mm + c.p20 * r_px * r_px + c.p11 * r_px * d_mm + c.p02 * d_mm * d_mm;
}

/** \brief The depth SD in mm of a model made of the polynomial alone, with the operations of
  * NoiseModel::moments () for it (variance max (f, 0)^2, its root, never below \a floor_mm),
  * so the same bits without a virtual call. NaN unless \a d_mm is positive and finite.
  */
PCL_TEXLET_HD double
polynomialSigmaMm (const PolynomialCoefficients &c, double r_px, double d_mm, double floor_mm)
{
  if (!(d_mm > 0.0) || !std::isfinite (d_mm))
    return NAN;
  const double f = evaluatePolynomial (c, r_px, d_mm);
  const double s = std::sqrt (f > 0.0 ? f * f : 0.0);
  return s > floor_mm ? s : floor_mm;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
