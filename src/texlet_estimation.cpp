/*
 * Explicit instantiations of TexletEstimation and computeTexlet for PCL's depth-camera point
 * types. Other point types: define PCL_NO_PRECOMPILE before including texlet_estimation.h.
 */
#include <pcl_texlet/impl/texlet_estimation.hpp>
#include <pcl_texlet/texlet_estimation.h>

#include <pcl/impl/instantiate.hpp>
#include <pcl/point_types.h>

// The texlet kernel is compiled twice, for x86-64-v3 (AVX2, FMA) and for the baseline, and the
// loader picks the one the processor runs (GCC's target_clones, an ifunc; flatten inlines the
// kernels into each, which would otherwise be called in their baseline build): the Monte Carlo
// draws and moments are SIMD loops that gain twice from the wider registers. The library is
// built with -ffp-contract=off, so both give the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define PCL_TEXLET_CPU_CLONES __attribute__ ((flatten, target_clones ("arch=x86-64-v3", "default")))
#else
#define PCL_TEXLET_CPU_CLONES
#endif

PCL_TEXLET_CPU_CLONES void
pcl::texlet::detail::computeTexletKernel (const kernels::Neighbourhood<double> &nb,
                                          const kernels::TexletSettings<double> &settings, std::uint32_t texlet,
                                          unsigned char *mask, double *work, kernels::TexletResult<double> &out)
{
  kernels::computeTexlet (nb, settings, texlet, mask, work, out);
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
