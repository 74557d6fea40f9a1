/*
 * pcl_texlet model lab (internal): the disparity lattice the quantisation term and the lab's
 * phase bins use. camera.yaml implies one (1000 f b / disparity_subpixel); a real Kinect's depths
 * sit on one of their own (docs/model_lab.md, "The disparity lattice").
 */
#pragma once

#include <pcl_texlet/lab/recording_measurement.h>

#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

/** A disparity lattice: in a recording's disparity d = 1000 f b / z its levels sit at
  * (k + phase) step, step = 1000 f b / constant_mm.
  */
struct QuantisationLattice
{
  double constant_mm = 0; ///< C of z_k = C / (k + phase); 0: camera.yaml's lattice
  double phase = 0;       ///< in steps

  /** The step (px of disparity) of a recording of f b \a fb_px_m; \a camera_step_px when the
    * lattice is camera.yaml's.
    */
  double
  stepPx (double fb_px_m, double camera_step_px) const
  {
    return constant_mm > 0 ? 1000.0 * fb_px_m / constant_mm : camera_step_px;
  }
};

/** The lattice the recordings' depths sit on when fitDisparityLattice finds one that differs
  * from camera.yaml's by more than 0.5 % (within that its phase would drift by its error times
  * the number of levels, up to 0.4 step at 1e-3: camera.yaml's exact step is better); else
  * camera.yaml's (constant 0, phase 0).
  */
QuantisationLattice
quantisationLattice (const std::vector<RecordingMeasurement::ConstPtr> &recs);

/** The sub-step phase, in [0, 1), of disparity \a disparity_px on the lattice of step \a step_px
  * and phase \a phase.
  */
double
subStepPhase (double disparity_px, double step_px, double phase);

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
