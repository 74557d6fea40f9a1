/*
 * pcl_texlet OpenNI2 driver: where the simulated device's frames come from, and the device URI
 * that selects it.
 *
 * URI syntax (docs/openni2_device.md):
 *
 *   pcltexlet:recording=PATH[;loop=0|1][;frames=N][;colour=0|1]
 *   pcltexlet:sim=plane|box[;distance=M][;tilt_x=DEG][;tilt_y=DEG][;elevation=DEG]
 *             [;effects=NAME,NAME,...][;set=EFFECT.PARAMETER=VALUE]...[;config=YAML]
 *             [;noise=paper|none][;shadows=0|1][;seed=N][;frames=N]
 *
 * A recording is any recording openRecording () reads except .oni files (an .oni file is played
 * by OpenNI2's own OniFile driver under its path). A simulator scene is endless unless frames=N
 * is given; a recording loops unless loop=0.
 *
 * This code has no OpenNI2 types: the driver (pcltexlet_driver.cpp) wraps it.
 */
#pragma once

#include <pcl_texlet/camera/camera_info.h>
#include <pcl_texlet/camera/depth_frame.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace oni_device
{

/** \brief The URI prefix every device of this driver has. */
constexpr const char *kUriPrefix = "pcltexlet:";

/** \brief A parsed device URI. */
struct DeviceUri
{
  std::string recording;    ///< recording path, or empty for a simulator scene
  std::string scene;        ///< "plane" or "box" for a simulator scene
  bool loop = true;         ///< recordings: start again after the last frame
  bool colour = true;       ///< recordings: offer the colour stream where every frame has colour
  std::uint64_t frames = 0; ///< frames to deliver (0: the recording once or looped, or endless)
  std::map<std::string, double> scene_parameters; ///< distance, tilt_x, tilt_y, elevation
  std::vector<std::string> effects;     ///< effects switched on with their default parameters
  std::vector<std::string> assignments; ///< effect.parameter=value
  std::string config;                   ///< simulation config YAML file
  std::string noise = "paper";          ///< base noise: paper or none
  bool shadows = true;
  std::uint32_t seed = 0;
};

/** \brief Parses \a uri.
  * \throws pcl::BadArgumentException naming the URI and what is wrong with it.
  */
DeviceUri
parseDeviceUri (const std::string &uri);

/** \brief A depth video mode the source offers. */
struct SourceMode
{
  int width = 0;
  int height = 0;
};

/** \brief The frames of one device: made on demand, frame i (from 0) at any time. */
class FrameSource
{
public:
  using Ptr = std::shared_ptr<FrameSource>;
  virtual ~FrameSource () = default;

  /** \brief Depth modes offered; the first is the default. */
  virtual std::vector<SourceMode>
  modes () const = 0;

  /** \brief Intrinsics of the depth frames at \a mode. */
  virtual CameraInfo
  cameraInfo (const SourceMode &mode) const = 0;

  /** \brief Whether frames carry colour (RGB888 on the depth image's grid). */
  virtual bool
  hasColour () const = 0;

  /** \brief Frames the device delivers before it falls silent; 0 for endless. */
  virtual std::uint64_t
  frameCount () const = 0;

  /** \brief Frame \a index (from 0) at \a mode into \a frame.
    * \throws pcl::PCLException for a frame that cannot be made (e.g. a file changed since open).
    */
  virtual void
  frame (std::uint64_t index, const SourceMode &mode, DepthFrame &frame) = 0;

  /** \brief What the device is, for OpenNI2's device name. */
  virtual std::string
  description () const = 0;
};

/** \brief The source a URI names; recordings are read through once here, so that a missing,
  * corrupt or inconsistent recording (e.g. a frame size that changes) fails the open.
  * \throws pcl::PCLException naming the URI or file and the problem.
  */
FrameSource::Ptr
openFrameSource (const std::string &uri);

} // namespace oni_device
} // namespace texlet
} // namespace pcl
