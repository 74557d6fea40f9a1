/*
 * pcl_texlet_viewer: where frames come from (files, recordings, a live or recorded sensor).
 */
#pragma once

#include <pcl_texlet/camera/camera_model.h>
#include <pcl_texlet/features/point_types.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <memory>
#include <string>

namespace pcl_texlet_viewer
{

using Cloud = pcl::PointCloud<pcl::PointXYZRGBA>;
using Texlets = pcl::PointCloud<pcl::Texlet>;

/** \brief One frame: an organised cloud to extract texlets from, or texlets read from a file. */
struct Frame
{
  Cloud::ConstPtr cloud;                        ///< null for a texlet file
  Texlets::ConstPtr texlets;                    ///< set for a texlet file
  pcl::texlet::CameraModel::ConstPtr camera;    ///< null: estimated from the cloud
  std::string name;
};

class FrameSource
{
public:
  using Ptr = std::unique_ptr<FrameSource>;
  virtual ~FrameSource () = default;

  /** \brief The next frame if there is a new one; files loop. \throws pcl::IOException for a bad file. */
  virtual bool
  next (Frame &frame) = 0;

  /** \brief Number of frames, 0 for a live stream. */
  virtual std::size_t
  size () const = 0;

  virtual std::string
  describe () const = 0;
};

/** \brief A source for \a input: an organised or texlet PCD file, a folder of PCD files, a
  * recording folder, a .oni file, or "sensor" (the first OpenNI2 device).
  * \throws pcl::IOException naming the input and the problem.
  */
FrameSource::Ptr
openSource (const std::string &input);

/** \brief The first OpenNI2 sensor, or null when none is connected. */
FrameSource::Ptr
openFirstSensor ();

} // namespace pcl_texlet_viewer
