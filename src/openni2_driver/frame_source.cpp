#include "frame_source.h"

#include <pcl_texlet/io/open_recording.h>
#include <pcl_texlet/simulation/simulation_config.h>

#include <pcl/exceptions.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace pcl
{
namespace texlet
{
namespace oni_device
{

namespace
{

[[noreturn]] void
badUri (const std::string &uri, const std::string &problem)
{
  throw pcl::BadArgumentException ("device URI '" + uri + "': " + problem);
}

double
parseNumber (const std::string &uri, const std::string &key, const std::string &text)
{
  char *end = nullptr;
  errno = 0;
  const double value = std::strtod (text.c_str (), &end);
  if (text.empty () || *end != '\0' || errno != 0 || !std::isfinite (value))
    badUri (uri, key + "=" + text + " is not a number");
  return value;
}

std::uint64_t
parseCount (const std::string &uri, const std::string &key, const std::string &text, std::uint64_t max)
{
  const double value = parseNumber (uri, key, text);
  if (value < 0 || value != std::floor (value) || value > double (max))
    badUri (uri, key + "=" + text + " is not a whole number from 0 to " + std::to_string (max));
  return static_cast<std::uint64_t> (value);
}

bool
parseFlag (const std::string &uri, const std::string &key, const std::string &text)
{
  if (text == "1" || text == "true" || text == "on")
    return true;
  if (text == "0" || text == "false" || text == "off")
    return false;
  badUri (uri, key + "=" + text + " is not 0 or 1");
}

std::vector<std::string>
split (const std::string &text, char separator)
{
  std::vector<std::string> parts;
  std::string::size_type start = 0;
  while (true)
  {
    const auto end = text.find (separator, start);
    parts.push_back (text.substr (start, end - start));
    if (end == std::string::npos)
      return parts;
    start = end + 1;
  }
}

std::string
sizeText (int width, int height)
{
  return std::to_string (width) + "x" + std::to_string (height);
}

/** A recording played from the reader openRecording () gives, reopened to go back. */
class RecordingSource : public FrameSource
{
public:
  RecordingSource (const DeviceUri &uri) : uri_ (uri)
  {
    // Read it through once: every frame must be readable and of one size, so that the device
    // never has to change its video mode or stop half-way.
    RecordingReader::Ptr reader = open ();
    info_ = reader->cameraInfo ();
    DepthFrame frame;
    bool all_colour = true;
    while (reader->next (frame))
    {
      if (count_ == 0 && (info_.width <= 0 || info_.height <= 0))
      {
        info_.width = frame.width;
        info_.height = frame.height;
      }
      if (frame.width != info_.width || frame.height != info_.height)
        throw pcl::IOException ("recording '" + uri_.recording + "': frame " + std::to_string (count_ + 1) + " ('" +
                                frame.name + "') is " + sizeText (frame.width, frame.height) + ", the recording is " +
                                sizeText (info_.width, info_.height) + ": an OpenNI2 stream has one frame size");
      all_colour = all_colour && frame.rgb.size () == std::size_t (3) * frame.width * frame.height;
      ++count_;
    }
    if (count_ == 0)
      throw pcl::IOException ("recording '" + uri_.recording + "' has no frame");
    colour_ = uri_.colour && all_colour;
    reader_ = open (); // ready for the first frame, which is due a period after the stream starts
  }

  std::vector<SourceMode>
  modes () const override
  {
    return {SourceMode {info_.width, info_.height}};
  }

  CameraInfo
  cameraInfo (const SourceMode &) const override { return info_; }

  bool
  hasColour () const override { return colour_; }

  std::uint64_t
  frameCount () const override
  {
    if (uri_.frames > 0)
      return uri_.loop ? uri_.frames : std::min<std::uint64_t> (uri_.frames, count_);
    return uri_.loop ? 0 : count_;
  }

  void
  frame (std::uint64_t index, const SourceMode &, DepthFrame &frame) override
  {
    const std::uint64_t wanted = index % count_;
    if (!reader_ || wanted < position_)
    {
      reader_ = open ();
      position_ = 0;
    }
    for (; position_ <= wanted; ++position_)
      if (!reader_->next (frame))
        throw pcl::IOException ("recording '" + uri_.recording + "' ended at frame " + std::to_string (position_) +
                                ", it had " + std::to_string (count_) + " when the device was opened");
    if (frame.width != info_.width || frame.height != info_.height)
      throw pcl::IOException ("recording '" + uri_.recording + "': frame '" + frame.name + "' is now " +
                              sizeText (frame.width, frame.height) + ", the device streams " +
                              sizeText (info_.width, info_.height));
  }

  std::string
  description () const override { return "recording " + uri_.recording; }

private:
  RecordingReader::Ptr
  open () const
  {
    if (recordingKind (uri_.recording) == RecordingKind::oni_file)
      throw pcl::IOException ("recording '" + uri_.recording + "' is an .oni file: open it by its path with "
                              "OpenNI2's own OniFile driver, not as pcltexlet:recording=");
    return openRecording (uri_.recording);
  }

  DeviceUri uri_;
  CameraInfo info_;
  std::uint64_t count_ = 0;
  bool colour_ = false;
  RecordingReader::Ptr reader_;
  std::uint64_t position_ = 0;
};

/** A simulator scene, one simulator per video mode (the sensor's intrinsics scale with it). */
class SimulatorSource : public FrameSource
{
public:
  SimulatorSource (const DeviceUri &uri) : uri_ (uri)
  {
    const auto parameter = [&] (const char *key, double fallback) {
      const auto it = uri_.scene_parameters.find (key);
      return it == uri_.scene_parameters.end () ? fallback : it->second;
    };
    if (uri_.scene == "plane")
      setup_ = sim::planeSetup (parameter ("distance", 1.5), parameter ("tilt_x", 0.0), parameter ("tilt_y", 0.0));
    else if (uri_.scene == "box")
      setup_ = sim::boxSetup (parameter ("distance", 1.2), parameter ("elevation", 40.0));
    else
      badUri (std::string (kUriPrefix) + "sim=" + uri_.scene, "unknown scene '" + uri_.scene + "' (plane or box)");

    settings_.seed = uri_.seed;
    if (!uri_.config.empty ())
      sim::loadSimulationConfig (uri_.config, settings_);
    for (const std::string &name : uri_.effects)
      sim::setEffectEnabled (settings_.effects, name, true);
    for (const std::string &assignment : uri_.assignments)
      sim::applyEffectAssignment (assignment, settings_.effects);
    settings_.base_noise = uri_.noise == "paper";
    settings_.projector_shadows = uri_.shadows;
    simulator (modes ().front ()); // fails the open for bad effect parameters
  }

  std::vector<SourceMode>
  modes () const override
  {
    return {SourceMode {640, 480}, SourceMode {320, 240}};
  }

  CameraInfo
  cameraInfo (const SourceMode &mode) const override { return simulator (mode).cameraInfo (0); }

  bool
  hasColour () const override { return false; }

  std::uint64_t
  frameCount () const override { return uri_.frames; }

  void
  frame (std::uint64_t index, const SourceMode &mode, DepthFrame &frame) override
  {
    simulator (mode).simulateFrameSerial (0, static_cast<std::uint32_t> (index), frame);
  }

  std::string
  description () const override { return "simulated " + uri_.scene; }

private:
  const sim::KinectSimulator &
  simulator (const SourceMode &mode) const
  {
    std::lock_guard<std::mutex> lock (mutex_);
    const int key = mode.width * 100000 + mode.height;
    auto it = simulators_.find (key);
    if (it == simulators_.end ())
    {
      const sim::DepthSensor model = sim::DepthSensor::kinect (mode.width, mode.height);
      // One thread: the device renders each frame on its stream's own thread.
      it = simulators_.emplace (key, std::make_unique<sim::KinectSimulator> (setup_.scene, setup_.sensors (model), settings_, 1))
               .first;
    }
    return *it->second;
  }

  DeviceUri uri_;
  sim::SceneSetup setup_;
  sim::SimulationSettings settings_;
  mutable std::mutex mutex_;
  mutable std::map<int, std::unique_ptr<sim::KinectSimulator>> simulators_;
};

} // namespace

DeviceUri
parseDeviceUri (const std::string &uri)
{
  const std::string prefix = kUriPrefix;
  if (uri.compare (0, prefix.size (), prefix) != 0)
    badUri (uri, "does not start with '" + prefix + "'");
  DeviceUri result;
  bool have_source = false;
  bool have_loop = false;
  for (const std::string &item : split (uri.substr (prefix.size ()), ';'))
  {
    if (item.empty ())
      continue;
    const auto equals = item.find ('=');
    if (equals == std::string::npos)
      badUri (uri, "'" + item + "' is not KEY=VALUE");
    const std::string key = item.substr (0, equals);
    const std::string value = item.substr (equals + 1);
    if (key == "recording" || key == "sim")
    {
      if (have_source)
        badUri (uri, "names more than one source (recording= or sim=)");
      if (value.empty ())
        badUri (uri, key + "= is empty");
      have_source = true;
      (key == "recording" ? result.recording : result.scene) = value;
    }
    else if (key == "loop")
    {
      result.loop = parseFlag (uri, key, value);
      have_loop = true;
    }
    else if (key == "colour" || key == "color")
      result.colour = parseFlag (uri, key, value);
    else if (key == "shadows")
      result.shadows = parseFlag (uri, key, value);
    else if (key == "frames")
      result.frames = parseCount (uri, key, value, 4294967295ull);
    else if (key == "seed")
      result.seed = static_cast<std::uint32_t> (parseCount (uri, key, value, 4294967295ull));
    else if (key == "distance" || key == "tilt_x" || key == "tilt_y" || key == "elevation")
      result.scene_parameters[key] = parseNumber (uri, key, value);
    else if (key == "effects")
    {
      for (const std::string &name : split (value, ','))
        if (!name.empty ())
          result.effects.push_back (name);
    }
    else if (key == "set")
      result.assignments.push_back (value);
    else if (key == "config")
      result.config = value;
    else if (key == "noise")
    {
      if (value != "paper" && value != "none")
        badUri (uri, "noise=" + value + " is not paper or none");
      result.noise = value;
    }
    else
      badUri (uri, "unknown key '" + key + "' (see docs/openni2_device.md)");
  }
  if (!have_source)
    badUri (uri, "names no source: recording=PATH or sim=plane|box");
  const bool simulated = !result.scene.empty ();
  if (simulated && have_loop)
    badUri (uri, "loop= applies to recordings; a simulator scene is endless unless frames= is given");
  if (!simulated && (!result.scene_parameters.empty () || !result.effects.empty () || !result.assignments.empty () ||
                     !result.config.empty ()))
    badUri (uri, "scene parameters, effects, set= and config= apply to sim= only");
  return result;
}

FrameSource::Ptr
openFrameSource (const std::string &uri)
{
  const DeviceUri parsed = parseDeviceUri (uri);
  if (!parsed.recording.empty ())
    return std::make_shared<RecordingSource> (parsed);
  return std::make_shared<SimulatorSource> (parsed);
}

} // namespace oni_device
} // namespace texlet
} // namespace pcl
