/*
 * pcl_texlet GPU: CUDA runtime errors as exceptions.
 *
 * Every CUDA runtime call of the GPU backend goes through PCL_TEXLET_CUDA_CHECK, so a failure
 * surfaces as a pcl::texlet::gpu::CudaError that names the call, CUDA's message and the error code,
 * instead of a status code nobody reads.
 */
#pragma once

#include <cuda_runtime_api.h>

#include <sstream>
#include <stdexcept>
#include <string>

namespace pcl
{
namespace texlet
{
namespace gpu
{

/** \brief A CUDA runtime call failed. what() names the call, CUDA's message and the code. */
class CudaError : public std::runtime_error
{
public:
  CudaError (cudaError_t code, const std::string &call, const char *file, int line)
    : std::runtime_error (describe (code, call, file, line)), code_ (code)
  {
  }

  /** \brief The CUDA error code. */
  cudaError_t
  code () const { return code_; }

private:
  static std::string
  describe (cudaError_t code, const std::string &call, const char *file, int line)
  {
    std::ostringstream msg;
    msg << call << " failed: " << cudaGetErrorString (code) << " (" << cudaGetErrorName (code) << ") at " << file
        << ":" << line;
    return msg.str ();
  }

  cudaError_t code_;
};

namespace detail
{
/** \brief Throws CudaError unless \a code is cudaSuccess. */
inline void
cudaCheck (cudaError_t code, const char *call, const char *file, int line)
{
  if (code != cudaSuccess)
  {
    cudaGetLastError (); // clear a non-sticky error so that later calls are not blamed for it
    throw CudaError (code, call, file, line);
  }
}
} // namespace detail

} // namespace gpu
} // namespace texlet
} // namespace pcl

/** \brief Runs a CUDA runtime call and throws pcl::texlet::gpu::CudaError naming it if it fails. */
#define PCL_TEXLET_CUDA_CHECK(call) ::pcl::texlet::gpu::detail::cudaCheck ((call), #call, __FILE__, __LINE__)

namespace pcl
{
namespace texlet
{
namespace gpu
{
/** \brief Number of CUDA devices; 0 (not an exception) when there is no device or no driver. */
inline int
cudaDeviceCount ()
{
  int n = 0;
  if (cudaGetDeviceCount (&n) != cudaSuccess)
  {
    cudaGetLastError ();
    return 0;
  }
  return n;
}
} // namespace gpu
} // namespace texlet
} // namespace pcl
