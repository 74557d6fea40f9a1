/*
 * pcl_texlet GPU: Random123's Box-Muller on the host when CUDA's headers are also included.
 *
 * Random123's boxmuller.hpp assumes that sincospi and sincospif exist whenever CUDART_VERSION
 * is defined, which is only true under nvcc. A host compiler that has seen cuda_runtime_api.h
 * (any translation unit using the GPU containers) would find neither, so they are provided
 * here with the fallback Random123 itself uses on plain host builds (sincos of pi x): host
 * code draws the same normals whether or not CUDA's headers came first.
 * Include before <Random123/boxmuller.hpp> (frame_texlet.h does).
 */
#pragma once

#if !defined(__CUDACC__)
#include <cuda_runtime_api.h> // defines CUDART_VERSION: decide here, not by include order
#include <math.h>

#if defined(CUDART_VERSION) && CUDART_VERSION >= 5000
inline void
sincospif (float x, float *s, float *c)
{
  sincosf (3.1415926535897932f * x, s, c);
}

inline void
sincospi (double x, double *s, double *c)
{
  sincos (3.1415926535897932 * x, s, c);
}
#endif
#endif
