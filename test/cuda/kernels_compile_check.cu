/*
 * Compiles the header-only kernels for the device: the CPU path's math must build under nvcc
 * unchanged, so the CUDA backend can run it. Built whenever CUDA is found (CI has nvcc but no
 * GPU, so this is a compile check; the GPU tests of the CUDA backend run it).
 */
#include <pcl_texlet/kernels/hex_grid.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/plumb_bob.h>
#include <pcl_texlet/kernels/texlet_kernel.h>

using namespace pcl::texlet::kernels;

template <typename S>
__global__ void
texletKernelCompileCheck (Neighbourhood<S> nb, TexletSettings<S> st, unsigned char *mask, S *work,
                          TexletResult<S> *out, int *centres)
{
  const HexGrid g = makeHexGrid (640, 480, 6);
  int u, v;
  hexCentre (g, threadIdx.x, u, v);
  double x, y;
  undistortPlumbBob (PlumbBob{0.1, -0.2, 0.001, 0.001, 0.05}, 0.01 * u, 0.01 * v, x, y);
  centres[threadIdx.x] = v * 640 + u + pixelDiscSize (6) + static_cast<int> (x + y);
  computeTexlet (nb, st, threadIdx.x, mask, work, out[threadIdx.x]);
}

template __global__ void texletKernelCompileCheck<float> (Neighbourhood<float>, TexletSettings<float>, unsigned char *,
                                                          float *, TexletResult<float> *, int *);
template __global__ void texletKernelCompileCheck<double> (Neighbourhood<double>, TexletSettings<double>,
                                                           unsigned char *, double *, TexletResult<double> *, int *);
