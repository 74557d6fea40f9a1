/*
 * The texlet kernel compiled for x86-64-v3 (AVX2, FMA; CMake gives this file
 * -march=x86-64-v3). With __AVX2__ defined, the kernels take their intrinsic paths (the
 * block-parallel Philox and Box-Muller of kernels/normal_blocks.h). src/features/texlet_estimation.cpp
 * calls this only on processors that run x86-64-v3. The library is built with
 * -ffp-contract=off, so this gives the same bits as the baseline build.
 */
#include <pcl_texlet/kernels/texlet_kernel.h>

namespace pcl
{
namespace texlet
{
namespace detail
{

/** \brief kernels::computeTexlet in double precision for x86-64-v3; flatten inlines every
  * kernel into it, so none of them is emitted out of line with AVX2 instructions (where the
  * linker could pick it for the baseline build).
  */
__attribute__ ((flatten, visibility ("hidden"))) void
computeTexletKernelX86_64_v3 (const kernels::Neighbourhood<double> &nb, const kernels::TexletSettings<double> &settings,
                              std::uint32_t texlet, unsigned char *mask, double *work,
                              kernels::TexletResult<double> &out)
{
  kernels::computeTexlet (nb, settings, texlet, mask, work, out);
}

} // namespace detail
} // namespace texlet
} // namespace pcl
