#include <pcl_texlet/io/openni2_device_reader.h>

#include <pcl/exceptions.h>
#include <pcl/pcl_config.h> // HAVE_OPENNI2

#ifdef HAVE_OPENNI2
#include "grabber_depth_queue.h"

#include <pcl_texlet/io/guarded_openni2_grabber.h>

#include <pcl/io/openni2/openni2_device.h>

#include <OpenNI.h>
#endif

#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace pcl
{
namespace texlet
{

namespace
{

/** OpenNI2's and PCL's messages on one line, without PCL's leading ": ". */
std::string
oneLine (const std::string &text)
{
  std::string line;
  for (char c : text)
  {
    const bool space = c == ' ' || c == '\t' || c == '\n' || c == '\r';
    if (!space)
      line += c;
    else if (!line.empty () && line.back () != ' ')
      line += ' ';
  }
  while (!line.empty () && line.back () == ' ')
    line.pop_back ();
  if (line.rfind (": ", 0) == 0)
    line.erase (0, 2);
  return line;
}

} // namespace

#ifdef HAVE_OPENNI2

/** \brief The grabber and the queue its callback fills. */
struct OpenNI2DeviceReader::Live
{
  bool openni_initialised = false;
  openni::Device announcer; ///< the device opened once before the grabber, so that OpenNI2 lists it
  GrabberDepthQueue queue {4}; ///< a live device does not wait: frames beyond 4 are dropped
  std::unique_ptr<GuardedOpenNI2Grabber> grabber;

  ~Live ()
  {
    queue.close ();
    grabber.reset (); // waits for its callbacks in flight, then stops and releases the device
    if (announcer.isValid ())
      announcer.close ();
    if (openni_initialised)
      openni::OpenNI::shutdown ();
  }
};

OpenNI2DeviceReader::OpenNI2DeviceReader (const std::string &uri, std::size_t frames, double timeout_s)
  : name_ (uri.empty () ? "the first OpenNI2 device" : "OpenNI2 device '" + uri + "'"), frames_ (frames), timeout_s_ (timeout_s)
{
  if (frames == 0)
    throw pcl::BadArgumentException (name_ + ": the number of frames to read must be positive");
  if (!(timeout_s > 0) || !std::isfinite (timeout_s))
    throw pcl::BadArgumentException (name_ + ": the frame timeout must be positive and finite");
  live_ = std::make_unique<Live> ();
  // PCL's grabber opens only devices OpenNI2 already lists. A device that a driver makes on
  // demand from its URI (as pcl_texlet's simulated Kinect does) is listed once it has been opened,
  // and opening it here first also reports why it cannot be, in OpenNI2's own words.
  std::error_code ec;
  if (!uri.empty () && !std::filesystem::exists (uri, ec))
  {
    live_->openni_initialised = openni::OpenNI::initialize () == openni::STATUS_OK;
    if (!live_->openni_initialised)
      throw pcl::IOException (name_ + ": cannot initialise OpenNI2: " + oneLine (openni::OpenNI::getExtendedError ()));
    if (live_->announcer.open (uri.c_str ()) != openni::STATUS_OK)
      throw pcl::IOException (name_ + ": cannot open it: " + oneLine (openni::OpenNI::getExtendedError ()));
  }
  try
  {
    live_->grabber = std::make_unique<GuardedOpenNI2Grabber> (uri);
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (name_ + ": cannot open it: " + oneLine (e.what ()));
  }
  float focal = 0;
  int width = 0, height = 0;
  float baseline = 0;
  try
  {
    const pcl::io::openni2::OpenNI2Device::Ptr device = live_->grabber->getDevice ();
    focal = device->getDepthFocalLength ();
    const pcl::io::openni2::OpenNI2VideoMode mode = device->getDepthVideoMode ();
    width = mode.x_resolution_;
    height = mode.y_resolution_;
    baseline = device->getBaseline ();
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (name_ + ": cannot read its depth stream: " + oneLine (e.what ()));
  }
  if (width <= 0 || height <= 0)
    throw pcl::IOException (name_ + ": its depth stream has no image size");
  if (!(focal > 0) || !std::isfinite (focal))
    throw pcl::IOException (name_ + ": its depth stream has no field of view, so no focal length");
  info_.width = width;
  info_.height = height;
  const double f = focal;
  const double K[9] = {f, 0, (width - 1) / 2.0, 0, f, (height - 1) / 2.0, 0, 0, 1};
  std::copy (K, K + 9, info_.K);
  if (baseline > 0 && std::isfinite (baseline))
    info_.baseline_m = baseline;
  try
  {
    live_->queue.connect (*live_->grabber);
    live_->grabber->start ();
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (name_ + ": cannot start its depth stream: " + oneLine (e.what ()));
  }
}

bool
OpenNI2DeviceReader::next (DepthFrame &frame)
{
  if (delivered_ >= frames_)
    return false;
  GrabbedDepthFrame item;
  const auto deadline = std::chrono::steady_clock::now () +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration> (std::chrono::duration<double> (timeout_s_));
  if (!live_->queue.pop (item, deadline))
  {
    std::ostringstream msg;
    msg << name_ << ": no depth frame within " << timeout_s_ << " s after " << delivered_ << " of " << frames_ << " frames";
    ++delivered_; // given up, like a bad frame of the other readers
    throw pcl::IOException (msg.str ());
  }
  ++delivered_;
  if (!item.error.empty ())
    throw pcl::IOException (name_ + ": cannot copy depth frame " + std::to_string (item.index) + ": " + oneLine (item.error));
  if (item.width != info_.width || item.height != info_.height)
    throw pcl::IOException (name_ + ": frame " + std::to_string (item.index) + " is " + std::to_string (item.width) + "x" +
                            std::to_string (item.height) + " but its depth stream is " + std::to_string (info_.width) +
                            "x" + std::to_string (info_.height));
  item.moveInto (frame);
  return true;
}

std::size_t
OpenNI2DeviceReader::droppedFrames () const
{
  return live_->queue.dropped ();
}

#else // HAVE_OPENNI2

struct OpenNI2DeviceReader::Live
{};

OpenNI2DeviceReader::OpenNI2DeviceReader (const std::string &uri, std::size_t frames, double timeout_s)
  : name_ (uri), frames_ (frames), timeout_s_ (timeout_s)
{
  throw pcl::IOException ("OpenNI2 device '" + uri + "': cannot open it: this PCL was built without OpenNI2");
}

bool
OpenNI2DeviceReader::next (DepthFrame &)
{
  return false;
}

std::size_t
OpenNI2DeviceReader::droppedFrames () const
{
  return 0;
}

#endif // HAVE_OPENNI2

OpenNI2DeviceReader::~OpenNI2DeviceReader () = default;

} // namespace texlet
} // namespace pcl
