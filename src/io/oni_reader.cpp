#include <pcl_texlet/io/oni_reader.h>

#include <pcl/exceptions.h>
#include <pcl/pcl_config.h> // HAVE_OPENNI2

#ifdef HAVE_OPENNI2
#include "grabber_depth_queue.h"

#include <pcl_texlet/io/guarded_openni2_grabber.h>

#include <pcl/io/openni2/openni2_device.h>

#include <OpenNI.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

#include "reader_util.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

// OpenNI2's player runs in manual mode and releases one record per wait of the reader's own
// streams, so that no depth frame replaces another in the grabber's stream before its callback
// has read it (why, and what else OpenNI2's file player needs: docs/openni2_device.md, "Playing
// .oni files through PCL's grabber").

#ifdef HAVE_OPENNI2

/** \brief How long OpenNI2's file player gets, once every stream of a file is stopped, to finish
  * a walk of its stream list in which it may have been preempted (several scheduling periods of a
  * loaded machine; the player itself turns every 10 ms).
  */
constexpr std::chrono::milliseconds kOniFilePlayerSettle {50};

/** \brief The grabber, the reader's own handle on its device and streams, and the queue between. */
struct OniReader::Playback
{
  bool openni_initialised = false;
  openni::Device control;     ///< the file again (the grabber's device): playback control
  openni::VideoStream depth;  ///< the reader's depth stream: sees each depth record first
  openni::VideoStream colour; ///< created when the file has colour, to see its records
  openni::VideoStream ir;     ///< created when the file has IR, to see its records
  GrabberDepthQueue queue {2}; ///< one frame per record released, so one at most; the rest is slack
  std::unique_ptr<GuardedOpenNI2Grabber> grabber;

  ~Playback ()
  {
    queue.close ();
    if (grabber)
    {
      try
      {
        grabber->stop (); // waits for its callbacks in flight
      }
      catch (...)
      {} // nothing to report from a destructor; the streams are destroyed below either way
    }
    // Every stream stopped, and the player given time to finish a walk of its stream list, before
    // any is destroyed: OpenNI2's player walks that list without its lock, and destroying a stream
    // frees its entry (docs/openni2_device.md, "The file player's crash").
    for (openni::VideoStream *stream : {&depth, &colour, &ir})
      if (stream->isValid ())
        stream->stop ();
    std::this_thread::sleep_for (kOniFilePlayerSettle);
    for (openni::VideoStream *stream : {&depth, &colour, &ir})
      if (stream->isValid ())
        stream->destroy ();
    grabber.reset ();
    if (control.isValid ())
      control.close ();
    if (openni_initialised)
      openni::OpenNI::shutdown ();
  }

  /** \brief The reader's started streams, depth first. */
  std::vector<openni::VideoStream *>
  watchers ()
  {
    std::vector<openni::VideoStream *> streams;
    for (openni::VideoStream *stream : {&depth, &colour, &ir})
      if (stream->isValid ())
        streams.push_back (stream);
    return streams;
  }

  /** \brief Releases records one at a time until one is a depth frame, and returns the grabber's
    * copy of it.
    * \throws pcl::IOException naming frame \a number of \a size when it does not come within
    *         \a timeout_s seconds, or the grabber's frame is not the released one.
    */
  GrabbedDepthFrame
  take (const std::string &what, double timeout_s, std::size_t number, std::size_t size);
};

namespace
{

/** \brief Clears the calling thread's OpenNI2 wake-up event (set by any frame of any stream since
  * its last wait), so that the next wait pokes a manual-mode player once: a wait on no stream
  * for zero milliseconds consumes the event and pokes no device.
  */
void
clearOpenNI2WakeUp ()
{
  openni::VideoStream *none[] = {nullptr};
  int ready = -1;
  openni::OpenNI::waitForAnyStream (none, 1, &ready, 0);
}

} // namespace

GrabbedDepthFrame
OniReader::Playback::take (const std::string &what, double timeout_s, std::size_t number, std::size_t size)
{
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline =
      Clock::now () + std::chrono::duration_cast<Clock::duration> (std::chrono::duration<double> (timeout_s));
  const auto lost = [&] {
    std::ostringstream msg;
    msg << what << "frame " << number << " of " << size << " did not arrive within " << timeout_s
        << " s (truncated or corrupt recording?)";
    return pcl::IOException (msg.str ());
  };
  std::vector<openni::VideoStream *> streams = watchers ();
  for (;;)
  {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds> (deadline - Clock::now ()).count ();
    if (left <= 0)
      throw lost ();
    clearOpenNI2WakeUp ();
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream (streams.data (), static_cast<int> (streams.size ()), &ready,
                                          static_cast<int> (left)) != openni::STATUS_OK ||
        ready < 0)
      throw lost ();
    openni::VideoFrameRef record;
    if (streams[ready]->readFrame (&record) != openni::STATUS_OK || !record.isValid ())
      throw pcl::IOException (what + "cannot read frame " + std::to_string (number) + " of " + std::to_string (size) +
                              " (" + openni::OpenNI::getExtendedError () + ")");
    if (streams[ready] != &depth)
      continue; // a colour or IR record: the reader plays depth only
    const unsigned index = static_cast<unsigned> (record.getFrameIndex ());
    record.release ();
    // The grabber's stream received the same record right after the reader's; its callback
    // copies it into the queue. No record is released before it is there.
    GrabbedDepthFrame frame;
    if (!queue.pop (frame, deadline))
      throw pcl::IOException (what + "the grabber did not deliver depth frame " + std::to_string (index) + " within " +
                              std::to_string (timeout_s) + " s");
    if (frame.index != index)
      throw pcl::IOException (what + "the grabber delivered depth frame " + std::to_string (frame.index) +
                              " where OpenNI2 played frame " + std::to_string (index));
    return frame;
  }
}

OniReader::OniReader (const std::string &file, double timeout_s) : file_ (file), timeout_s_ (timeout_s)
{
  const std::string what = ".oni file '" + file + "': ";
  if (!(timeout_s > 0) || !std::isfinite (timeout_s))
    throw pcl::BadArgumentException (what + "the frame timeout must be positive and finite");
  std::error_code ec;
  // Checked here: for a path that does not exist the grabber would open any connected camera.
  if (!fs::exists (file, ec))
    throw pcl::IOException (what + "does not exist");
  if (!fs::is_regular_file (file, ec))
    throw pcl::IOException (what + "is not a file");
  if (detail::lowerExtension (file) != ".oni")
    throw pcl::IOException (what + "is not an .oni file (OpenNI2 plays only files named *.oni)");

  playback_ = std::make_unique<Playback> ();
  Playback &p = *playback_;
  p.openni_initialised = openni::OpenNI::initialize () == openni::STATUS_OK;
  if (!p.openni_initialised)
    throw pcl::IOException (what + "cannot initialise OpenNI2 (" + detail::description (std::runtime_error (openni::OpenNI::getExtendedError ())) + ")");
  const auto openniError = [] { return detail::description (std::runtime_error (openni::OpenNI::getExtendedError ())); };
  if (p.control.open (file.c_str ()) != openni::STATUS_OK)
    throw pcl::IOException (what + "OpenNI2 cannot play it: not an .oni recording, or truncated or corrupt (" +
                            openniError () + ")");
  if (!p.control.isFile ())
    throw pcl::IOException (what + "OpenNI2 did not open it as a recording");
  if (!p.control.hasSensor (openni::SENSOR_DEPTH) || p.depth.create (p.control, openni::SENSOR_DEPTH) != openni::STATUS_OK)
    throw pcl::IOException (what + "cannot open its depth stream (" + openniError () + ")");
  OniCropping cropping;
  if (p.depth.getProperty (ONI_STREAM_PROPERTY_CROPPING, &cropping) != openni::STATUS_OK)
    throw pcl::IOException (what + "its depth stream was recorded without the cropping property, and OpenNI2's "
                                   "OniFile driver plays no frame of such a stream (recordings of OpenNI2's Dummy "
                                   "device are like this)");
  const openni::VideoMode mode = p.depth.getVideoMode ();
  if (mode.getPixelFormat () != openni::PIXEL_FORMAT_DEPTH_1_MM)
    throw pcl::IOException (what + "depth pixel format " + std::to_string (mode.getPixelFormat ()) +
                            " is not millimetres (PIXEL_FORMAT_DEPTH_1_MM)");
  if (mode.getResolutionX () <= 0 || mode.getResolutionY () <= 0)
    throw pcl::IOException (what + "depth stream has no image size");
  if (p.control.hasSensor (openni::SENSOR_COLOR) && p.colour.create (p.control, openni::SENSOR_COLOR) != openni::STATUS_OK)
    throw pcl::IOException (what + "cannot open its colour stream (" + openniError () + ")");
  if (p.control.hasSensor (openni::SENSOR_IR) && p.ir.create (p.control, openni::SENSOR_IR) != openni::STATUS_OK)
    throw pcl::IOException (what + "cannot open its IR stream (" + openniError () + ")");

  // The grabber's streams come after the reader's, so each frame reaches the reader's first.
  try
  {
    p.grabber = std::make_unique<GuardedOpenNI2Grabber> (file);
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (what + "OpenNI2 cannot play it: not an .oni recording, or truncated or corrupt (" +
                            detail::description (e) + ")");
  }
  int frames = 0;
  float focal = 0;
  try
  {
    const pcl::io::openni2::OpenNI2Device::Ptr device = p.grabber->getDevice ();
    frames = device->getDepthFrameCount ();
    focal = device->getDepthFocalLength ();
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (what + "cannot read its depth stream (" + detail::description (e) + ")");
  }
  if (frames <= 0)
    throw pcl::IOException (what + "has no depth frame count (" + std::to_string (frames) +
                            "): not a finalised recording (was its recorder stopped?)");
  if (!(focal > 0) || !std::isfinite (focal))
    throw pcl::IOException (what + "its depth stream has no field of view, so no focal length");
  info_.width = mode.getResolutionX ();
  info_.height = mode.getResolutionY ();
  const double f = focal;
  const double K[9] = {f, 0, (info_.width - 1) / 2.0, 0, f, (info_.height - 1) / 2.0, 0, 0, 1};
  std::copy (K, K + 9, info_.K);
  size_ = static_cast<std::size_t> (frames);

  // After the grabber's device set real-time speed, before any stream starts the player.
  openni::PlaybackControl *control = p.control.getPlaybackControl ();
  if (!control || control->setRepeatEnabled (false) != openni::STATUS_OK || control->setSpeed (-1.0f) != openni::STATUS_OK)
    throw pcl::IOException (what + "cannot switch playback to manual without repeat (" + openniError () + ")");
  for (openni::VideoStream *stream : p.watchers ())
    if (stream->start () != openni::STATUS_OK)
      throw pcl::IOException (what + "cannot start playback (" + openniError () + ")");
  try
  {
    p.queue.connect (*p.grabber);
    p.grabber->start ();
  }
  catch (const std::exception &e)
  {
    throw pcl::IOException (what + "cannot start playback (" + detail::description (e) + ")");
  }
}

bool
OniReader::next (DepthFrame &frame)
{
  if (delivered_ >= size_)
    return false;
  const std::string what = ".oni file '" + file_ + "': ";
  const std::size_t number = ++delivered_; // a frame that fails is given up, like a bad frame of the other readers
  GrabbedDepthFrame item = playback_->take (what, timeout_s_, number, size_);
  if (delivered_ == size_)
    playback_.reset (); // the last frame: OpenNI2's player, at the end of the file, would spin until closed

  // OpenNI2's recorder numbers frames 1, 2, 3, ...: a gap means playback lost frames.
  const unsigned previous = last_index_;
  last_index_ = item.index;
  if (item.index != previous + 1)
    throw pcl::IOException (what + "frame index " + std::to_string (item.index) + " followed " + std::to_string (previous) +
                            ": playback lost or reordered frames");
  if (!item.error.empty ())
    throw pcl::IOException (what + "cannot copy depth frame " + std::to_string (item.index) + " (" +
                            detail::description (std::runtime_error (item.error)) + ")");
  if (item.width != info_.width || item.height != info_.height)
    throw pcl::IOException (what + "frame " + std::to_string (item.index) + " is " + detail::sizeText (item.width, item.height) +
                            " but the depth stream is " + detail::sizeText (info_.width, info_.height));
  const std::size_t expected_bytes = std::size_t (item.width) * item.height * sizeof (std::uint16_t);
  if (item.bytes < 0 || std::size_t (item.bytes) < expected_bytes)
    throw pcl::IOException (what + "frame " + std::to_string (item.index) + " holds " + std::to_string (item.bytes) +
                            " bytes of depth, expected " + std::to_string (expected_bytes) + ": corrupt recording");
  item.moveInto (frame);
  return true;
}

#else // HAVE_OPENNI2

struct OniReader::Playback
{};

OniReader::OniReader (const std::string &file, double timeout_s) : file_ (file), timeout_s_ (timeout_s)
{
  throw pcl::IOException (".oni file '" + file + "': cannot play it: this PCL was built without OpenNI2");
}

bool
OniReader::next (DepthFrame &)
{
  return false;
}

#endif // HAVE_OPENNI2

OniReader::~OniReader () = default;

} // namespace texlet
} // namespace pcl
