/*
 * pcl_texlet GPU tests: a synthetic 16-bit depth frame with closed-form geometry, for the GPU tests
 * and pcl_texlet_gpu_bench on machines without PCL (the simulator needs PCL).
 *
 * A tilted wall and a sphere in front of it, seen by a pinhole camera; depth noise drawn from
 * the paper's noise model with Philox (keyed by pixel), quantised to millimetres, plus a
 * rectangle without readings and scattered dropouts.
 */
#pragma once

#include <pcl_texlet/gpu/frame_texlet.h>
#include <pcl_texlet/kernels/philox_rng.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace pcl_texlet_test
{

struct SyntheticFrame
{
  using DeviceCamera = pcl::texlet::gpu::DeviceCamera;

  int width = 640, height = 480;
  DeviceCamera camera = DeviceCamera::pinhole (580.0, 580.0, 319.5, 239.5);
  double wall_normal[3] = {0.25, -0.15, -1.0}; ///< towards the camera (normalised on use)
  double wall_distance = 1.5;                   ///< metres from the camera centre along the optical axis
  double sphere_centre[3] = {-0.15, 0.05, 1.1}, sphere_radius = 0.15; ///< metres
  bool noise = true;                            ///< depth noise from the paper's model
  double dropout = 0.01;                        ///< fraction of pixels without a reading
  std::uint32_t seed = 7;

  /** \brief The wall's unit normal (facing the camera) and offset d in n . p = d. */
  void
  wall (double n[3], double &d) const
  {
    const double l = std::sqrt (wall_normal[0] * wall_normal[0] + wall_normal[1] * wall_normal[1] +
                                wall_normal[2] * wall_normal[2]);
    for (int i = 0; i < 3; ++i)
      n[i] = wall_normal[i] / l;
    d = n[2] * wall_distance; // the wall passes through (0, 0, wall_distance)
  }

  /** \brief Whether a point (metres) lies on the sphere (within \a tol). */
  bool
  onSphere (const double p[3], double tol) const
  {
    const double dx = p[0] - sphere_centre[0], dy = p[1] - sphere_centre[1], dz = p[2] - sphere_centre[2];
    return std::fabs (std::sqrt (dx * dx + dy * dy + dz * dz) - sphere_radius) < tol;
  }

  /** \brief Depth image in millimetres, row-major; 0 where there is no reading. */
  std::vector<std::uint16_t>
  render () const
  {
    std::vector<std::uint16_t> depth (static_cast<std::size_t> (width) * height, 0);
    double n[3], d;
    wall (n, d);
    const pcl::texlet::gpu::DeviceNoise model;
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u)
      {
        const std::uint32_t pixel = static_cast<std::uint32_t> (v * width + u);
        if (u > 40 && u < 90 && v > 300 && v < 400)
          continue; // a region without readings (a black or too-oblique surface)
        const auto w = pcl::texlet::kernels::philoxWords (seed, pixel, 0u, 0u, pcl::texlet::kernels::RandomStream::SensorNoise);
        if (pcl::texlet::kernels::uniformFloat (w.v[0]) < dropout)
          continue;
        double rx, ry;
        camera.pixelToRay (u, v, rx, ry);
        // Ray (rx, ry, 1) z: the wall, then the sphere if it is hit in front of the wall.
        const double denom = n[0] * rx + n[1] * ry + n[2];
        double z = denom != 0 ? d / denom : -1;
        const double a = rx * rx + ry * ry + 1;
        const double b = -2 * (rx * sphere_centre[0] + ry * sphere_centre[1] + sphere_centre[2]);
        const double c = sphere_centre[0] * sphere_centre[0] + sphere_centre[1] * sphere_centre[1] +
                         sphere_centre[2] * sphere_centre[2] - sphere_radius * sphere_radius;
        const double disc = b * b - 4 * a * c;
        if (disc >= 0)
        {
          const double zs = (-b - std::sqrt (disc)) / (2 * a);
          if (zs > 0 && (z <= 0 || zs < z))
            z = zs;
        }
        if (!(z > 0))
          continue;
        double mm = z * 1000.0;
        if (noise)
        {
          const double sigma = model.sigmaMm (camera.principalPointDistance (u, v), mm);
          const float g = r123::boxmuller (w.v[1], w.v[2]).x;
          mm += sigma * g;
        }
        const long q = std::lround (mm);
        depth[pixel] = q > 0 && q < 65535 ? static_cast<std::uint16_t> (q) : 0;
      }
    return depth;
  }
};

} // namespace pcl_texlet_test
