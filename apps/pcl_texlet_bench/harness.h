/*
 * pcl_texlet_bench: timing harness. Methods run interleaved, one call each per repetition
 * with the starting method rotated, so a busy machine slows them all alike; warm-up runs are
 * not counted; each method's times are summarised by median, quartiles and extremes, and its
 * ratio to a reference by the median of the per-repetition ratios.
 *
 * Both wall-clock and process CPU time are taken. On an idle machine the wall time is what a
 * user waits. On a shared one it is not: a run of a few ms can finish inside one time slice
 * while a long run always shares the cores, so wall ratios drift against long methods. CPU
 * time (all threads of the process, CLOCK_PROCESS_CPUTIME_ID) counts only the cycles the
 * method ran and stays a fair ratio between methods with the same thread count.
 */
#pragma once

#include "methods.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <time.h>

namespace pcl_texlet_bench
{

/** \brief Median, quartiles and extremes of a sample. */
struct Spread
{
  double median = NAN, q1 = NAN, q3 = NAN, min = NAN, max = NAN;
};

inline double
quantile (std::vector<double> v, double q)
{
  v.erase (std::remove_if (v.begin (), v.end (), [] (double x) { return !std::isfinite (x); }), v.end ());
  if (v.empty ())
    return NAN;
  std::sort (v.begin (), v.end ());
  const double pos = q * (v.size () - 1);
  const std::size_t lo = static_cast<std::size_t> (std::floor (pos));
  const std::size_t hi = std::min (lo + 1, v.size () - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

inline Spread
spread (const std::vector<double> &v)
{
  Spread s;
  s.median = quantile (v, 0.5);
  s.q1 = quantile (v, 0.25);
  s.q3 = quantile (v, 0.75);
  s.min = quantile (v, 0.0);
  s.max = quantile (v, 1.0);
  return s;
}

/** \brief Times of one method, milliseconds, and its per-repetition ratios to the reference. */
struct Timing
{
  std::vector<double> ms;        ///< wall clock
  std::vector<double> ratio;     ///< wall clock / the reference's, per repetition
  std::vector<double> cpu_ms;    ///< process CPU time, all threads
  std::vector<double> cpu_ratio; ///< CPU time / the reference's, per repetition
};

/** \brief CPU time of the whole process (every thread), milliseconds. */
inline double
processCpuMs ()
{
  timespec ts;
  clock_gettime (CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * ts.tv_sec + 1e-6 * ts.tv_nsec;
}

/** \brief Runs every runner \a warmup + \a repetitions times, interleaved.
  * \param reference index of the runner the ratios are taken to (-1: none)
  * \param progress called after each repetition with (done, total)
  */
inline std::vector<Timing>
timeInterleaved (const std::vector<MethodRunner *> &runners, int reference, int warmup, int repetitions,
                 const std::function<void (int, int)> &progress)
{
  const int m = static_cast<int> (runners.size ());
  std::vector<Timing> t (m);
  std::vector<double> now (m), cpu (m);
  for (int rep = 0; rep < warmup + repetitions; ++rep)
  {
    for (int k = 0; k < m; ++k)
    {
      const int i = (k + rep) % m; // rotate who goes first
      const double c0 = processCpuMs ();
      const auto t0 = std::chrono::steady_clock::now ();
      runners[i]->run ();
      now[i] = std::chrono::duration<double, std::milli> (std::chrono::steady_clock::now () - t0).count ();
      cpu[i] = processCpuMs () - c0;
    }
    if (rep >= warmup)
      for (int i = 0; i < m; ++i)
      {
        t[i].ms.push_back (now[i]);
        t[i].cpu_ms.push_back (cpu[i]);
        if (reference >= 0)
        {
          t[i].ratio.push_back (now[i] / now[reference]);
          t[i].cpu_ratio.push_back (cpu[i] / cpu[reference]);
        }
      }
    if (progress)
      progress (rep + 1, warmup + repetitions);
  }
  return t;
}

/** \brief Least-squares line y = a + b x and its coefficient of determination. */
struct LineFit
{
  double intercept = NAN, slope = NAN, r2 = NAN;
};

inline LineFit
fitLine (const std::vector<double> &x, const std::vector<double> &y)
{
  LineFit f;
  const std::size_t n = x.size ();
  if (n < 2)
    return f;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    mx += x[i] / n;
    my += y[i] / n;
  }
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  f.r2 = syy > 0 ? sxy * sxy / (sxx * syy) : 1.0;
  return f;
}

} // namespace pcl_texlet_bench
