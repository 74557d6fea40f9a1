/*
 * pcl_texlet_bench: how figures are printed and written to the JSON, shared by the studies.
 */
#pragma once

#include "harness.h"
#include "methods.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace pcl_texlet_bench
{

inline nlohmann::json
spreadJson (const Spread &s)
{
  return {{"median", s.median}, {"q1", s.q1}, {"q3", s.q3}, {"min", s.min}, {"max", s.max}};
}

/** NaN is not JSON: it becomes null. */
inline nlohmann::json
num (double x)
{
  return std::isfinite (x) ? nlohmann::json (x) : nlohmann::json (nullptr);
}

/** \brief \a x with \a precision decimals for the tables; "-" when it is not finite. */
inline std::string
fmt (double x, int precision = 1)
{
  if (!std::isfinite (x))
    return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision (precision) << x;
  return s.str ();
}

/** \brief The centres where a method made a normal. */
inline std::size_t
countFinite (const MethodOutput &out)
{
  std::size_t n = 0;
  for (const auto &v : out.normal)
    n += v.allFinite () ? 1 : 0;
  return n;
}

/** \brief The mean of the finite values of \a v; NaN when there are none. */
inline double
meanFinite (const std::vector<float> &v)
{
  double s = 0;
  std::size_t n = 0;
  for (const float x : v)
    if (std::isfinite (x))
    {
      s += x;
      ++n;
    }
  return n ? s / n : NAN;
}

/** \brief The mean of \a e; NaN when it is empty. */
inline double
meanOf (const std::vector<double> &e)
{
  double m = 0;
  for (const double x : e)
    m += x / e.size ();
  return e.empty () ? NAN : m;
}

} // namespace pcl_texlet_bench
