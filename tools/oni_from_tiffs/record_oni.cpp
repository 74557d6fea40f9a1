/*
 * record_oni URI OUTPUT.oni FRAMES: records the depth stream (lossless) and the colour stream, if
 * any (JPEG), of an OpenNI2 device with OpenNI2's own Recorder until FRAMES depth frames have
 * arrived, then finalises the file.
 * Exit code 0 when all frames were recorded, 1 otherwise. Used by make_oni.sh, and by the tests to
 * record OpenNI2's Dummy device ("Dummy").
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
  // Colour too, where the device has it, JPEG-compressed as OpenNI2's recorders usually store it;
  // depth stays lossless.
  openni::VideoStream colour;
  if (device.hasSensor (openni::SENSOR_COLOR) && colour.create (device, openni::SENSOR_COLOR) != openni::STATUS_OK)
    return fail ("creating the colour stream");
  openni::Recorder recorder;
  if (recorder.create (argv[2]) != openni::STATUS_OK || recorder.attach (depth, false) != openni::STATUS_OK ||
      (colour.isValid () && recorder.attach (colour, true) != openni::STATUS_OK) || recorder.start () != openni::STATUS_OK)
    return fail ("starting the recorder");
  if (depth.start () != openni::STATUS_OK || (colour.isValid () && colour.start () != openni::STATUS_OK))
    return fail ("starting the streams");

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
  if (colour.isValid ())
  {
    colour.stop ();
    colour.destroy ();
  }
  device.close ();
  // No OpenNI::shutdown (): OpenNI2 2.2's Dummy driver leaves a thread running that crashes the
  // process once shutdown unloads the driver. The file is complete here; exit frees the rest.
  std::printf ("recorded %d of %d frames into %s\n", recorded, wanted, argv[2]);
  return recorded == wanted ? 0 : 1;
}
