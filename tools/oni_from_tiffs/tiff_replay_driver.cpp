/*
 * An OpenNI2 device driver that replays the frames of PCL's image grabber (<folder>/*_depth.tiff,
 * 16-bit depth in mm, and the <stamp>_rgb.tiff beside any of them, 8-bit RGB; 640x480) as a
 * depth sensor and a colour sensor, once each at 30 Hz, under the URI "tiffreplay:<folder>".
 * Frame i (from 1) of either sensor has timestamp i * 33333 us; a colour frame exists only where
 * the grabber wrote one.
 *
 * It exists to make a real .oni file here, where no sensor is attached: OpenNI2's own Recorder
 * records this device like any other. Its streams report the properties a sensor driver reports
 * (video mode, cropping, mirroring, field of view, depth range), because OpenNI2's OniFile driver
 * plays back no frame of a recording that lacks the cropping property (the reason recordings of
 * OpenNI2's Dummy device play back nothing). The field of view is that of the 525 px focal length
 * in the grabber's intrinsics.xml.
 *
 * Built and used by make_oni.sh; not part of the library.
 */
#include <new>
// ONI_EXPORT_DRIVER uses XnLib's allocation macros, which OpenNI2's public headers do not ship.
#define XN_NEW(type, arg) new type (arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include <tiffio.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <dirent.h>
#include <unistd.h>
#include <string>
#include <thread>
#include <vector>

namespace
{

const char *const kUriPrefix = "tiffreplay:";
const int kWidth = 640;
const int kHeight = 480;
const double kFocalPx = 525.0;
const std::uint64_t kFramePeriodUs = 33333;

struct Frame
{
  int index = 0;              ///< from 1
  std::uint64_t timestamp_us = 0;
  std::vector<std::uint8_t> bytes; ///< row-major, as the video mode lays them out
};

struct Recording
{
  std::vector<Frame> depth;
  std::vector<Frame> colour;
};

/** Reads a 640x480 strip TIFF of \a samples samples of \a bits bits into \a bytes; false if it is not one. */
bool
readTiff (const std::string &path, int bits, int samples, std::vector<std::uint8_t> &bytes)
{
  TIFF *tiff = TIFFOpen (path.c_str (), "r");
  if (!tiff)
    return false;
  std::uint32_t width = 0, height = 0;
  std::uint16_t file_bits = 0, file_samples = 0;
  TIFFGetField (tiff, TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField (tiff, TIFFTAG_IMAGELENGTH, &height);
  TIFFGetFieldDefaulted (tiff, TIFFTAG_BITSPERSAMPLE, &file_bits);
  TIFFGetFieldDefaulted (tiff, TIFFTAG_SAMPLESPERPIXEL, &file_samples);
  const std::size_t row = std::size_t (kWidth) * samples * bits / 8;
  bool ok = width == kWidth && height == kHeight && file_bits == bits && file_samples == samples &&
            TIFFScanlineSize64 (tiff) == row;
  bytes.assign (row * kHeight, 0);
  for (std::uint32_t y = 0; ok && y < height; ++y)
    ok = TIFFReadScanline (tiff, bytes.data () + y * row, y) == 1;
  TIFFClose (tiff);
  return ok;
}

/** The depth frames of \a folder in name order, each with its colour frame where there is one;
  * the first file that cannot be read ends the recording.
  */
Recording
loadRecording (const std::string &folder)
{
  const std::string suffix = "_depth.tiff";
  std::vector<std::string> stems;
  if (DIR *dir = opendir (folder.c_str ()))
  {
    while (const dirent *entry = readdir (dir))
    {
      const std::string name = entry->d_name;
      if (name.size () > suffix.size () && name.compare (name.size () - suffix.size (), suffix.size (), suffix) == 0)
        stems.push_back (name.substr (0, name.size () - suffix.size ()));
    }
    closedir (dir);
  }
  std::sort (stems.begin (), stems.end ());
  Recording recording;
  for (const std::string &stem : stems)
  {
    Frame depth;
    depth.index = static_cast<int> (recording.depth.size () + 1);
    depth.timestamp_us = depth.index * kFramePeriodUs;
    if (!readTiff (folder + "/" + stem + suffix, 16, 1, depth.bytes))
      break;
    Frame colour;
    colour.index = depth.index;
    colour.timestamp_us = depth.timestamp_us;
    const std::string rgb = folder + "/" + stem + "_rgb.tiff";
    if (access (rgb.c_str (), R_OK) == 0 && readTiff (rgb, 8, 3, colour.bytes))
      recording.colour.push_back (std::move (colour));
    recording.depth.push_back (std::move (depth));
  }
  return recording;
}

OniVideoMode
videoMode (OniSensorType sensor)
{
  OniVideoMode mode;
  mode.pixelFormat = sensor == ONI_SENSOR_DEPTH ? ONI_PIXEL_FORMAT_DEPTH_1_MM : ONI_PIXEL_FORMAT_RGB888;
  mode.resolutionX = kWidth;
  mode.resolutionY = kHeight;
  mode.fps = 30;
  return mode;
}

/** One sensor's frames, each raised at its timestamp after start (). */
class ReplayStream : public oni::driver::StreamBase
{
public:
  ReplayStream (OniSensorType sensor, const std::vector<Frame> *frames) : sensor_ (sensor), frames_ (frames) {}
  ~ReplayStream () override { stop (); }

  OniStatus
  start () override
  {
    stop ();
    running_ = true;
    thread_ = std::thread ([this] { run (); });
    return ONI_STATUS_OK;
  }

  void
  stop () override
  {
    running_ = false;
    if (thread_.joinable ())
      thread_.join ();
  }

  OniBool
  isPropertySupported (int id) override
  {
    const bool range = sensor_ == ONI_SENSOR_DEPTH && (id == ONI_STREAM_PROPERTY_MAX_VALUE || id == ONI_STREAM_PROPERTY_MIN_VALUE);
    return range || id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_CROPPING ||
           id == ONI_STREAM_PROPERTY_MIRRORING || id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ||
           id == ONI_STREAM_PROPERTY_VERTICAL_FOV;
  }

  OniStatus
  getProperty (int id, void *data, int *size) override
  {
    if (!isPropertySupported (id))
      return ONI_STATUS_NOT_SUPPORTED;
    switch (id)
    {
      case ONI_STREAM_PROPERTY_VIDEO_MODE:
        if (*size != sizeof (OniVideoMode))
          return ONI_STATUS_BAD_PARAMETER;
        *static_cast<OniVideoMode *> (data) = videoMode (sensor_);
        return ONI_STATUS_OK;
      case ONI_STREAM_PROPERTY_CROPPING:
      {
        if (*size != sizeof (OniCropping))
          return ONI_STATUS_BAD_PARAMETER;
        OniCropping *cropping = static_cast<OniCropping *> (data);
        cropping->enabled = FALSE;
        cropping->originX = cropping->originY = 0;
        cropping->width = kWidth;
        cropping->height = kHeight;
        return ONI_STATUS_OK;
      }
      case ONI_STREAM_PROPERTY_MIRRORING:
        if (*size != sizeof (OniBool))
          return ONI_STATUS_BAD_PARAMETER;
        *static_cast<OniBool *> (data) = FALSE;
        return ONI_STATUS_OK;
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
      case ONI_STREAM_PROPERTY_VERTICAL_FOV:
      {
        if (*size != sizeof (float))
          return ONI_STATUS_BAD_PARAMETER;
        const double half = id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ? kWidth / 2.0 : kHeight / 2.0;
        *static_cast<float *> (data) = static_cast<float> (2.0 * std::atan (half / kFocalPx));
        return ONI_STATUS_OK;
      }
      default: // depth range of a Kinect v1, mm
        if (*size != sizeof (int))
          return ONI_STATUS_BAD_PARAMETER;
        *static_cast<int *> (data) = id == ONI_STREAM_PROPERTY_MAX_VALUE ? 10000 : 0;
        return ONI_STATUS_OK;
    }
  }

  OniStatus
  setProperty (int id, const void *data, int size) override
  {
    // Applications switch mirroring off and set the one video mode; both are what it already is.
    if (id == ONI_STREAM_PROPERTY_MIRRORING && size == sizeof (OniBool) && !*static_cast<const OniBool *> (data))
      return ONI_STATUS_OK;
    if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && size == sizeof (OniVideoMode))
    {
      const OniVideoMode *m = static_cast<const OniVideoMode *> (data);
      const OniVideoMode mode = videoMode (sensor_);
      if (m->resolutionX == mode.resolutionX && m->resolutionY == mode.resolutionY && m->pixelFormat == mode.pixelFormat)
        return ONI_STATUS_OK;
    }
    return ONI_STATUS_NOT_SUPPORTED;
  }

private:
  void
  run ()
  {
    // Colour follows its depth frame by a few milliseconds, so that the recording's record order
    // (and with it the file) is the same every time.
    const auto start = std::chrono::steady_clock::now () + std::chrono::milliseconds (sensor_ == ONI_SENSOR_DEPTH ? 0 : 10);
    for (const Frame &source : *frames_)
    {
      std::this_thread::sleep_until (start + std::chrono::microseconds (source.timestamp_us));
      if (!running_)
        return;
      OniFrame *frame = getServices ().acquireFrame ();
      if (!frame)
        return;
      std::memcpy (frame->data, source.bytes.data (), source.bytes.size ());
      frame->dataSize = static_cast<int> (source.bytes.size ());
      frame->frameIndex = source.index;
      frame->timestamp = source.timestamp_us;
      frame->videoMode = videoMode (sensor_);
      frame->width = kWidth;
      frame->height = kHeight;
      frame->cropOriginX = frame->cropOriginY = 0;
      frame->croppingEnabled = FALSE;
      frame->stride = static_cast<int> (source.bytes.size () / kHeight);
      frame->sensorType = sensor_;
      raiseNewFrame (frame);
      getServices ().releaseFrame (frame);
    }
  }

  OniSensorType sensor_;
  const std::vector<Frame> *frames_;
  std::atomic<bool> running_ {false};
  std::thread thread_;
};

class Device : public oni::driver::DeviceBase
{
public:
  explicit Device (const std::string &folder) : recording_ (loadRecording (folder))
  {
    depth_mode_ = videoMode (ONI_SENSOR_DEPTH);
    colour_mode_ = videoMode (ONI_SENSOR_COLOR);
    sensors_[0].sensorType = ONI_SENSOR_DEPTH;
    sensors_[0].numSupportedVideoModes = 1;
    sensors_[0].pSupportedVideoModes = &depth_mode_;
    sensors_[1].sensorType = ONI_SENSOR_COLOR;
    sensors_[1].numSupportedVideoModes = 1;
    sensors_[1].pSupportedVideoModes = &colour_mode_;
  }

  bool
  empty () const { return recording_.depth.empty (); }

  OniStatus
  getSensorInfoList (OniSensorInfo **sensors, int *count) override
  {
    *sensors = sensors_;
    *count = recording_.colour.empty () ? 1 : 2;
    return ONI_STATUS_OK;
  }

  oni::driver::StreamBase *
  createStream (OniSensorType type) override
  {
    if (type == ONI_SENSOR_DEPTH)
      return new ReplayStream (type, &recording_.depth);
    if (type == ONI_SENSOR_COLOR && !recording_.colour.empty ())
      return new ReplayStream (type, &recording_.colour);
    return nullptr;
  }

  void
  destroyStream (oni::driver::StreamBase *stream) override { delete stream; }

private:
  Recording recording_;
  OniVideoMode depth_mode_;
  OniVideoMode colour_mode_;
  OniSensorInfo sensors_[2];
};

class Driver : public oni::driver::DriverBase
{
public:
  explicit Driver (OniDriverServices *services) : DriverBase (services) {}

  OniStatus
  tryDevice (const char *uri) override
  {
    if (std::strncmp (uri, kUriPrefix, std::strlen (kUriPrefix)) != 0)
      return ONI_STATUS_ERROR;
    infos_.emplace_back ();
    OniDeviceInfo &info = infos_.back ();
    std::snprintf (info.uri, sizeof (info.uri), "%s", uri);
    std::snprintf (info.vendor, sizeof (info.vendor), "pcl_texlet");
    std::snprintf (info.name, sizeof (info.name), "TIFF replay");
    deviceConnected (&info);
    return ONI_STATUS_OK;
  }

  oni::driver::DeviceBase *
  deviceOpen (const char *uri, const char *) override
  {
    if (std::strncmp (uri, kUriPrefix, std::strlen (kUriPrefix)) != 0)
      return nullptr;
    const std::string folder = uri + std::strlen (kUriPrefix);
    Device *device = new Device (folder);
    if (device->empty ())
    {
      getServices ().errorLoggerAppend ("no 640x480 16-bit *_depth.tiff in '%s'", folder.c_str ());
      delete device;
      return nullptr;
    }
    return device;
  }

  void
  deviceClose (oni::driver::DeviceBase *device) override { delete device; }

  void
  shutdown () override {}

private:
  std::deque<OniDeviceInfo> infos_; // OpenNI2 keeps pointers to these: a deque never moves them
};

} // namespace

ONI_EXPORT_DRIVER (Driver)
