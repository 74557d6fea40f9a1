#include <pcl_texlet/io/guarded_openni2_grabber.h>

#ifdef HAVE_OPENNI2

#include <pcl/io/openni2/openni2_device.h>

#include <OpenNI.h>

#include <condition_variable>
#include <mutex>

namespace pcl
{
namespace texlet
{

namespace
{

/** \brief True if \a stream's frame holder has a frame, so that readFrame returns at once.
  *
  * OpenNI2 2.2 has no peek: a wait of zero milliseconds looks at the holder. (Where it is empty,
  * the wait also "pokes" the device, which only a file played in manual mode heeds.)
  */
bool
hasFrame (openni::VideoStream &stream)
{
  openni::VideoStream *streams[] = {&stream};
  int ready = -1;
  return openni::OpenNI::waitForAnyStream (streams, 1, &ready, 0) == openni::STATUS_OK;
}

} // namespace

/** \brief Counts the stream callbacks in flight; closed, it lets none start. */
struct GuardedOpenNI2Grabber::Gate
{
  std::mutex mutex;
  std::condition_variable idle;
  int in_flight = 0;
  bool open = false;

  /** \brief True (and counted) if a callback may run now. */
  bool
  enter ()
  {
    std::lock_guard<std::mutex> lock (mutex);
    if (!open)
      return false;
    ++in_flight;
    return true;
  }

  void
  leave ()
  {
    std::lock_guard<std::mutex> lock (mutex);
    if (--in_flight == 0)
      idle.notify_all ();
  }

  void
  openGate ()
  {
    std::lock_guard<std::mutex> lock (mutex);
    open = true;
  }

  /** \brief Runs \a process (a stream callback) if the gate is open and \a stream has a frame. */
  template <typename Process> void
  run (openni::VideoStream &stream, Process process)
  {
    if (!enter ())
      return;
    struct Leave
    {
      Gate &gate;
      ~Leave () { gate.leave (); }
    } leave {*this};
    if (hasFrame (stream))
      process ();
  }

  /** \brief No callback starts after this; returns once the started ones have returned. */
  void
  closeAndDrain ()
  {
    std::unique_lock<std::mutex> lock (mutex);
    open = false;
    idle.wait (lock, [this] { return in_flight == 0; });
  }
};

GuardedOpenNI2Grabber::GuardedOpenNI2Grabber (const std::string &device_id, const Mode &depth_mode, const Mode &image_mode)
  : OpenNI2Grabber (device_id, depth_mode, image_mode), gate_ (std::make_shared<Gate> ())
{
  // Replaces the callbacks OpenNI2Grabber's constructor set; no stream has started, so none runs.
  // They hold the gate, not this object: a left-over wake-up after the destructor finds it closed.
  const std::shared_ptr<Gate> gate = gate_;
  device_->setDepthCallback ([gate, this] (openni::VideoStream &stream) {
    gate->run (stream, [&] { processDepthFrame (stream); });
  });
  device_->setColorCallback ([gate, this] (openni::VideoStream &stream) {
    gate->run (stream, [&] { processColorFrame (stream); });
  });
  device_->setIRCallback ([gate, this] (openni::VideoStream &stream) {
    gate->run (stream, [&] { processIRFrame (stream); });
  });
}

GuardedOpenNI2Grabber::~GuardedOpenNI2Grabber () noexcept
{
  try
  {
    stop ();
  }
  catch (...)
  {} // a destructor reports nothing; the gate is closed either way, OpenNI2Grabber stops again
  gate_->closeAndDrain ();
}

void
GuardedOpenNI2Grabber::start ()
{
  gate_->openGate ();
  OpenNI2Grabber::start ();
}

void
GuardedOpenNI2Grabber::stop ()
{
  gate_->closeAndDrain ();
  OpenNI2Grabber::stop ();
}

} // namespace texlet
} // namespace pcl

#endif // HAVE_OPENNI2
