/*
 * pcl_texlet model lab (internal): how far a pixel's measured SD is from its true one by chance
 * alone, measured from the pixel's own samples (docs/model_lab.md section 2).
 */
#pragma once

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** The SDs of a pixel's alternate samples (first, third, ... against second, fourth, ...).
  *
  * Why: an SD from n samples scatters about the true SD by a part that no model removes (16 % of
  * it for 20 Gaussian samples, far more where a pixel flickers between two depth levels). Two
  * disjoint halves scatter independently, so the square of their difference measures that part
  * without a model of the noise's shape; the sample SD's variance goes as 1 / (n - 1).
  */
class SplitSd
{
public:
  /** Adds the next sample (any fixed offset: only differences count). */
  void
  add (double value)
  {
    Half &h = half_[next_];
    h.n += 1, h.s1 += value, h.s2 += value * value;
    next_ ^= 1;
  }

  /** Both halves have an SD (two samples each). */
  bool
  splittable () const
  {
    return half_[0].n >= 2 && half_[1].n >= 2;
  }

  /** The variance of the SD of all the samples about its expectation, from the halves'
    * difference: E (s_a - s_b)^2 = c (1 / (n_a - 1) + 1 / (n_b - 1)) and Var s_n = c / (n - 1).
    * Only where splittable ().
    */
  double
  samplingVarianceOfSd () const
  {
    const double a = half_[0].sd (), b = half_[1].sd ();
    const double n = half_[0].n + half_[1].n;
    const double c = (a - b) * (a - b) / (1.0 / (half_[0].n - 1) + 1.0 / (half_[1].n - 1));
    return c / (n - 1);
  }

private:
  struct Half
  {
    double n = 0, s1 = 0, s2 = 0;
    double
    sd () const
    {
      const double ss = s2 - s1 * s1 / n;
      return ss > 0 ? std::sqrt (ss / (n - 1)) : 0.0;
    }
  };
  Half half_[2];
  int next_ = 0;
};

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
