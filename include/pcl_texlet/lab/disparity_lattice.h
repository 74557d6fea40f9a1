/*
 * pcl_texlet lab: the disparity lattice of a recording, from its depth values.
 *
 * A structured-light sensor measures disparity in sub-pixel steps, so its depths sit on a
 * lattice z_k = C / (k + phase): equally spaced in inverse depth, 1 / C apart. C is 1000 f b /
 * step (mm) only when the sensor's internal constants are the calibrated ones; a real Kinect's
 * are not, so the lab measures C from the depth values instead of trusting camera.yaml.
 */
#pragma once

#include <pcl_texlet/lab/recording_measurement.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{

/** \brief The lattice fitted to a set of depth values, and how well they sit on it. */
struct DisparityLattice
{
  bool found = false;         ///< the values sit on a lattice: coherence at least kMinCoherence, more than chance
                              ///< gives 1 time in 1000 over the range searched, residual_ratio at most kMaxResidualRatio
  double constant_mm = 0.0;   ///< C: z_k = C / (k + phase), mm
  double phase = 0.0;         ///< in [0, 1)
  double coherence = 0.0;     ///< |mean of exp(2 pi i C / z)| over the values, weighted: 1 on the lattice
  double camera_constant_mm = 0.0; ///< 1000 f b / step from camera.yaml
  std::size_t values = 0;     ///< distinct depth values the fit used
  /** \brief 90th percentile of the well-resolved values' distance from the lattice over what
    * their whole-mm rounding explains (about 1.6 on a lattice; NaN: too few values resolve a step).
    */
  double residual_ratio = 0.0;

  /** \brief Fewest coherence that counts as a lattice: values on one give about 1 (their mm
    * rounding allowed for). Clusters of consecutive millimetres, as unquantised noise gives, can
    * pass it too, so a lattice also needs kMaxResidualRatio (docs/model_lab.md).
    */
  static constexpr double kMinCoherence = 0.8;
  /** \brief Largest residual_ratio of a lattice (NaN fails too: a lattice must show its steps). */
  static constexpr double kMaxResidualRatio = 3.0;
};

/** \brief Fits the lattice z_k = C / (k + phase) to the distinct nonzero depth values \a depth_mm
  * (whole millimetres, as PNG and TIFF frames hold them), searching C within [0.7, 1.45] times
  * \a camera_constant_mm (outside it C / 2 and 2 C, which fit as well or better, would be
  * confused with C). Values are weighted by how much of a lattice step their own millimetre
  * rounding leaves resolved.
  * \throws pcl::BadArgumentException when \a camera_constant_mm is not positive
  */
DisparityLattice
fitDisparityLattice (const std::vector<std::uint16_t> &depth_mm, double camera_constant_mm);

/** \brief The lattice of the depth values of every frame of \a recordings (their cameras must
  * agree on f b and step: the first one's give the search range).
  */
DisparityLattice
fitDisparityLattice (const std::vector<RecordingMeasurement::ConstPtr> &recordings);

/** \brief One line for people: the lattice found and how it compares with camera.yaml's, or why
  * there is none.
  */
std::string
latticeSummary (const DisparityLattice &lattice);

} // namespace lab
} // namespace texlet
} // namespace pcl
