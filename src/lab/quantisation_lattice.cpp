#include "quantisation_lattice.h"

#include <pcl_texlet/lab/disparity_lattice.h>

#include <cmath>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

QuantisationLattice
quantisationLattice (const std::vector<RecordingMeasurement::ConstPtr> &recs)
{
  QuantisationLattice out;
  if (recs.empty ())
    return out;
  const DisparityLattice l = fitDisparityLattice (recs);
  if (l.found && std::fabs (l.constant_mm / l.camera_constant_mm - 1.0) > 0.005)
  {
    out.constant_mm = l.constant_mm;
    out.phase = l.phase;
  }
  return out;
}

double
subStepPhase (double disparity_px, double step_px, double phase)
{
  const double x = disparity_px / step_px - phase;
  return x - std::floor (x);
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
