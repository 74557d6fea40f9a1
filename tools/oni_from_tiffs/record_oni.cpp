/*
 * record_oni URI OUTPUT.oni FRAMES: records the depth stream of an OpenNI2 device with OpenNI2's
 * own Recorder (lossless) until FRAMES frames have arrived, then finalises the file.
 * Exit code 0 when all frames were recorded, 1 otherwise. Used by make_oni.sh.
 */
#include <OpenNI.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>

int
main (int argc, char **argv)
{
  if (argc != 4 || std::atoi (argv[3]) <= 0)
  {
    std::fprintf (stderr, "usage: record_oni URI OUTPUT.oni FRAMES\n");
    return 2;
  }
  const auto fail = [] (const char *step) {
    std::fprintf (stderr, "record_oni: %s failed: %s\n", step, openni::OpenNI::getExtendedError ());
    return 1;
  };
  if (openni::OpenNI::initialize () != openni::STATUS_OK)
    return fail ("initialising OpenNI2");
  openni::Device device;
  if (device.open (argv[1]) != openni::STATUS_OK)
    return fail ("opening the device");
  openni::VideoStream depth;
  if (depth.create (device, openni::SENSOR_DEPTH) != openni::STATUS_OK)
    return fail ("creating the depth stream");
  openni::Recorder recorder;
  if (recorder.create (argv[2]) != openni::STATUS_OK || recorder.attach (depth, false) != openni::STATUS_OK ||
      recorder.start () != openni::STATUS_OK)
    return fail ("starting the recorder");
  if (depth.start () != openni::STATUS_OK)
    return fail ("starting the depth stream");

  const int wanted = std::atoi (argv[3]);
  int recorded = 0;
  for (; recorded < wanted; ++recorded)
  {
    openni::VideoStream *streams[] = {&depth};
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream (streams, 1, &ready, 3000) != openni::STATUS_OK)
      break;
    openni::VideoFrameRef frame;
    if (depth.readFrame (&frame) != openni::STATUS_OK)
      break;
    std::printf ("frame %d: %dx%d, centre depth %u mm\n", frame.getFrameIndex (), frame.getWidth (), frame.getHeight (),
                 static_cast<const std::uint16_t *> (frame.getData ())[frame.getHeight () / 2 * frame.getWidth () +
                                                                        frame.getWidth () / 2]);
  }
  // Stopping and destroying the recorder writes the frame count and seek table.
  recorder.stop ();
  recorder.destroy ();
  depth.stop ();
  depth.destroy ();
  device.close ();
  openni::OpenNI::shutdown ();
  std::printf ("recorded %d of %d frames into %s\n", recorded, wanted, argv[2]);
  return recorded == wanted ? 0 : 1;
}
