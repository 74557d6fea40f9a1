/*
 * pcl_texlet kernels: what a texlet is computed from.
 */
#pragma once

#include <pcl_texlet/kernels/vec3.h>

#include <limits>

namespace pcl
{
namespace texlet
{
namespace kernels
{

template <typename S> struct WindowDiscForm;

/** \brief The valid points of a texlet's pixel disc, with the depth noise of each, and the
  * hexagonal ring used by normal averaging. Points are in the camera frame (z = depth along
  * the optical axis, > 0); sigma is the depth SD in the same unit. Depth noise moves a point
  * along its ray from the camera centre, i.e. p -> p (1 + dz / z).
  */
template <typename S>
struct Neighbourhood
{
  const S *x = nullptr;
  const S *y = nullptr;
  const S *z = nullptr;
  const S *sigma = nullptr; ///< may be null when no uncertainty is computed
  int count = 0;

  Vec3<S> ring[7];      ///< centre (0) and six hexagonal neighbours (1..6) in angular order
  S ring_sigma[7];      ///< their depth SD
  bool ring_valid[7];   ///< whether each has a finite point
  int ring_du[7] = {0, 0, 0, 0, 0, 0, 0}; ///< their pixel offsets from the centre, where ring_offsets
  int ring_dv[7] = {0, 0, 0, 0, 0, 0, 0};
  /** Whether ring_du, ring_dv are known, so that the ring's shared noise follows its pixels
    * (ringCorrelation()); else the ring shares the lines' part whole and the window's part is
    * taken as its own. */
  bool ring_offsets = false;
  /** The centre pixel's viewing ray, scaled to z = 1 (a point at depth z is z * centre_ray);
    * has_centre_ray is false where neither the centre nor a symmetric pair around it has a reading. */
  Vec3<S> centre_ray = {S (0), S (0), S (1)};
  bool has_centre_ray = false;
  /** The part of each point's depth variance shared with the other points (column or row bands,
    * frame offsets): the depth noises of points i and j have covariance
    * shared_fraction sigma_i sigma_j line_correlation^|l_i - l_j| (l: their lines, line ()), and
    * (1 - shared_fraction) sigma_i^2 of each is its own. 0: independent noise. */
  S shared_fraction = S (0);
  /** The correlation of the shared part between adjacent lines, in (0, 1]; 1: the whole patch
    * shares it. Below 1 the lines come from pixel[k] (line ()). */
  S line_correlation = S (1);
  const int *pixel = nullptr; ///< the points' pixel indices (v * width + u), for their lines
  int width = 0;              ///< the image's width, pixels
  /** Whether the shared noise's lines are rows (horizontal bands) rather than columns; the disc
    * is symmetric under u <-> v, so everything else is the same. */
  bool lines_are_rows = false;
  /** The part of each point's depth variance shared with its neighbours over a window (the
    * matcher's correlation window, term spatial_correlation): points du, dv apart (their pixels)
    * correlate by window_fraction tri(du) tri(dv), tri(d) = max(0, 1 - |d| / window_px). */
  S window_fraction = S (0);
  int window_px = 1; ///< that window's width, whole pixels (1 .. kMaxWindowPx)
  /** The window's form of the texlet's disc from tables (window_disc_form.h), where its pixels
    * without a reading or an inlier are few; null: by the windows' sums. */
  const WindowDiscForm<S> *window_disc = nullptr;
  /** With window_disc: each point's offset in the disc (in disc order), where some of its pixels
    * have no reading; null: point k is offset k (the disc is whole). */
  const int *disc_offset = nullptr;

  PCL_TEXLET_HD Vec3<S>
  point (int i) const { return {x[i], y[i], z[i]}; }

  /** \brief Point \a i's line of shared noise: its column, or its row where lines_are_rows. */
  PCL_TEXLET_HD int
  line (int i) const { return lines_are_rows ? pixel[i] / width : pixel[i] % width; }
};

/** \brief The noise model at a texlet's centre pixel and its points' mean depth, from one
  * evaluation: the depth SD, and the part of its variance the points share (the column or row
  * variance over the whole) with its correlation length across those lines.
  */
struct CentreNoise
{
  double sigma = 0.0;               ///< depth SD, metres
  double fraction = 0.0;            ///< Neighbourhood::shared_fraction
  /** lines over which the correlation falls by e; infinite (as NoiseMoments'), or <= 0: no fall */
  double line_correlation_px = std::numeric_limits<double>::infinity ();
  bool lines_are_rows = false;      ///< Neighbourhood::lines_are_rows
  double window_fraction = 0.0;     ///< Neighbourhood::window_fraction
  double window_px = 1.0;           ///< Neighbourhood::window_px, before rounding
};

} // namespace kernels
} // namespace texlet
} // namespace pcl
