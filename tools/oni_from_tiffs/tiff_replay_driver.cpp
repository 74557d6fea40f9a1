/*
 * An OpenNI2 device driver that replays the 16-bit depth TIFFs of PCL's image grabber
 * (<folder>/*_depth.tiff, 640x480, millimetres) as a depth sensor, once each at 30 Hz, under the
 * URI "tiffreplay:<folder>".
 *
 * It exists to make a real .oni file here, where no sensor is attached: OpenNI2's own Recorder
 * records this device like any other. It reports the stream properties a sensor driver reports
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
#include <deque>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <dirent.h>
#include <string>
#include <thread>
#include <vector>

namespace
{

const char *const kUriPrefix = "tiffreplay:";
const int kWidth = 640;
const int kHeight = 480;
const double kFocalPx = 525.0;

using Frames = std::vector<std::vector<std::uint16_t>>;

/** The *_depth.tiff frames of \a folder in name order; a file that is not 640x480 16-bit grey ends the list. */
Frames
loadFrames (const std::string &folder)
{
  std::vector<std::string> names;
  if (DIR *dir = opendir (folder.c_str ()))
  {
    const std::string suffix = "_depth.tiff";
    while (const dirent *entry = readdir (dir))
    {
      const std::string name = entry->d_name;
      if (name.size () > suffix.size () && name.compare (name.size () - suffix.size (), suffix.size (), suffix) == 0)
        names.push_back (name);
    }
    closedir (dir);
  }
  std::sort (names.begin (), names.end ());
  Frames frames;
  for (const std::string &name : names)
  {
    TIFF *tiff = TIFFOpen ((folder + "/" + name).c_str (), "r");
    if (!tiff)
      break;
    std::uint32_t width = 0, height = 0;
    std::uint16_t bits = 0, samples = 0;
    TIFFGetField (tiff, TIFFTAG_IMAGEWIDTH, &width);
    TIFFGetField (tiff, TIFFTAG_IMAGELENGTH, &height);
    TIFFGetFieldDefaulted (tiff, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted (tiff, TIFFTAG_SAMPLESPERPIXEL, &samples);
    bool ok = width == kWidth && height == kHeight && bits == 16 && samples == 1;
    std::vector<std::uint16_t> depth (std::size_t (kWidth) * kHeight);
    for (std::uint32_t y = 0; ok && y < height; ++y)
      ok = TIFFReadScanline (tiff, depth.data () + std::size_t (y) * kWidth, y) == 1;
    TIFFClose (tiff);
    if (!ok)
      break;
    frames.push_back (std::move (depth));
  }
  return frames;
}

class DepthStream : public oni::driver::StreamBase
{
public:
  explicit DepthStream (const Frames *frames) : frames_ (frames) {}
  ~DepthStream () override { stop (); }

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
    return id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_CROPPING ||
           id == ONI_STREAM_PROPERTY_MIRRORING || id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ||
           id == ONI_STREAM_PROPERTY_VERTICAL_FOV || id == ONI_STREAM_PROPERTY_MAX_VALUE ||
           id == ONI_STREAM_PROPERTY_MIN_VALUE;
  }

  OniStatus
  getProperty (int id, void *data, int *size) override
  {
    switch (id)
    {
      case ONI_STREAM_PROPERTY_VIDEO_MODE:
        if (*size != sizeof (OniVideoMode))
          return ONI_STATUS_BAD_PARAMETER;
        *static_cast<OniVideoMode *> (data) = mode ();
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
      case ONI_STREAM_PROPERTY_MAX_VALUE:
      case ONI_STREAM_PROPERTY_MIN_VALUE:
        if (*size != sizeof (int))
          return ONI_STATUS_BAD_PARAMETER;
        *static_cast<int *> (data) = id == ONI_STREAM_PROPERTY_MAX_VALUE ? 10000 : 0; // a Kinect v1's range, mm
        return ONI_STATUS_OK;
    }
    return ONI_STATUS_NOT_SUPPORTED;
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
      if (m->resolutionX == kWidth && m->resolutionY == kHeight && m->pixelFormat == ONI_PIXEL_FORMAT_DEPTH_1_MM)
        return ONI_STATUS_OK;
    }
    return ONI_STATUS_NOT_SUPPORTED;
  }

  static OniVideoMode
  mode ()
  {
    OniVideoMode m;
    m.pixelFormat = ONI_PIXEL_FORMAT_DEPTH_1_MM;
    m.resolutionX = kWidth;
    m.resolutionY = kHeight;
    m.fps = 30;
    return m;
  }

private:
  void
  run ()
  {
    auto due = std::chrono::steady_clock::now ();
    for (std::size_t index = 0; running_ && index < frames_->size (); ++index)
    {
      due += std::chrono::microseconds (33333);
      std::this_thread::sleep_until (due);
      OniFrame *frame = getServices ().acquireFrame ();
      if (!frame)
        return;
      const std::vector<std::uint16_t> &depth = (*frames_)[index];
      std::memcpy (frame->data, depth.data (), depth.size () * sizeof (std::uint16_t));
      frame->dataSize = static_cast<int> (depth.size () * sizeof (std::uint16_t));
      frame->frameIndex = static_cast<int> (index + 1);
      frame->timestamp = (index + 1) * 33333;
      frame->videoMode = mode ();
      frame->width = kWidth;
      frame->height = kHeight;
      frame->cropOriginX = frame->cropOriginY = 0;
      frame->croppingEnabled = FALSE;
      frame->stride = kWidth * sizeof (std::uint16_t);
      frame->sensorType = ONI_SENSOR_DEPTH;
      raiseNewFrame (frame);
      getServices ().releaseFrame (frame);
    }
  }

  const Frames *frames_;
  std::atomic<bool> running_ {false};
  std::thread thread_;
};

class Device : public oni::driver::DeviceBase
{
public:
  explicit Device (const std::string &folder) : frames_ (loadFrames (folder))
  {
    mode_ = DepthStream::mode ();
    sensor_.sensorType = ONI_SENSOR_DEPTH;
    sensor_.numSupportedVideoModes = 1;
    sensor_.pSupportedVideoModes = &mode_;
  }

  bool
  empty () const { return frames_.empty (); }

  OniStatus
  getSensorInfoList (OniSensorInfo **sensors, int *count) override
  {
    *sensors = &sensor_;
    *count = 1;
    return ONI_STATUS_OK;
  }

  oni::driver::StreamBase *
  createStream (OniSensorType type) override
  {
    return type == ONI_SENSOR_DEPTH ? new DepthStream (&frames_) : nullptr;
  }

  void
  destroyStream (oni::driver::StreamBase *stream) override { delete stream; }

private:
  Frames frames_;
  OniVideoMode mode_;
  OniSensorInfo sensor_;
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
