/*
 * pcl_texlet: PCL's OpenNI2Grabber with a stop () that is safe while frames flow.
 *
 * PCL 1.13's OpenNI2Grabber::stop () stops the OpenNI2 streams without waiting for a frame
 * callback that libOpenNI2 2.2 is running on a stream's listener thread, and its destructor then
 * releases the device that callback still reads. Two failures follow under load (docs/
 * openni2_device.md, "Stopping a grabber"): the callback reads a released device, or it blocks
 * in VideoStream::readFrame on a frame holder that stop () emptied, until libOpenNI2 cancels the
 * thread while destroying the stream, and the cancelled callback destroys the stream a second time.
 */
#pragma once

#include <pcl/pcl_config.h> // HAVE_OPENNI2

#ifdef HAVE_OPENNI2

#include <pcl/io/openni2_grabber.h>

#include <memory>
#include <string>

namespace pcl
{
namespace texlet
{

/** \brief pcl::io::OpenNI2Grabber whose stop () and destructor first wait for the frame callbacks
  * in flight, and whose stream callbacks never wait for a frame that is not there.
  *
  * Every stream callback of the grabber (depth, colour, IR) passes a gate: stop () closes it, so
  * that no callback starts after it, and waits until those that had started have returned; only
  * then does it stop the OpenNI2 streams. A callback that OpenNI2 wakes with no frame in the
  * stream's holder (OpenNI2 replaced a frame that was not read yet, so one wake-up is left over)
  * returns at once, instead of blocking in readFrame until the next frame, which after stop ()
  * never comes.
  *
  * Clouds and images are PCL's own: the gate calls OpenNI2Grabber's frame processing unchanged.
  * Like any callback interface, stop () must not be called from inside a grabber callback, and a
  * callback must not wait on the thread that calls stop ().
  */
class GuardedOpenNI2Grabber : public pcl::io::OpenNI2Grabber
{
public:
  /** \brief Opens the device as pcl::io::OpenNI2Grabber does (same arguments, same exceptions). */
  explicit GuardedOpenNI2Grabber (const std::string &device_id = "", const Mode &depth_mode = OpenNI_Default_Mode,
                                  const Mode &image_mode = OpenNI_Default_Mode);

  /** \brief Stops as stop () does, then lets OpenNI2Grabber release the device. Never throws. */
  ~GuardedOpenNI2Grabber () noexcept override;

  /** \brief Opens the gate, then starts the streams the registered callbacks need. */
  void
  start () override;

  /** \brief Closes the gate, waits for the callbacks in flight to return, then stops the streams. */
  void
  stop () override;

private:
  struct Gate;
  std::shared_ptr<Gate> gate_; ///< shared with the stream callbacks, which outlive this object's members
};

} // namespace texlet
} // namespace pcl

#endif // HAVE_OPENNI2
