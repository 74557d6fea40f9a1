/*
 * pcl_texlet tests: where a wall of the model lab's test sets stands before the sensor.
 */
#pragma once

namespace pcl_texlet_test
{

/** \brief A plane wall: its distance along the optical axis, its tilts, and the projectors
  * lighting it.
  */
struct WallPose
{
  double distance_m = 1.5;
  double tilt_x_deg = 0.0;
  double tilt_y_deg = 0.0;
  int projectors = 1;
};

} // namespace pcl_texlet_test
