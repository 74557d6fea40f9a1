/*
 * pcl_texlet model lab, step 1 (measure): per-pixel statistics of a recording over its frames.
 *
 * Per pixel: temporal mean and SD (pixels with too few valid frames are left out and counted;
 * recordings of one frame are accepted, their SD is undefined, NaN),
 * the reference surface (a robust plane fit of the mean for plane scenes, a local plane fit
 * otherwise), the bias (mean minus surface), and the covariates the effects show against:
 * radius, depth, incidence angle, column, row, disparity sub-step phase, frame index (for the
 * per-frame quantities), active projectors (meta.yaml), distance to the nearest depth edge.
 *
 * The frames are kept (16-bit) so that the lab can split them into halves, fit on one and score
 * on the other. Only scene facts are read from meta.yaml (scene, projectors), never the effects
 * a simulator switched on.
 */
#pragma once

#include <pcl_texlet/noise/noise_model.h>
#include <pcl_texlet/io/recording_reader.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{

/** \brief Options of the measurement. */
struct MeasurementSettings
{
  /** \brief Fewest valid frames a pixel needs, as a share of the recording's frames (at least 2,
    * at most the recording's frames: a single-frame recording uses every pixel with a reading).
    */
  double min_valid_share = 0.6;
  /** \brief A depth jump between neighbours larger than this share of the depth is an edge. */
  double edge_jump_share = 0.03;
  /** \brief Robust plane fit: residuals beyond this many robust SDs are outliers. */
  double outlier_sigmas = 4.0;
  /** \brief Half side of the window of the local surface fit (non-plane scenes), pixels. */
  int local_fit_radius_px = 3;
};

/** \brief One recording, measured. Per-pixel arrays are row-major, width x height. */
struct RecordingMeasurement
{
  using Ptr = std::shared_ptr<RecordingMeasurement>;
  using ConstPtr = std::shared_ptr<const RecordingMeasurement>;

  std::string name;          ///< the path it was read from
  CameraInfo camera;         ///< intrinsics, baseline, disparity step
  int width = 0, height = 0;
  int frames = 0;
  double active_projectors = 1; ///< meta.yaml `projectors` (1 when absent)
  bool plane_scene = false;  ///< meta.yaml `scene: plane`: the surface is one plane
  std::string scene = "unknown"; ///< meta.yaml `scene`, or "unknown"

  std::vector<std::uint16_t> depth_mm; ///< the frames, frames x width x height, 0 = no reading

  std::vector<std::uint8_t> used;   ///< 1 where the pixel has enough valid frames and a surface
  std::vector<std::uint16_t> valid_frames; ///< valid frames per pixel
  std::vector<float> mean_mm;       ///< temporal mean of the valid frames
  /** \brief Temporal SD (n - 1) of the valid frames; NaN where a pixel has one valid frame (a
    * single frame shows no temporal SD; single-frame recordings have it NaN everywhere).
    */
  std::vector<float> sd_mm;
  std::vector<float> surface_mm;    ///< reference surface depth (the noise-free depth estimate)
  std::vector<float> bias_mm;       ///< mean minus surface
  std::vector<float> cos_incidence; ///< cosine of the angle between surface normal and viewing ray
  std::vector<float> edge_distance_px; ///< distance to the nearest depth edge (large: none)
  std::vector<float> phase;         ///< sub-step phase of the surface's disparity, [0, 1)
  std::vector<std::uint8_t> inlier; ///< used in the surface fit (plane scenes)
  /** \brief Mean grey level of the frames' colour images, 0 (black) to 1 (white), as
    * PixelContext::intensity holds it (greyLevel()); empty when the recording has none.
    */
  std::vector<float> intensity;

  std::size_t left_out = 0;         ///< pixels with readings but too few valid frames
  std::size_t no_surface = 0;       ///< pixels never valid
  double plane[3] = {0, 0, 0};      ///< plane scenes: disparity = p0 + p1 x + p2 y (normalised x, y)

  /** \brief f (px) times baseline (m). */
  double fb () const { return camera.fb (); }

  /** \brief The noise model's contexts of this recording's pixels: its principal point, f b
    * active projectors and image size.
    */
  PixelContextBuilder
  noiseContexts () const
  {
    PixelContextBuilder b (camera.cx (), camera.cy (), fb ());
    b.setActiveProjectors (active_projectors).setImageSize (width, height);
    return b;
  }
  /** \brief Distance of pixel (u, v) from the principal point, px. */
  double radius (double u, double v) const;
  /** \brief Depth of frame \a t at pixel \a i, mm (0 = none). */
  std::uint16_t at (int t, std::size_t i) const { return depth_mm[static_cast<std::size_t> (t) * width * height + i]; }
  /** \brief Number of used pixels. */
  std::size_t usedCount () const;
};

/** \brief Reads every frame of \a reader and measures them.
  * \param meta_yaml text of the recording's meta.yaml ("" when it has none)
  * \throws pcl::BadArgumentException naming the recording when it has no frame, frames of
  *         differing sizes, or no pixel with enough valid frames.
  */
RecordingMeasurement::Ptr
measureRecording (RecordingReader &reader, const std::string &name, const std::string &meta_yaml,
                  const MeasurementSettings &settings = MeasurementSettings ());

/** \brief Measures frames already in memory (e.g. from the simulator).
  * \param meta_yaml meta.yaml text with the scene facts ("" for none)
  */
RecordingMeasurement::Ptr
measureFrames (const std::vector<DepthFrame> &frames, const CameraInfo &camera, const std::string &name,
               const std::string &meta_yaml, const MeasurementSettings &settings = MeasurementSettings ());

/** \brief Text of the meta.yaml in recording folder \a folder, or "" when there is none (or
  * \a folder is a file, e.g. an .oni recording).
  */
std::string
readMetaYaml (const std::string &folder);

/** \brief What a recording tells the noise model beyond its frames, for
  * pcl::TexletEstimation::setNoiseContext, as the lab uses it: `fb_px_m` from \a camera (fx times
  * the baseline: the disparity-defined terms at the recording's resolution) and
  * `active_projectors` from \a meta_yaml (`projectors`, 1 when absent). The frame index is the
  * caller's to set per frame.
  * \throws pcl::IOException naming \a name for a meta.yaml that is not valid YAML, malformed, or
  *         gives fewer than 1 projector.
  */
PixelContext
recordingNoiseContext (const CameraInfo &camera, const std::string &meta_yaml, const std::string &name);

/** \brief Opens \a path with openRecording, reads its meta.yaml if it has one, and measures it.
  * \throws pcl::IOException / pcl::BadArgumentException naming the path.
  */
RecordingMeasurement::Ptr
measureRecording (const std::string &path, const MeasurementSettings &settings = MeasurementSettings ());

} // namespace lab
} // namespace texlet
} // namespace pcl
