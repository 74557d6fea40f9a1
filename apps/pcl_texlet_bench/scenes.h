/*
 * pcl_texlet_bench: simulated scenes with ground-truth normals, and the paper's Fig. 8 patch.
 */
#pragma once

#include "methods.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pcl_texlet_bench
{

/** \brief A simulated depth frame as an organised cloud, with what the sensor really saw. */
struct SimulatedScene
{
  std::string name;
  Cloud::Ptr cloud;
  pcl::texlet::CameraModel::ConstPtr camera; ///< the simulated sensor's pinhole
  std::vector<Eigen::Vector3f> truth_normal; ///< per pixel, facing the camera; NaN where no surface
  std::vector<float> truth_depth;            ///< per pixel, metres; 0 where no surface
};

/** \brief Names simulateScene knows. */
const std::vector<std::string> &
sceneNames ();

/** \brief One frame of the library's KinectSimulator with the paper's noise (Eq. 4, in
  * disparity, depth in whole mm) and projector shadows, no other effect:
  * - "plane": a wall 1.2 m away tilted 20 degrees about x and 30 about y (planeSetup);
  * - "sphere": a ball of radius 0.25 m, 1.1 m away, in front of a wall at 1.6 m;
  * - "box": the paper's 128 x 112 x 240 mm box on a table, 1.2 m away, 45 degrees above it
  *   (boxSetup): planes meeting at edges and a depth step to the table.
  * \throws pcl::BadArgumentException for an unknown name or a bad size.
  */
SimulatedScene
simulateScene (const std::string &name, int width, int height, std::uint32_t seed);

/** \brief Pixels at a depth edge or crease of the true geometry: a surface pixel whose
  * 4-neighbour has no surface or no reading, lies more than 2 cm deeper or shallower, or has a
  * normal more than 30 degrees away.
  */
std::vector<std::uint8_t>
edgePixels (const SimulatedScene &scene);

/** \brief Centres whose pixel disc of \a radius holds an edge pixel. */
std::vector<std::uint8_t>
nearEdge (const std::vector<std::uint8_t> &edges, int width, int height, const pcl::Indices &centres, int radius);

/** \brief A plane through (0, 0, distance) tilted \a tilt_deg about the image's x axis, seen
  * by a pinhole (f = 525 px, centred), with Gaussian depth noise of \a sigma_m added along each
  * ray (the Kinect's noise moves a point along its ray). Returns the cloud; \a normal is the
  * plane's unit normal facing the camera.
  */
Cloud::Ptr
noisyPlane (int width, int height, double distance_m, double tilt_deg, double sigma_m, std::uint32_t seed,
            Eigen::Vector3f &normal);

} // namespace pcl_texlet_bench
