/*
 * pcl_texlet_record: records an OpenNI2 device to an .oni file with OpenNI2's own Recorder.
 *
 *   pcl_texlet_record [--device URI] --frames N OUTPUT.oni
 *
 * The device is any OpenNI2 device: a physical sensor (the first one without --device), or the
 * simulated Kinect of pcl_texlet's OpenNI2 driver (docs/openni2_device.md), e.g.
 * --device 'pcltexlet:sim=plane;effects=vertical_stripes;seed=7'. Depth is recorded lossless, colour
 * (where the device has it, unless --no-colour) JPEG-compressed, as OpenNI2's tools record them.
 * Recording stops once N depth frames have arrived; every wait for a frame is bounded by
 * --timeout. The file is written under a temporary name in OUTPUT's folder and renamed when
 * complete, so a failed run leaves no file.
 */
#include "common/app_main.h"

#include <pcl_texlet/common/atomic_file.h>

#include <OpenNI.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>

namespace fs = std::filesystem;
using pcl_texlet_app::InputError;

namespace
{

/** OpenNI2's last error on one line. */
std::string
openniError ()
{
  // OpenNI2 indents and breaks its messages: one line, single spaces.
  std::string text;
  for (const char *c = openni::OpenNI::getExtendedError (); *c; ++c)
  {
    const bool space = *c == ' ' || *c == '\t' || *c == '\n' || *c == '\r';
    if (!space)
      text += *c;
    else if (!text.empty () && text.back () != ' ')
      text += ' ';
  }
  while (!text.empty () && text.back () == ' ')
    text.pop_back ();
  return text.empty () ? "no reason given" : text;
}

int
run (int argc, char **argv)
{
  std::string device_uri;
  std::string output;
  int frames = 0;
  double timeout_s = 5.0;
  bool no_colour = false;
  bool quiet = false;
  std::string size;

  CLI::App app {"Record an OpenNI2 device (a sensor, or pcl_texlet's simulated Kinect) to an .oni file"};
  app.add_option ("OUTPUT", output, ".oni file to write")->required ();
  app.add_option ("-d,--device", device_uri, "OpenNI2 device URI (default: the first device), e.g. "
                                             "'pcltexlet:sim=plane;seed=1' or 'pcltexlet:recording=FOLDER;loop=0'");
  app.add_option ("-n,--frames", frames, "depth frames to record")->required ();
  app.add_option ("--timeout", timeout_s, "longest wait for one frame, seconds")->capture_default_str ();
  app.add_option ("--size", size, "depth (and colour) image size WIDTHxHEIGHT at 30 Hz, e.g. 320x240 (default: the "
                                  "device's)");
  app.add_flag ("--no-colour", no_colour, "record depth only");
  app.add_flag ("-q,--quiet", quiet, "no progress lines");
  if (!pcl_texlet_app::parseCommandLine (app, argc, argv))
    return 0;
  if (frames <= 0)
    throw InputError ("--frames must be positive, got " + std::to_string (frames));
  if (!(timeout_s > 0) || timeout_s > 3600)
    throw InputError ("--timeout must be in (0, 3600] seconds");
  if (fs::path (output).extension () != ".oni")
    throw InputError ("output '" + output + "' must end in .oni (OpenNI2 plays only files named *.oni)");
  std::error_code ec;
  const fs::path folder = fs::absolute (output).parent_path ();
  if (!fs::is_directory (folder, ec))
    throw InputError ("output folder '" + folder.string () + "' does not exist");
  const std::string device_name = device_uri.empty () ? "the first OpenNI2 device" : "OpenNI2 device '" + device_uri + "'";

  if (openni::OpenNI::initialize () != openni::STATUS_OK)
    throw InputError ("cannot initialise OpenNI2: " + openniError ());
  openni::Device device;
  if (device.open (device_uri.empty () ? openni::ANY_DEVICE : device_uri.c_str ()) != openni::STATUS_OK)
    throw InputError ("cannot open " + device_name + ": " + openniError ());
  openni::VideoStream depth;
  if (!device.hasSensor (openni::SENSOR_DEPTH) || depth.create (device, openni::SENSOR_DEPTH) != openni::STATUS_OK)
    throw InputError (device_name + " has no depth stream: " + openniError ());
  openni::VideoStream colour;
  if (!no_colour && device.hasSensor (openni::SENSOR_COLOR) && colour.create (device, openni::SENSOR_COLOR) != openni::STATUS_OK)
    throw InputError ("cannot open the colour stream of " + device_name + ": " + openniError ());

  if (!size.empty ())
  {
    int width = 0, height = 0;
    char x = 0, rest = 0;
    if (std::sscanf (size.c_str (), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' || width <= 0 || height <= 0)
      throw InputError ("--size '" + size + "' is not WIDTHxHEIGHT");
    for (openni::VideoStream *stream : {&depth, &colour})
    {
      if (!stream->isValid ())
        continue;
      const openni::Array<openni::VideoMode> &modes = stream->getSensorInfo ().getSupportedVideoModes ();
      bool set = false;
      for (int i = 0; i < modes.getSize () && !set; ++i)
        if (modes[i].getResolutionX () == width && modes[i].getResolutionY () == height && modes[i].getFps () == 30 &&
            modes[i].getPixelFormat () == stream->getVideoMode ().getPixelFormat ())
          set = stream->setVideoMode (modes[i]) == openni::STATUS_OK;
      if (!set)
        throw InputError (device_name + " offers no " + size + " mode at 30 Hz" +
                          (stream == &colour ? " for colour (try --no-colour)" : ""));
    }
  }

  // OpenNI2 plays and counts only files named *.oni: the temporary keeps the extension.
  pcl::texlet::AtomicFile partial ((folder / fs::path (output).filename ()).string ());
  openni::Recorder recorder;
  if (recorder.create (partial.temporaryPath ().c_str ()) != openni::STATUS_OK || recorder.attach (depth, false) != openni::STATUS_OK ||
      (colour.isValid () && recorder.attach (colour, true) != openni::STATUS_OK) || recorder.start () != openni::STATUS_OK)
    throw InputError ("cannot record into '" + output + "': " + openniError ());
  // Recorder::start () only queues the start for the recorder's thread, which drops frames that
  // arrive before it has started: give it a moment before the first frame can come.
  std::this_thread::sleep_for (std::chrono::milliseconds (200));
  if (depth.start () != openni::STATUS_OK || (colour.isValid () && colour.start () != openni::STATUS_OK))
    throw InputError ("cannot start the streams of " + device_name + ": " + openniError ());

  int recorded = 0;
  int last_index = -1;
  std::string failure;
  while (recorded < frames)
  {
    openni::VideoStream *streams[] = {&depth};
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream (streams, 1, &ready, static_cast<int> (timeout_s * 1000)) != openni::STATUS_OK)
    {
      // A device that plays a recording once falls silent after its last frame, and this loop
      // may have missed reading its first: the file's count below decides.
      if (recorded > 0)
        break;
      failure = "no depth frame from " + device_name + " within " + std::to_string (timeout_s) + " s after " +
                std::to_string (recorded) + " of " + std::to_string (frames) + " frames";
      break;
    }
    openni::VideoFrameRef frame;
    if (depth.readFrame (&frame) != openni::STATUS_OK)
    {
      failure = "cannot read a depth frame of " + device_name + ": " + openniError ();
      break;
    }
    if (frame.getFrameIndex () == last_index)
      continue;
    // The recorder stores every frame the stream gets; one read may come after two of them
    // (devices number frames consecutively), so the frames recorded are counted by index.
    recorded += last_index >= 0 && frame.getFrameIndex () > last_index ? frame.getFrameIndex () - last_index : 1;
    last_index = frame.getFrameIndex ();
    if (!quiet)
      std::cout << "frame " << recorded << "/" << frames << ": index " << frame.getFrameIndex () << ", "
                << frame.getWidth () << "x" << frame.getHeight () << std::endl;
  }
  const bool had_colour = colour.isValid ();
  // The streams stop first. libOpenNI2 hands a frame to the recorder on the device's frame thread
  // holding the stream's recorder lock, and then takes the recorder's stream lock; destroying the
  // recorder takes those two the other way round. A frame in flight then can deadlock both (the
  // recorder's thread holds its stream lock while it writes). A stopped stream of a device whose
  // stop waits for the frame it is handing out (the simulated device's does) has none in flight.
  depth.stop ();
  if (colour.isValid ())
    colour.stop ();
  // Stopping and destroying the recorder writes the frame count and seek table.
  recorder.stop ();
  recorder.destroy ();
  depth.destroy ();
  if (colour.isValid ())
    colour.destroy ();
  device.close ();
  // No OpenNI::shutdown (): OpenNI2 2.2 can crash unloading drivers whose threads still run
  // (its Dummy driver's do); the file is complete here and exit frees the rest.
  if (!failure.empty ())
    throw InputError (failure);

  // The file's own count is the truth: the reads above can miss a frame the recorder stored.
  int stored = -1;
  {
    openni::Device file;
    openni::VideoStream stream;
    if (file.open (partial.temporaryPath ().c_str ()) == openni::STATUS_OK && stream.create (file, openni::SENSOR_DEPTH) == openni::STATUS_OK &&
        file.getPlaybackControl ())
      stored = file.getPlaybackControl ()->getNumberOfFrames (stream);
    if (stream.isValid ())
      stream.destroy ();
    if (file.isValid ())
      file.close ();
  }
  if (stored < frames)
    throw InputError ("the recording '" + output + "' holds " + std::to_string (stored) + " depth frames, not " +
                      std::to_string (frames) + ": OpenNI2's recorder lost frames");
  partial.commit ();
  if (!quiet)
    std::cout << "recorded " << stored << " depth frames" << (had_colour ? " and their colour" : "") << " into "
              << output << std::endl;
  return 0;
}

} // namespace

int
main (int argc, char **argv)
{
  return pcl_texlet_app::runApp ("pcl_texlet_record", run, argc, argv);
}
