/*
 * pcl_texlet OpenNI2 driver: a recording folder or a simulator scene as a live 30 Hz Kinect-class
 * device, for any OpenNI2 program (PCL's OpenNI2Grabber, pcl_openni2_viewer, ROS openni2_camera).
 *
 * The device (URI syntax in frame_source.h and docs/openni2_device.md) has a depth sensor
 * (PIXEL_FORMAT_DEPTH_1_MM; a simulator scene at VGA and QVGA, a recording at its own size) and,
 * for recordings whose every frame has colour, a colour sensor (RGB888 on the depth image's grid,
 * so depth is already registered to colour). One clock thread per device makes frame i (from 0)
 * a period after frame i - 1 (the first a period after the start) and hands it to every started stream with frame index i + 1 and timestamp
 * (i + 1) * 33333 us, so depth and colour of one instant share index and timestamp (OpenNI2's
 * depth-colour frame sync pairs frames by index).
 *
 * Properties answered consistently with the source's camera model (fx, fy, baseline):
 * - fields of view 2 atan (w / (2 fx)) and 2 atan (h / (2 fy)), so PCL's grabber's focal length
 *   w / (2 tan (hFOV / 2)) is fx (the grabber takes the principal point as ((w-1)/2, (h-1)/2),
 *   which the simulator's sensors have);
 * - PS1080's zero-plane distance (120 mm) and pixel size (at SXGA: 120 mm / (fx * 1280 / w)),
 *   which ROS and OpenNI1-era code turn into the focal length, and the emitter-camera distance
 *   (the baseline, cm) that PCL's grabber reads;
 * - cropping (off), mirroring (off by default; on flips rows), depth range, registration (depth to
 *   colour: the frames already are), depth-colour frame sync.
 * Every property is also announced to OpenNI2's Recorder (notifyAllProperties), so .oni files
 * recorded from this device carry them.
 */
#include "frame_source.h"

#include <new>
// ONI_EXPORT_DRIVER uses XnLib's allocation macros, which OpenNI2's public headers do not ship.
#define XN_NEW(type, arg) new type (arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>
#include <PS1080.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace
{

using pcl::texlet::CameraInfo;
using pcl::texlet::DepthFrame;
using pcl::texlet::oni_device::FrameSource;
using pcl::texlet::oni_device::SourceMode;

constexpr int kFps = 30;
constexpr std::uint64_t kFramePeriodUs = 33333;
constexpr std::uint64_t kZeroPlaneDistanceMm = 120; // a PS1080's: only the ratio to the pixel size matters

class Device;

/** Writes \a value into OpenNI2's property buffer when its size is that of T. */
template <typename T> OniStatus
answer (void *data, int *size, T value)
{
  if (!data || !size || *size != int (sizeof (T)))
    return ONI_STATUS_BAD_PARAMETER;
  std::memcpy (data, &value, sizeof (T));
  return ONI_STATUS_OK;
}

/** One sensor's stream; the device's clock thread hands it frames while it is started. */
class Stream : public oni::driver::StreamBase
{
public:
  Stream (Device &device, OniSensorType sensor) : device_ (device), sensor_ (sensor) {}
  ~Stream () override;

  OniStatus
  start () override;

  void
  stop () override;

  OniBool
  isPropertySupported (int id) override;

  OniStatus
  getProperty (int id, void *data, int *size) override;

  OniStatus
  setProperty (int id, const void *data, int size) override;

  void
  notifyAllProperties () override;

  /** Raises \a source as frame \a index (from 1); runs on the device's clock thread. */
  void
  deliver (const DepthFrame &source, std::uint64_t index);

  OniSensorType
  sensor () const { return sensor_; }

private:
  OniVideoMode
  videoMode () const;

  Device &device_;
  OniSensorType sensor_;
  std::atomic<bool> mirroring_ {false};
};

class Device : public oni::driver::DeviceBase
{
public:
  Device (FrameSource::Ptr source, oni::driver::DriverServices &services) : source_ (std::move (source)), services_ (services)
  {
    const std::vector<SourceMode> modes = source_->modes ();
    mode_ = modes.front ();
    for (const SourceMode &m : modes)
    {
      depth_modes_.push_back (OniVideoMode {ONI_PIXEL_FORMAT_DEPTH_1_MM, m.width, m.height, kFps});
      colour_modes_.push_back (OniVideoMode {ONI_PIXEL_FORMAT_RGB888, m.width, m.height, kFps});
    }
    sensors_[0].sensorType = ONI_SENSOR_DEPTH;
    sensors_[0].numSupportedVideoModes = static_cast<int> (depth_modes_.size ());
    sensors_[0].pSupportedVideoModes = depth_modes_.data ();
    sensors_[1].sensorType = ONI_SENSOR_COLOR;
    sensors_[1].numSupportedVideoModes = static_cast<int> (colour_modes_.size ());
    sensors_[1].pSupportedVideoModes = colour_modes_.data ();
  }

  ~Device () override { stopClock (); }

  OniStatus
  getSensorInfoList (OniSensorInfo **sensors, int *count) override
  {
    *sensors = sensors_;
    *count = source_->hasColour () ? 2 : 1;
    return ONI_STATUS_OK;
  }

  oni::driver::StreamBase *
  createStream (OniSensorType type) override
  {
    if (type == ONI_SENSOR_DEPTH || (type == ONI_SENSOR_COLOR && source_->hasColour ()))
      return new Stream (*this, type);
    return nullptr;
  }

  void
  destroyStream (oni::driver::StreamBase *stream) override { delete stream; }

  OniBool
  isPropertySupported (int id) override
  {
    return id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION;
  }

  OniStatus
  getProperty (int id, void *data, int *size) override
  {
    if (id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION)
      return answer<int> (data, size, registration_);
    return ONI_STATUS_NOT_SUPPORTED;
  }

  OniStatus
  setProperty (int id, const void *data, int size) override
  {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION || size != int (sizeof (int)))
      return ONI_STATUS_NOT_SUPPORTED;
    const int mode = *static_cast<const int *> (data);
    if (!isImageRegistrationModeSupported (static_cast<OniImageRegistrationMode> (mode)))
      return ONI_STATUS_NOT_SUPPORTED;
    registration_ = mode;
    return ONI_STATUS_OK;
  }

  /** Depth to colour is what the frames already are, where there is colour. */
  OniBool
  isImageRegistrationModeSupported (OniImageRegistrationMode mode) override
  {
    return mode == ONI_IMAGE_REGISTRATION_OFF || (mode == ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR && source_->hasColour ());
  }

  const FrameSource &
  source () const { return *source_; }

  SourceMode
  mode () const
  {
    std::lock_guard<std::mutex> lock (mutex_);
    return mode_;
  }

  CameraInfo
  cameraInfo () const { return source_->cameraInfo (mode ()); }

  /** Sets the mode of both sensors (they share one image grid); false for a mode not offered. */
  bool
  setMode (int width, int height)
  {
    for (const SourceMode &m : source_->modes ())
      if (m.width == width && m.height == height)
      {
        std::lock_guard<std::mutex> lock (mutex_);
        mode_ = m;
        return true;
      }
    return false;
  }

  const std::vector<OniVideoMode> &
  depthModes () const { return depth_modes_; }

  void
  streamStarted (Stream *stream)
  {
    std::lock_guard<std::mutex> delivering (deliver_mutex_);
    std::lock_guard<std::mutex> lock (mutex_);
    started_.insert (stream);
    if (!clock_.joinable ())
    {
      running_ = true;
      clock_ = std::thread ([this] { run (); });
    }
  }

  /** After it returns, no frame is handed to \a stream any more. */
  void
  streamStopped (Stream *stream)
  {
    bool last = false;
    {
      std::lock_guard<std::mutex> delivering (deliver_mutex_);
      std::lock_guard<std::mutex> lock (mutex_);
      started_.erase (stream);
      last = started_.empty ();
    }
    if (last)
      stopClock ();
  }

private:
  void
  stopClock ()
  {
    {
      std::lock_guard<std::mutex> lock (mutex_);
      running_ = false;
    }
    wake_.notify_all ();
    if (clock_.joinable () && clock_.get_id () != std::this_thread::get_id ())
      clock_.join ();
  }

  /** The clock: frame i at start + i periods; a source that fails ends the stream, logged. */
  void
  run ()
  {
    const std::uint64_t count = source_->frameCount ();
    // The first frame comes a period after the start, as a sensor's does. A frame made late (a
    // slow disk) moves the schedule on rather than bursting to catch up: consumers that read the
    // newest frame (OpenNI2's readFrame) would lose the frames of a burst.
    auto due = std::chrono::steady_clock::now () + std::chrono::microseconds (kFramePeriodUs);
    DepthFrame frame;
    for (std::uint64_t i = 0; count == 0 || i < count; ++i)
    {
      {
        std::unique_lock<std::mutex> lock (mutex_);
        if (wake_.wait_until (lock, due, [this] { return !running_; }))
          return;
      }
      due = std::max (due, std::chrono::steady_clock::now ()) + std::chrono::microseconds (kFramePeriodUs);
      try
      {
        source_->frame (i, mode (), frame);
      }
      catch (const std::exception &e)
      {
        services_.errorLoggerAppend ("pcltexlet: %s", e.what ());
        std::fprintf (stderr, "pcltexlet driver: the device stops: %s\n", e.what ());
        return;
      }
      std::lock_guard<std::mutex> delivering (deliver_mutex_);
      std::vector<Stream *> streams;
      {
        std::lock_guard<std::mutex> lock (mutex_);
        if (!running_)
          return;
        streams.assign (started_.begin (), started_.end ());
      }
      // Depth first, so a recorder stores each instant's records in one order.
      std::sort (streams.begin (), streams.end (),
                 [] (const Stream *a, const Stream *b) { return a->sensor () == ONI_SENSOR_DEPTH && b->sensor () != ONI_SENSOR_DEPTH; });
      for (Stream *stream : streams)
        stream->deliver (frame, i + 1);
    }
  }

  FrameSource::Ptr source_;
  oni::driver::DriverServices &services_;
  std::vector<OniVideoMode> depth_modes_;
  std::vector<OniVideoMode> colour_modes_;
  OniSensorInfo sensors_[2];
  int registration_ = ONI_IMAGE_REGISTRATION_OFF;

  mutable std::mutex mutex_;   ///< mode_, started_, running_
  std::mutex deliver_mutex_;   ///< held while frames are handed out, so that stop () waits for them
  std::condition_variable wake_;
  SourceMode mode_;
  std::set<Stream *> started_;
  bool running_ = false;
  std::thread clock_;
};

Stream::~Stream () { stop (); }

OniStatus
Stream::start ()
{
  device_.streamStarted (this);
  return ONI_STATUS_OK;
}

void
Stream::stop ()
{
  device_.streamStopped (this);
}

OniVideoMode
Stream::videoMode () const
{
  const SourceMode m = device_.mode ();
  return OniVideoMode {sensor_ == ONI_SENSOR_DEPTH ? ONI_PIXEL_FORMAT_DEPTH_1_MM : ONI_PIXEL_FORMAT_RGB888, m.width, m.height, kFps};
}

OniBool
Stream::isPropertySupported (int id)
{
  switch (id)
  {
    case ONI_STREAM_PROPERTY_VIDEO_MODE:
    case ONI_STREAM_PROPERTY_CROPPING:
    case ONI_STREAM_PROPERTY_MIRRORING:
    case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
    case ONI_STREAM_PROPERTY_VERTICAL_FOV:
    case ONI_STREAM_PROPERTY_STRIDE:
      return TRUE;
    case ONI_STREAM_PROPERTY_MAX_VALUE:
    case ONI_STREAM_PROPERTY_MIN_VALUE:
    case XN_STREAM_PROPERTY_ZERO_PLANE_DISTANCE:
    case XN_STREAM_PROPERTY_ZERO_PLANE_PIXEL_SIZE:
    case XN_STREAM_PROPERTY_EMITTER_DCMOS_DISTANCE:
      return sensor_ == ONI_SENSOR_DEPTH;
    default:
      return FALSE;
  }
}

OniStatus
Stream::getProperty (int id, void *data, int *size)
{
  if (!isPropertySupported (id))
    return ONI_STATUS_NOT_SUPPORTED;
  const OniVideoMode mode = videoMode ();
  const CameraInfo info = device_.cameraInfo ();
  switch (id)
  {
    case ONI_STREAM_PROPERTY_VIDEO_MODE:
      return answer (data, size, mode);
    case ONI_STREAM_PROPERTY_CROPPING:
      return answer (data, size, OniCropping {FALSE, 0, 0, mode.resolutionX, mode.resolutionY});
    case ONI_STREAM_PROPERTY_MIRRORING:
      return answer<OniBool> (data, size, mirroring_ ? TRUE : FALSE);
    case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
      return answer (data, size, static_cast<float> (2.0 * std::atan (mode.resolutionX / (2.0 * info.fx ()))));
    case ONI_STREAM_PROPERTY_VERTICAL_FOV:
      return answer (data, size, static_cast<float> (2.0 * std::atan (mode.resolutionY / (2.0 * info.fy ()))));
    case ONI_STREAM_PROPERTY_STRIDE:
      return answer<int> (data, size, mode.resolutionX * (sensor_ == ONI_SENSOR_DEPTH ? 2 : 3));
    case ONI_STREAM_PROPERTY_MAX_VALUE:
      return answer<int> (data, size, 10000); // a Kinect v1's, mm
    case ONI_STREAM_PROPERTY_MIN_VALUE:
      return answer<int> (data, size, 0);
    case XN_STREAM_PROPERTY_ZERO_PLANE_DISTANCE: // PS1080: unsigned long long, mm
      return answer<unsigned long long> (data, size, kZeroPlaneDistanceMm);
    case XN_STREAM_PROPERTY_ZERO_PLANE_PIXEL_SIZE: // PS1080: double, mm, of an SXGA (1280 px wide) pixel
      return answer<double> (data, size, kZeroPlaneDistanceMm / (info.fx () * 1280.0 / mode.resolutionX));
    case XN_STREAM_PROPERTY_EMITTER_DCMOS_DISTANCE: // PS1080: double, cm
      return answer<double> (data, size, info.baseline_m * 100.0);
    default:
      return ONI_STATUS_NOT_SUPPORTED;
  }
}

OniStatus
Stream::setProperty (int id, const void *data, int size)
{
  if (!data)
    return ONI_STATUS_BAD_PARAMETER;
  if (id == ONI_STREAM_PROPERTY_MIRRORING && size == int (sizeof (OniBool)))
  {
    mirroring_ = *static_cast<const OniBool *> (data) != FALSE;
    raisePropertyChanged (id, data, size);
    return ONI_STATUS_OK;
  }
  if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && size == int (sizeof (OniVideoMode)))
  {
    const OniVideoMode *m = static_cast<const OniVideoMode *> (data);
    const OniVideoMode current = videoMode ();
    if (m->pixelFormat != current.pixelFormat || m->fps != kFps || !device_.setMode (m->resolutionX, m->resolutionY))
      return ONI_STATUS_NOT_SUPPORTED;
    raisePropertyChanged (id, data, size);
    return ONI_STATUS_OK;
  }
  if (id == ONI_STREAM_PROPERTY_CROPPING && size == int (sizeof (OniCropping)))
    return static_cast<const OniCropping *> (data)->enabled ? ONI_STATUS_NOT_SUPPORTED : ONI_STATUS_OK;
  return ONI_STATUS_NOT_SUPPORTED;
}

void
Stream::notifyAllProperties ()
{
  const int ids[] = {ONI_STREAM_PROPERTY_VIDEO_MODE,         ONI_STREAM_PROPERTY_CROPPING,
                     ONI_STREAM_PROPERTY_MIRRORING,          ONI_STREAM_PROPERTY_HORIZONTAL_FOV,
                     ONI_STREAM_PROPERTY_VERTICAL_FOV,       ONI_STREAM_PROPERTY_STRIDE,
                     ONI_STREAM_PROPERTY_MAX_VALUE,          ONI_STREAM_PROPERTY_MIN_VALUE,
                     XN_STREAM_PROPERTY_ZERO_PLANE_DISTANCE, XN_STREAM_PROPERTY_ZERO_PLANE_PIXEL_SIZE,
                     XN_STREAM_PROPERTY_EMITTER_DCMOS_DISTANCE};
  for (int id : ids)
  {
    if (!isPropertySupported (id))
      continue;
    std::uint8_t buffer[sizeof (OniVideoMode) + sizeof (OniCropping) + 16];
    int size = 0;
    switch (id)
    {
      case ONI_STREAM_PROPERTY_VIDEO_MODE: size = sizeof (OniVideoMode); break;
      case ONI_STREAM_PROPERTY_CROPPING: size = sizeof (OniCropping); break;
      case ONI_STREAM_PROPERTY_MIRRORING: size = sizeof (OniBool); break;
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
      case ONI_STREAM_PROPERTY_VERTICAL_FOV: size = sizeof (float); break;
      case XN_STREAM_PROPERTY_ZERO_PLANE_DISTANCE: size = sizeof (unsigned long long); break;
      case XN_STREAM_PROPERTY_ZERO_PLANE_PIXEL_SIZE:
      case XN_STREAM_PROPERTY_EMITTER_DCMOS_DISTANCE: size = sizeof (double); break;
      default: size = sizeof (int);
    }
    if (getProperty (id, buffer, &size) == ONI_STATUS_OK)
      raisePropertyChanged (id, buffer, size);
  }
}

void
Stream::deliver (const DepthFrame &source, std::uint64_t index)
{
  const OniVideoMode mode = videoMode ();
  if (source.width != mode.resolutionX || source.height != mode.resolutionY)
    return; // made before a mode change: the next frame has the new size
  const bool depth = sensor_ == ONI_SENSOR_DEPTH;
  if (!depth && source.rgb.size () != std::size_t (3) * source.width * source.height)
    return;
  OniFrame *frame = getServices ().acquireFrame ();
  if (!frame)
    return;
  const int pixel = depth ? 2 : 3;
  const int stride = source.width * pixel;
  const std::uint8_t *bytes = depth ? reinterpret_cast<const std::uint8_t *> (source.depth_mm.data ()) : source.rgb.data ();
  std::uint8_t *out = static_cast<std::uint8_t *> (frame->data);
  if (!mirroring_)
    std::memcpy (out, bytes, std::size_t (stride) * source.height);
  else
    for (int v = 0; v < source.height; ++v)
      for (int u = 0; u < source.width; ++u)
        std::memcpy (out + std::size_t (v) * stride + std::size_t (source.width - 1 - u) * pixel,
                     bytes + std::size_t (v) * stride + std::size_t (u) * pixel, pixel);
  frame->dataSize = stride * source.height;
  frame->frameIndex = static_cast<int> (index);
  frame->timestamp = index * kFramePeriodUs;
  frame->videoMode = mode;
  frame->width = source.width;
  frame->height = source.height;
  frame->cropOriginX = frame->cropOriginY = 0;
  frame->croppingEnabled = FALSE;
  frame->stride = stride;
  frame->sensorType = sensor_;
  raiseNewFrame (frame);
  getServices ().releaseFrame (frame);
}

class Driver : public oni::driver::DriverBase
{
public:
  explicit Driver (OniDriverServices *services) : DriverBase (services) {}

  /** Announces the devices of PCLTEXLET_DEVICES (URIs separated by '|'), so that programs that
    * open the first device, or list devices before opening one (PCL's OpenNI2Grabber does), find
    * them. Other URIs with the prefix are announced when a program opens them (tryDevice).
    */
  OniStatus
  initialize (oni::driver::DeviceConnectedCallback connected, oni::driver::DeviceDisconnectedCallback disconnected,
              oni::driver::DeviceStateChangedCallback state_changed, void *cookie) override
  {
    const OniStatus status = DriverBase::initialize (connected, disconnected, state_changed, cookie);
    if (status != ONI_STATUS_OK)
      return status;
    if (const char *devices = std::getenv ("PCLTEXLET_DEVICES"))
    {
      std::string list = devices;
      std::string::size_type start = 0;
      while (start <= list.size ())
      {
        const auto end = std::min (list.find ('|', start), list.size ());
        const std::string uri = list.substr (start, end - start);
        if (!uri.empty ())
          tryDevice (uri.c_str ());
        start = end + 1;
      }
    }
    return ONI_STATUS_OK;
  }

  /** Announces any URI with the prefix; whether it names a source is checked by deviceOpen. */
  OniStatus
  tryDevice (const char *uri) override
  {
    const std::string text = uri ? uri : "";
    if (text.compare (0, std::strlen (pcl::texlet::oni_device::kUriPrefix), pcl::texlet::oni_device::kUriPrefix) != 0)
      return ONI_STATUS_ERROR;
    std::lock_guard<std::mutex> lock (mutex_);
    for (const OniDeviceInfo &info : infos_)
      if (text == info.uri)
        return ONI_STATUS_OK;
    if (text.size () >= sizeof (OniDeviceInfo::uri))
    {
      getServices ().errorLoggerAppend ("pcltexlet: device URI longer than OpenNI2's %d characters: %s",
                                        int (sizeof (OniDeviceInfo::uri) - 1), text.c_str ());
      return ONI_STATUS_ERROR;
    }
    infos_.emplace_back ();
    OniDeviceInfo &info = infos_.back ();
    std::memset (&info, 0, sizeof (info));
    std::snprintf (info.uri, sizeof (info.uri), "%s", text.c_str ());
    std::snprintf (info.vendor, sizeof (info.vendor), "pcl_texlet");
    std::snprintf (info.name, sizeof (info.name), "simulated Kinect");
    deviceConnected (&info);
    return ONI_STATUS_OK;
  }

  oni::driver::DeviceBase *
  deviceOpen (const char *uri, const char *) override
  {
    try
    {
      return new Device (pcl::texlet::oni_device::openFrameSource (uri ? uri : ""), getServices ());
    }
    catch (const std::exception &e)
    {
      // PCL's exceptions start with ": " when they name no function.
      std::string what = e.what ();
      if (what.rfind (": ", 0) == 0)
        what.erase (0, 2);
      getServices ().errorLoggerAppend ("pcltexlet: %s", what.c_str ());
      return nullptr;
    }
  }

  void
  deviceClose (oni::driver::DeviceBase *device) override { delete device; }

  void
  shutdown () override {}

  /** OpenNI2 pairs the frames itself (by frame index, which the streams of a device share); it
    * needs only a handle from the driver.
    */
  void *
  enableFrameSync (oni::driver::StreamBase **, int) override { return new int (0); }

  void
  disableFrameSync (void *group) override { delete static_cast<int *> (group); }

private:
  std::mutex mutex_;
  std::deque<OniDeviceInfo> infos_; // OpenNI2 keeps pointers to these: a deque never moves them
};

} // namespace

ONI_EXPORT_DRIVER (Driver)
