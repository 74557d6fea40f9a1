/*
 * pcl_texlet kernels: shared compile-time settings.
 *
 * Everything under kernels/ is header-only math with no PCL types, so the CPU path, the CUDA
 * backend and the tests run the very same code. Functions are marked PCL_TEXLET_HD so nvcc
 * compiles them for host and device alike.
 */
#pragma once

#if defined(__CUDACC__)
#define PCL_TEXLET_HD __host__ __device__ __forceinline__
#else
#define PCL_TEXLET_HD inline
#endif

#include <cstdint>

namespace pcl
{
namespace texlet
{

/** \brief How the plane of a texlet is fitted to its inlier points. */
enum class PlaneFitMethod : int
{
  PCA = 0,      ///< closed-form 3x3 symmetric eigen solve of the inliers' covariance (paper, Sect. 3.1)
  SVD = 1,      ///< one-sided Jacobi SVD of the centred inlier matrix (the paper's reference)
  Averaging = 2 ///< normal averaging over the six hexagonal neighbours (paper Eq. 5)
};

/** \brief How the uncertainty of P and N is propagated from the per-point depth noise. */
enum class UncertaintyMethod : int
{
  None = 0,      ///< no covariances (NaN in the output)
  Analytic = 1,  ///< first-order propagation (mean and eigenvector perturbation)
  MonteCarlo = 2 ///< re-fit with noise drawn from the noise model (paper, Sect. 3.2)
};

/** \brief Which point of the fitted plane is the texlet's centre P (docs/texlet_covariances.md). */
enum class TexletCentre : int
{
  CentreRay = 0, ///< where the centre pixel's viewing ray meets the plane: it does not move with the inlier set
  InlierMean = 1 ///< the inliers' mean (the paper's definition): it moves with which disc pixels are inliers
};

} // namespace texlet
} // namespace pcl
