#include "effect_size.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{
namespace
{

struct Fall
{
  double fall = 0, share = 0, before = 0, after = 0;
};

/** The fall of the mean square of (pred - meas) from \a b to \a c over the pixels where the
  * prediction moves by at least half its 95th-percentile move, and the RMS before and after.
  */
Fall
fallWhereItShows (const std::vector<float> &b_pred, const std::vector<float> &c_pred, const std::vector<float> &meas)
{
  const std::size_t n = std::min ({b_pred.size (), c_pred.size (), meas.size ()});
  std::vector<float> move;
  move.reserve (n);
  for (std::size_t i = 0; i < n; ++i)
    if (std::isfinite (b_pred[i]) && std::isfinite (c_pred[i]) && std::isfinite (meas[i]))
      move.push_back (std::fabs (c_pred[i] - b_pred[i]));
  Fall out;
  if (move.empty ())
    return out;
  const std::size_t q = static_cast<std::size_t> (0.95 * (move.size () - 1));
  std::nth_element (move.begin (), move.begin () + q, move.end ());
  const double cut = 0.5 * move[q];
  if (!(cut > 0))
    return out;
  double e_b = 0, e_c = 0, count = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!(std::isfinite (b_pred[i]) && std::isfinite (c_pred[i]) && std::isfinite (meas[i])) ||
        std::fabs (c_pred[i] - b_pred[i]) < cut)
      continue;
    e_b += (b_pred[i] - meas[i]) * (b_pred[i] - meas[i]);
    e_c += (c_pred[i] - meas[i]) * (c_pred[i] - meas[i]);
    count += 1;
  }
  out.share = count / move.size ();
  out.before = std::sqrt (e_b / count);
  out.after = std::sqrt (e_c / count);
  out.fall = e_b > 0 ? 1.0 - e_c / e_b : 0.0;
  return out;
}

} // namespace

EffectSize
effectSize (const PixelErrors &base, const PixelErrors &candidate)
{
  EffectSize e;
  const Fall sd = fallWhereItShows (base.sd_pred, candidate.sd_pred, base.sd_meas);
  const Fall bias = fallWhereItShows (base.mean_pred, candidate.mean_pred, base.mean_meas);
  const Fall line = fallWhereItShows (base.line_pred, candidate.line_pred, base.line_meas);
  e.sd_fall = sd.fall, e.sd_share = sd.share, e.sd_before_mm = sd.before, e.sd_after_mm = sd.after;
  e.line_fall = line.fall, e.line_share = line.share, e.line_before_mm = line.before, e.line_after_mm = line.after;
  e.bias_fall = bias.fall, e.bias_share = bias.share, e.bias_before_mm = bias.before, e.bias_after_mm = bias.after;
  return e;
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
