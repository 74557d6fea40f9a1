#include <pcl_texlet/openni2_device_reader.h>

#include <pcl/exceptions.h>
#include <pcl/pcl_config.h> // HAVE_OPENNI2

#ifdef HAVE_OPENNI2
#include <pcl/io/image_depth.h>
#include <pcl/io/openni2/openni2_device.h>
#include <pcl/io/openni2_grabber.h>

#include <OpenNI.h>
#endif

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
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
  struct Item
  {
    unsigned index = 0;
    int width = 0;
    int height = 0;
    std::vector<std::uint16_t> depth_mm;
  };

  static constexpr std::size_t kCapacity = 4;

  std::unique_ptr<pcl::io::OpenNI2Grabber> grabber;
  openni::Device announcer; ///< the device opened once before the grabber, so that OpenNI2 lists it
  bool openni_initialised = false;
  std::mutex mutex;
  std::condition_variable arrived;
  std::deque<Item> queue;
  std::size_t dropped = 0;

  ~Live ()
  {
    try
    {
      if (grabber)
        grabber->stop ();
    }
    catch (...)
    {} // nothing to report from a destructor
    grabber.reset ();
    if (announcer.isValid ())
      announcer.close ();
    if (openni_initialised)
      openni::OpenNI::shutdown ();
  }

  /** Runs on OpenNI2's listener thread. */
  void
  onDepth (const pcl::io::DepthImage::Ptr &image)
  {
    Item item;
    item.index = image->getFrameID ();
    item.width = static_cast<int> (image->getWidth ());
    item.height = static_cast<int> (image->getHeight ());
    item.depth_mm.resize (std::size_t (item.width) * item.height);
    image->fillDepthImageRaw (item.width, item.height, item.depth_mm.data ());
    {
      std::lock_guard<std::mutex> lock (mutex);
      if (queue.size () >= kCapacity)
      {
        ++dropped;
        return;
      }
      queue.push_back (std::move (item));
    }
    arrived.notify_one ();
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
    live_->grabber = std::make_unique<pcl::io::OpenNI2Grabber> (uri);
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
    Live *live = live_.get ();
    live_->grabber->registerCallback (std::function<void (const pcl::io::DepthImage::Ptr &)> (
        [live] (const pcl::io::DepthImage::Ptr &image) { live->onDepth (image); }));
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
  Live::Item item;
  {
    std::unique_lock<std::mutex> lock (live_->mutex);
    if (!live_->arrived.wait_for (lock, std::chrono::duration<double> (timeout_s_), [this] { return !live_->queue.empty (); }))
    {
      std::ostringstream msg;
      msg << name_ << ": no depth frame within " << timeout_s_ << " s after " << delivered_ << " of " << frames_ << " frames";
      ++delivered_; // given up, like a bad frame of the other readers
      throw pcl::IOException (msg.str ());
    }
    item = std::move (live_->queue.front ());
    live_->queue.pop_front ();
  }
  ++delivered_;
  if (item.width != info_.width || item.height != info_.height)
    throw pcl::IOException (name_ + ": frame " + std::to_string (item.index) + " is " + std::to_string (item.width) + "x" +
                            std::to_string (item.height) + " but its depth stream is " + std::to_string (info_.width) +
                            "x" + std::to_string (info_.height));
  char name[16];
  std::snprintf (name, sizeof (name), "%06u", item.index);
  frame.name = name;
  frame.width = item.width;
  frame.height = item.height;
  frame.depth_mm = std::move (item.depth_mm);
  frame.rgb.clear ();
  return true;
}

std::size_t
OpenNI2DeviceReader::droppedFrames () const
{
  std::lock_guard<std::mutex> lock (live_->mutex);
  return live_->dropped;
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
