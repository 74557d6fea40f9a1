/*
 * pcl_texlet common: an OpenMP loop whose body may throw. No exception may leave an OpenMP
 * region (the program would terminate), so each iteration's is caught and the first one is
 * rethrown once the loop is done.
 */
#pragma once

#include <exception>

namespace pcl
{
namespace texlet
{

/** \brief Runs \a body (i) for every i in [0, n), on \a threads OpenMP threads when \a parallel
  * (dynamic schedule), else serially on the calling thread. Every iteration runs, also after one
  * has thrown; the first exception caught is rethrown after the loop.
  * Without OpenMP the loop is serial.
  */
template <typename Body> void
parallelFor (int n, int threads, bool parallel, Body body)
{
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic) num_threads(threads) if (parallel)
  for (int i = 0; i < n; ++i)
  {
    try
    {
      body (i);
    }
    catch (...)
    {
#pragma omp critical(pcl_texlet_parallel_for_error)
      if (!error)
        error = std::current_exception ();
    }
  }
  if (error)
    std::rethrow_exception (error);
}

} // namespace texlet
} // namespace pcl
