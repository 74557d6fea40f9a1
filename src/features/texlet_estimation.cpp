/*
 * Explicit instantiations of TexletEstimation and computeTexlet for PCL's depth-camera point
 * types. Other point types: define PCL_NO_PRECOMPILE before including texlet_estimation.h.
 */
#include <pcl_texlet/features/impl/texlet_estimation.hpp>
#include <pcl_texlet/features/texlet_estimation.h>

#include <pcl/impl/instantiate.hpp>
#include <pcl/point_types.h>

// The texlet kernel is compiled twice: here for the baseline, and in
// src/features/texlet_kernel_x86_64_v3.cpp for x86-64-v3 (AVX2, FMA), where the Monte Carlo draws use
// AVX2 intrinsics and the other SIMD loops the wider registers. The first call picks the one
// the processor runs. flatten inlines the kernels into each. The library is built with
// -ffp-contract=off, so both give the same bits.
#if defined(PCL_TEXLET_X86_64_V3_KERNEL)
namespace pcl
{
namespace texlet
{
namespace detail
{
void
computeTexletKernelX86_64_v3 (const kernels::Neighbourhood<double> &nb, const kernels::TexletSettings<double> &settings,
                              std::uint32_t texlet, unsigned char *mask, double *work,
                              kernels::TexletResult<double> &out);
} // namespace detail
} // namespace texlet
} // namespace pcl
#endif

namespace
{

#if defined(__GNUC__)
__attribute__ ((flatten))
#endif
void
computeTexletKernelBaseline (const pcl::texlet::kernels::Neighbourhood<double> &nb,
                             const pcl::texlet::kernels::TexletSettings<double> &settings, std::uint32_t texlet,
                             unsigned char *mask, double *work, pcl::texlet::kernels::TexletResult<double> &out)
{
  pcl::texlet::kernels::computeTexlet (nb, settings, texlet, mask, work, out);
}

using KernelFunction = decltype (&computeTexletKernelBaseline);

KernelFunction
pickKernel ()
{
#if defined(PCL_TEXLET_X86_64_V3_KERNEL)
  __builtin_cpu_init ();
#if defined(__clang__)
  const bool v3 = __builtin_cpu_supports ("avx2") && __builtin_cpu_supports ("fma") &&
                  __builtin_cpu_supports ("bmi") && __builtin_cpu_supports ("bmi2");
#else
  const bool v3 = __builtin_cpu_supports ("x86-64-v3");
#endif
  if (v3)
    return &pcl::texlet::detail::computeTexletKernelX86_64_v3;
#endif
  return &computeTexletKernelBaseline;
}

} // namespace

void
pcl::texlet::detail::computeTexletKernel (const kernels::Neighbourhood<double> &nb,
                                          const kernels::TexletSettings<double> &settings, std::uint32_t texlet,
                                          unsigned char *mask, double *work, kernels::TexletResult<double> &out)
{
  static const KernelFunction kernel = pickKernel ();
  kernel (nb, settings, texlet, mask, work, out);
}

#define PCL_INSTANTIATE_TexletEstimation(T, OutT) template class PCL_EXPORTS pcl::TexletEstimation<T, OutT>;
#define PCL_INSTANTIATE_computeTexlet(T, OutT)                                                                         \
  template PCL_EXPORTS bool pcl::computeTexlet<T, OutT> (const pcl::PointCloud<T> &, pcl::index_t,                   \
                                                         const pcl::texlet::TexletParameters &,                        \
                                                         const pcl::texlet::CameraModel &,                             \
                                                         const pcl::texlet::NoiseModel &, OutT &);

// clang-format off
PCL_INSTANTIATE_PRODUCT (TexletEstimation, ((pcl::PointXYZ)(pcl::PointXYZRGB)(pcl::PointXYZRGBA)(pcl::PointXYZRGBNormal))((pcl::Texlet)))
PCL_INSTANTIATE_PRODUCT (computeTexlet, ((pcl::PointXYZ)(pcl::PointXYZRGB)(pcl::PointXYZRGBA)(pcl::PointXYZRGBNormal))((pcl::Texlet)))
// clang-format on
