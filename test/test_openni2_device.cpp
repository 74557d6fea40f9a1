/*
 * The simulated Kinect as an OpenNI2 device (src/openni2_driver), on the real libOpenNI2 and
 * PCL's real OpenNI2Grabber, with no physical sensor.
 *
 * OpenNI2 (Debian 12) loads drivers only from its system driver folder. The test process moves
 * into a private mount namespace and binds a temporary folder holding the built driver and the
 * system's OniFile driver over that folder: nothing is written into system folders, and the apps
 * the tests start inherit the namespace. Where that is not permitted (not root), the tests skip
 * and say why.
 *
 * libOpenNI2 2.2 itself sometimes deadlocks in its Recorder: every app run is bounded by
 * timeout(1) and recording is retried; every wait for a frame is bounded.
 */
#include <pcl_texlet/camera/depth_image.h>
#include <pcl_texlet/io/guarded_openni2_grabber.h>
#include <pcl_texlet/io/openni2_device_reader.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/features/point_types.h>
#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/oni_reader.h>
#include <pcl_texlet/io/open_recording.h>
#include <pcl_texlet/io/png_image.h>
#include <pcl_texlet/simulation/effects.h>
#include <pcl_texlet/simulation/kinect_simulator.h>
#include <pcl_texlet/simulation/scene_setup.h>
#include <pcl_texlet/simulation/simulated_recording.h>

#include <pcl/exceptions.h>
#include <pcl/io/openni2/openni2_device.h>
#include <pcl/io/openni2_grabber.h>
#include <pcl/io/pcd_io.h>

#include <OpenNI.h>
#include <PS1080.h>

#include <gtest/gtest.h>

#include <sched.h>
#include <sys/mount.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace pcl::texlet;

namespace
{

// The simulated scenes the tests use; all are listed to the driver (PCLTEXLET_DEVICES) before
// OpenNI2 starts, since PCL's grabber opens only listed devices.
const std::string kPlaneUri = "pcltexlet:sim=plane;distance=1.2;tilt_x=20;tilt_y=-10;"
                              "effects=vertical_stripes,disparity_quantization;seed=11";
const std::string kMissingUri = "pcltexlet:recording=/nonexistent/pcl_texlet_recording";

/** The private mount namespace with the built driver; skip_reason is empty once it is ready. */
struct DriverNamespace
{
  std::string skip_reason;
  fs::path folder; ///< temporary: the driver folder and the tests' files

  DriverNamespace ()
  {
    char pattern[] = "/tmp/pcl_texlet_oni_XXXXXX";
    if (!mkdtemp (pattern))
    {
      skip_reason = "cannot make a temporary folder";
      return;
    }
    folder = pattern;
    const fs::path drivers = folder / "drivers";
    fs::create_directories (drivers);
    fs::copy_file (DRIVER_FILE, drivers / "libPclTexletDevice.so.0");
    const fs::path onifile = fs::path (SYSTEM_DRIVER_DIR) / "libOniFile.so.0";
    std::error_code ec;
    if (fs::exists (onifile, ec))
      fs::copy_file (onifile, drivers / "libOniFile.so.0");
    if (unshare (CLONE_NEWNS) != 0)
    {
      skip_reason = std::string ("a private mount namespace is not permitted here (unshare: ") + std::strerror (errno) +
                    "; run as root, as CI does): the driver cannot be put where OpenNI2 loads drivers without "
                    "writing into " SYSTEM_DRIVER_DIR;
      return;
    }
    // Private first, so that the bind below never reaches the system's mount namespace.
    if (mount ("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
        mount (drivers.c_str (), SYSTEM_DRIVER_DIR, nullptr, MS_BIND, nullptr) != 0)
    {
      skip_reason = std::string ("cannot bind the test driver folder over " SYSTEM_DRIVER_DIR ": ") + std::strerror (errno);
      return;
    }
    setenv ("PCLTEXLET_DEVICES", (kPlaneUri + "|" + kMissingUri).c_str (), 1);
  }

  ~DriverNamespace ()
  {
    std::error_code ec;
    if (!folder.empty ())
      fs::remove_all (folder, ec);
  }
};

DriverNamespace &
driverNamespace ()
{
  static DriverNamespace ns;
  return ns;
}

class OpenNI2Device : public ::testing::Test
{
protected:
  void
  SetUp () override
  {
    if (!driverNamespace ().skip_reason.empty ())
      GTEST_SKIP () << driverNamespace ().skip_reason;
    dir_ = driverNamespace ().folder / ::testing::UnitTest::GetInstance ()->current_test_info ()->name ();
    fs::create_directories (dir_);
  }

public:
  std::string
  file (const std::string &name) const { return (dir_ / name).string (); }

  /** Runs \a command (bounded by timeout(1)), stdout and stderr into files; returns the exit code. */
  int
  run (const std::string &command, std::string *err = nullptr, int limit_s = 120)
  {
    const std::string line = "timeout -s KILL " + std::to_string (limit_s) + " " + command + " > " + file ("out.log") +
                             " 2> " + file ("err.log");
    const int status = std::system (line.c_str ());
    if (err)
    {
      std::ifstream in (file ("err.log"));
      std::stringstream text;
      text << in.rdbuf ();
      *err = text.str ();
    }
    return WIFEXITED (status) ? WEXITSTATUS (status) : -1;
  }

  /** pcl_texlet_record, retried where libOpenNI2 deadlocks (killed: 137). */
  int
  record (const std::string &uri, int frames, const std::string &oni, std::string *err = nullptr)
  {
    int code = -1;
    for (int attempt = 0; attempt < 3; ++attempt)
    {
      code = run (std::string (RECORD_APP) + " -q -d '" + uri + "' -n " + std::to_string (frames) + " " + oni, err, 60);
      if (code != 137)
        break;
    }
    return code;
  }

  fs::path dir_;
};

/** The simulator the device of kPlaneUri runs, at \a width x \a height. */
sim::KinectSimulator
planeSimulator (int width, int height)
{
  const sim::SceneSetup setup = sim::planeSetup (1.2, 20, -10);
  sim::SimulationSettings settings;
  settings.seed = 11;
  sim::setEffectEnabled (settings.effects, "vertical_stripes", true);
  sim::setEffectEnabled (settings.effects, "disparity_quantization", true);
  return sim::KinectSimulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (width, height)), settings, 1);
}

std::size_t
countLines (const std::string &text)
{
  return static_cast<std::size_t> (std::count (text.begin (), text.end (), '\n'));
}

// --- PCL's grabber on the simulated device -----------------------------------------------------

class GrabberMode : public OpenNI2Device, public ::testing::WithParamInterface<int>
{};

// PCL's grabber, guarded (pcl::texlet::GuardedOpenNI2Grabber): its stop () waits for the frame
// callback in flight. PCL 1.13's own stop () does not, and under CPU load the callback crashed the
// process or blocked until libOpenNI2 cancelled it (docs/openni2_device.md, "Stopping a grabber").
TEST_P (GrabberMode, CloudsEqualTheSimulatorsDepthBackProjected)
{
  const bool vga = GetParam () == 640;
  const pcl::io::OpenNI2Grabber::Mode mode =
      vga ? pcl::io::OpenNI2Grabber::OpenNI_VGA_30Hz : pcl::io::OpenNI2Grabber::OpenNI_QVGA_30Hz;
  // Declared before the grabber, so that they outlive any callback still running while it stops.
  using Cloud = pcl::PointCloud<pcl::PointXYZ>;
  std::mutex mutex;
  std::condition_variable arrived;
  std::vector<Cloud::ConstPtr> clouds;
  GuardedOpenNI2Grabber grabber (kPlaneUri, mode, mode);
  const int width = vga ? 640 : 320, height = vga ? 480 : 240;
  const sim::KinectSimulator simulator = planeSimulator (width, height);
  const sim::DepthSensor &sensor = simulator.sensor (0);

  // What the grabber derives from the device's properties is the simulator's camera.
  EXPECT_NEAR (grabber.getDevice ()->getDepthFocalLength (), sensor.fx, 1e-3);
  EXPECT_NEAR (grabber.getDevice ()->getBaseline (), sensor.baseline_m, 1e-6);
  EXPECT_FALSE (grabber.getDevice ()->isFile ());

  grabber.registerCallback (std::function<void (const Cloud::ConstPtr &)> ([&] (const Cloud::ConstPtr &cloud) {
    std::lock_guard<std::mutex> lock (mutex);
    if (clouds.size () < 3)
      clouds.push_back (cloud);
    arrived.notify_all ();
  }));
  grabber.start ();
  {
    std::unique_lock<std::mutex> lock (mutex);
    arrived.wait_for (lock, std::chrono::seconds (20), [&] { return clouds.size () >= 3; });
  }
  grabber.stop ();
  ASSERT_EQ (clouds.size (), 3u) << "the grabber delivered too few clouds within 20 s";

  const PinholeModel camera = PinholeModel::fromCameraInfo (simulator.cameraInfo (0));
  for (const Cloud::ConstPtr &cloud : clouds)
  {
    ASSERT_TRUE (cloud->isOrganized ());
    ASSERT_EQ (int (cloud->width), width);
    ASSERT_EQ (int (cloud->height), height);
    ASSERT_GE (cloud->header.seq, 1u);
    // Frame index i + 1 is simulator frame i.
    const DepthFrame frame = simulator.simulateFrame (0, cloud->header.seq - 1);
    EXPECT_EQ (cloud->header.stamp, std::uint64_t (cloud->header.seq) * 33333u);
    Cloud expected;
    depthToCloud (frame, camera, expected);
    std::size_t valid = 0, mismatched = 0;
    double worst = 0;
    for (std::size_t i = 0; i < cloud->size (); ++i)
    {
      const pcl::PointXYZ &p = (*cloud)[i], &q = expected[i];
      if (std::isfinite (p.z) != std::isfinite (q.z))
      {
        ++mismatched;
        continue;
      }
      if (!std::isfinite (p.z))
        continue;
      ++valid;
      worst = std::max (worst, double ((p.getVector3fMap () - q.getVector3fMap ()).norm ()));
    }
    EXPECT_EQ (mismatched, 0u) << "frame " << cloud->header.seq;
    EXPECT_LT (worst, 1e-3) << "frame " << cloud->header.seq;
    EXPECT_GT (valid, cloud->size () * 9 / 10) << "frame " << cloud->header.seq;
  }
}

INSTANTIATE_TEST_SUITE_P (VgaAndQvga, GrabberMode, ::testing::Values (640, 320));

// --- the device through OpenNI2's own API ------------------------------------------------------

TEST_F (OpenNI2Device, StreamPropertiesFrameIndicesAndMirroringFollowTheCameraModel)
{
  ASSERT_EQ (openni::OpenNI::initialize (), openni::STATUS_OK);
  openni::Device device;
  ASSERT_EQ (device.open (kPlaneUri.c_str ()), openni::STATUS_OK) << openni::OpenNI::getExtendedError ();
  EXPECT_FALSE (device.hasSensor (openni::SENSOR_COLOR)); // a simulator scene has no colour
  openni::VideoStream depth;
  ASSERT_EQ (depth.create (device, openni::SENSOR_DEPTH), openni::STATUS_OK);

  const openni::Array<openni::VideoMode> &modes = depth.getSensorInfo ().getSupportedVideoModes ();
  ASSERT_EQ (modes.getSize (), 2);
  EXPECT_EQ (modes[0].getResolutionX (), 640);
  EXPECT_EQ (modes[1].getResolutionX (), 320);
  EXPECT_EQ (modes[0].getFps (), 30);
  EXPECT_EQ (modes[0].getPixelFormat (), openni::PIXEL_FORMAT_DEPTH_1_MM);

  const sim::DepthSensor sensor = sim::DepthSensor::kinect (640, 480);
  EXPECT_NEAR (depth.getHorizontalFieldOfView (), 2 * std::atan (320.0 / sensor.fx), 1e-6);
  EXPECT_NEAR (depth.getVerticalFieldOfView (), 2 * std::atan (240.0 / sensor.fy), 1e-6);
  unsigned long long zpd = 0;
  double zpps = 0, emitter_cm = 0;
  ASSERT_EQ (depth.getProperty (XN_STREAM_PROPERTY_ZERO_PLANE_DISTANCE, &zpd), openni::STATUS_OK);
  ASSERT_EQ (depth.getProperty (XN_STREAM_PROPERTY_ZERO_PLANE_PIXEL_SIZE, &zpps), openni::STATUS_OK);
  ASSERT_EQ (depth.getProperty (XN_STREAM_PROPERTY_EMITTER_DCMOS_DISTANCE, &emitter_cm), openni::STATUS_OK);
  // ROS and OpenNI1-era code: focal length at VGA = ZPD / ZPPS (an SXGA pixel) / 2.
  EXPECT_NEAR (zpd / zpps / 2.0, sensor.fx, 1e-9);
  EXPECT_NEAR (emitter_cm, 100 * sensor.baseline_m, 1e-12);
  OniCropping cropping;
  ASSERT_EQ (depth.getProperty (ONI_STREAM_PROPERTY_CROPPING, &cropping), openni::STATUS_OK);
  EXPECT_FALSE (cropping.enabled);
  EXPECT_TRUE (device.isImageRegistrationModeSupported (openni::IMAGE_REGISTRATION_OFF));
  EXPECT_FALSE (device.isImageRegistrationModeSupported (openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR));

  ASSERT_EQ (depth.setMirroringEnabled (true), openni::STATUS_OK);
  EXPECT_TRUE (depth.getMirroringEnabled ());
  ASSERT_EQ (depth.start (), openni::STATUS_OK);
  const sim::KinectSimulator simulator = planeSimulator (640, 480);
  int previous = 0;
  for (int k = 0; k < 3; ++k)
  {
    openni::VideoStream *streams[] = {&depth};
    int ready = -1;
    ASSERT_EQ (openni::OpenNI::waitForAnyStream (streams, 1, &ready, 5000), openni::STATUS_OK);
    openni::VideoFrameRef frame;
    ASSERT_EQ (depth.readFrame (&frame), openni::STATUS_OK);
    ASSERT_GT (frame.getFrameIndex (), previous);
    previous = frame.getFrameIndex ();
    EXPECT_EQ (frame.getTimestamp (), std::uint64_t (frame.getFrameIndex ()) * 33333u);
    ASSERT_EQ (frame.getWidth (), 640);
    ASSERT_EQ (frame.getStrideInBytes (), 1280);
    const DepthFrame truth = simulator.simulateFrame (0, frame.getFrameIndex () - 1);
    const auto *pixels = static_cast<const std::uint16_t *> (frame.getData ());
    std::size_t differing = 0;
    for (int v = 0; v < 480; ++v)
      for (int u = 0; u < 640; ++u)
        differing += pixels[v * 640 + (639 - u)] != truth.depth_mm[std::size_t (v) * 640 + u];
    EXPECT_EQ (differing, 0u) << "frame " << frame.getFrameIndex () << " is not the simulator's, mirrored";
  }
  depth.stop ();
  depth.destroy ();
  device.close ();
  openni::OpenNI::shutdown ();
}

// --- bad input ---------------------------------------------------------------------------------

TEST_F (OpenNI2Device, BadUriFailsTheOpenWithTheDriversMessage)
{
  ASSERT_EQ (openni::OpenNI::initialize (), openni::STATUS_OK);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"pcltexlet:sim=plane;bogus=1", "unknown key 'bogus'"},
      {"pcltexlet:sim=cylinder", "unknown scene 'cylinder'"},
      {"pcltexlet:sim=plane;effects=no_such_effect", "no_such_effect"},
      {"pcltexlet:sim=plane;seed=-3", "seed=-3"},
      {"pcltexlet:loop=1", "names no source"},
      {"pcltexlet:recording=" + std::string (DATA_DIR) + "/kinect/grabber_sequence.oni", "is an .oni file"},
  };
  for (const auto &c : cases)
  {
    openni::Device device;
    EXPECT_NE (device.open (c.first.c_str ()), openni::STATUS_OK) << c.first;
    EXPECT_NE (std::string (openni::OpenNI::getExtendedError ()).find (c.second), std::string::npos)
        << c.first << ": " << openni::OpenNI::getExtendedError ();
  }
  openni::OpenNI::shutdown ();
}

TEST_F (OpenNI2Device, GrabberThrowsNamingAMissingRecording)
{
  try
  {
    pcl::io::OpenNI2Grabber grabber (kMissingUri);
    FAIL () << "the grabber opened a device for a missing recording";
  }
  catch (const pcl::IOException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("/nonexistent/pcl_texlet_recording"), std::string::npos) << e.what ();
    EXPECT_NE (std::string (e.what ()).find ("does not exist"), std::string::npos) << e.what ();
  }
}

TEST_F (OpenNI2Device, RecordingsWithAChangingFrameSizeOrACorruptFrameFailTheOpen)
{
  ASSERT_EQ (openni::OpenNI::initialize (), openni::STATUS_OK);
  // A frame size that changes after the first frame.
  const fs::path changing = file ("changing");
  fs::create_directories (changing / "depth");
  CameraInfo info;
  info.width = 64;
  info.height = 48;
  info.K[0] = info.K[4] = 58;
  info.K[2] = 31.5;
  info.K[5] = 23.5;
  saveCameraInfoYaml ((changing / "camera.yaml").string (), info);
  const std::vector<std::uint16_t> big (64 * 48, 1000), small (32 * 24, 1000);
  writeDepthPng ((changing / "depth" / "000000.png").string (), big.data (), 64, 48);
  writeDepthPng ((changing / "depth" / "000001.png").string (), small.data (), 32, 24);
  openni::Device device;
  EXPECT_NE (device.open (("pcltexlet:recording=" + changing.string ()).c_str ()), openni::STATUS_OK);
  std::string error = openni::OpenNI::getExtendedError ();
  EXPECT_NE (error.find ("000001"), std::string::npos) << error;
  EXPECT_NE (error.find ("32x24"), std::string::npos) << error;

  // A corrupt frame file.
  fs::remove (changing / "depth" / "000001.png");
  std::ofstream ((changing / "depth" / "000001.png").string ()) << "not a PNG";
  EXPECT_NE (device.open (("pcltexlet:recording=" + changing.string () + ";loop=0").c_str ()), openni::STATUS_OK);
  error = openni::OpenNI::getExtendedError ();
  EXPECT_NE (error.find ("000001.png"), std::string::npos) << error;
  openni::OpenNI::shutdown ();
}

TEST_F (OpenNI2Device, AppsExitTwoWithOneLineForBadDevicesAndTruncatedOni)
{
  std::string err;
  EXPECT_EQ (record ("pcltexlet:sim=plane;bogus=1", 3, file ("x.oni"), &err), 2) << err;
  EXPECT_EQ (countLines (err), 1u) << err;
  EXPECT_NE (err.find ("unknown key 'bogus'"), std::string::npos) << err;
  EXPECT_FALSE (fs::exists (file ("x.oni")));

  EXPECT_EQ (run (std::string (EXTRACT_APP) + " 'sensor:" + kMissingUri + "' " + file ("texlets") + " --frames 2", &err), 2)
      << err;
  EXPECT_EQ (countLines (err), 1u) << err;
  EXPECT_NE (err.find ("does not exist"), std::string::npos) << err;

  EXPECT_EQ (run (std::string (EXTRACT_APP) + " 'sensor:" + kPlaneUri + "' " + file ("texlets"), &err), 2) << err;
  EXPECT_EQ (countLines (err), 1u) << err;
  EXPECT_NE (err.find ("--frames"), std::string::npos) << err;

  // A truncated .oni file as the device to record: the open or the first frame fails, within the
  // timeout, and no output is left.
  const std::string source = std::string (DATA_DIR) + "/kinect/grabber_sequence.oni";
  const std::string truncated = file ("truncated.oni");
  fs::copy_file (source, truncated);
  fs::resize_file (truncated, fs::file_size (source) / 5);
  EXPECT_EQ (run (std::string (RECORD_APP) + " -q --timeout 3 -d " + truncated + " -n 3 " + file ("y.oni"), &err, 60), 2)
      << err;
  EXPECT_EQ (countLines (err), 1u) << err;
  EXPECT_FALSE (fs::exists (file ("y.oni")));
}

// --- recording folder -> simulated device -> openni::Recorder -> .oni -> playback --------------

/** The depth frames of \a oni, played by OpenNI2's OniFile driver one record at a time (manual
  * playback: each bounded wait releases the next record). It takes the file's frame count and no
  * more: at the end of the file the player walks its stream list in a busy loop while the stream
  * is started, and destroying the stream then can crash it; so the stream is stopped and the
  * player given 50 ms before it is destroyed, as OniReader does (docs/openni2_device.md).
  */
std::vector<DepthFrame>
playOni (const std::string &oni, int &frame_count, double &focal_px)
{
  std::vector<DepthFrame> frames;
  EXPECT_EQ (openni::OpenNI::initialize (), openni::STATUS_OK);
  openni::Device device;
  EXPECT_EQ (device.open (oni.c_str ()), openni::STATUS_OK) << openni::OpenNI::getExtendedError ();
  if (!device.isValid ())
    return frames;
  openni::PlaybackControl *control = device.getPlaybackControl ();
  EXPECT_EQ (control->setRepeatEnabled (false), openni::STATUS_OK);
  EXPECT_EQ (control->setSpeed (-1.0f), openni::STATUS_OK);
  openni::VideoStream depth;
  EXPECT_EQ (depth.create (device, openni::SENSOR_DEPTH), openni::STATUS_OK);
  frame_count = control->getNumberOfFrames (depth);
  focal_px = depth.getVideoMode ().getResolutionX () / (2 * std::tan (depth.getHorizontalFieldOfView () / 2));
  EXPECT_EQ (depth.start (), openni::STATUS_OK);
  for (int k = 0; k < frame_count; ++k)
  {
    openni::VideoStream *streams[] = {&depth};
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream (streams, 1, &ready, 3000) != openni::STATUS_OK)
    {
      ADD_FAILURE () << "no depth frame " << k + 1 << " of " << frame_count << " within 3 s";
      break;
    }
    openni::VideoFrameRef ref;
    if (depth.readFrame (&ref) != openni::STATUS_OK)
    {
      ADD_FAILURE () << "cannot read depth frame " << k + 1 << ": " << openni::OpenNI::getExtendedError ();
      break;
    }
    EXPECT_EQ (ref.getFrameIndex (), k + 1);
    DepthFrame frame;
    frame.width = ref.getWidth ();
    frame.height = ref.getHeight ();
    const auto *pixels = static_cast<const std::uint16_t *> (ref.getData ());
    frame.depth_mm.assign (pixels, pixels + std::size_t (frame.width) * frame.height);
    frames.push_back (std::move (frame));
  }
  depth.stop ();
  std::this_thread::sleep_for (std::chrono::milliseconds (50));
  depth.destroy ();
  device.close ();
  openni::OpenNI::shutdown (); // balances the initialize () above
  return frames;
}

/** Records \a folder (played once) to .oni and plays it back: every depth pixel, the frame count
  * and the focal length must survive.
  */
void
expectRoundTrip (OpenNI2Device &test, const std::string &folder, const std::string &oni)
{
  const RecordingReader::Ptr source = openRecording (folder);
  const int frames = static_cast<int> (source->size ());
  std::string err;
  const int code = test.record ("pcltexlet:recording=" + folder + ";loop=0", frames, oni, &err);
  if (code == 137)
    GTEST_SKIP () << "libOpenNI2 deadlocked recording in 3 tries of 60 s";
  ASSERT_EQ (code, 0) << err;

  int frame_count = 0;
  double focal_px = 0;
  const std::vector<DepthFrame> played = playOni (oni, frame_count, focal_px);
  EXPECT_EQ (frame_count, frames);
  EXPECT_NEAR (focal_px, source->cameraInfo ().fx (), 1e-3);
  ASSERT_EQ (played.size (), std::size_t (frames));
  DepthFrame expected;
  for (const DepthFrame &actual : played)
  {
    ASSERT_TRUE (source->next (expected));
    ASSERT_EQ (actual.width, expected.width);
    ASSERT_EQ (actual.height, expected.height);
    EXPECT_TRUE (actual.depth_mm == expected.depth_mm) << "frame " << expected.name << " changed";
  }

  // The same file through PCL's grabber (OniReader): every frame again, in order, unchanged.
  const RecordingReader::Ptr again = openRecording (folder);
  OniReader reader (oni);
  ASSERT_EQ (reader.size (), std::size_t (frames));
  DepthFrame grabbed;
  std::size_t unchanged = 0;
  while (reader.next (grabbed))
  {
    ASSERT_TRUE (again->next (expected));
    EXPECT_EQ (grabbed.name, std::string (6 - std::to_string (unchanged + 1).size (), '0') + std::to_string (unchanged + 1));
    EXPECT_TRUE (grabbed.depth_mm == expected.depth_mm) << "frame " << expected.name << " changed through the grabber";
    unchanged += grabbed.depth_mm == expected.depth_mm;
  }
  EXPECT_EQ (unchanged, std::size_t (frames));
}

TEST_F (OpenNI2Device, RealKinectFramesSurviveRecordingAndPlayback)
{
  expectRoundTrip (*this, std::string (DATA_DIR) + "/kinect/grabber_sequence", file ("real.oni"));
}

TEST_F (OpenNI2Device, SimulatedRecordingFolderSurvivesRecordingAndPlayback)
{
  const sim::SceneSetup setup = sim::boxSetup (1.2, 40);
  sim::SimulationSettings settings;
  settings.seed = 5;
  sim::setEffectEnabled (settings.effects, "temporal_drift", true);
  const sim::KinectSimulator simulator (setup.scene, setup.sensors (sim::DepthSensor::kinect (320, 240)), settings, 1);
  const std::string folder = file ("box");
  sim::writeSimulatedRecording (simulator, setup, 0, 0, 12, folder);
  expectRoundTrip (*this, folder, file ("box.oni"));
}

// --- pcl_texlet_extract on the live simulated device -------------------------------------------

TEST_F (OpenNI2Device, ExtractRunsOnTheLiveSimulatedDeviceForAFixedNumberOfFrames)
{
  // A wall 1.2 m straight ahead: every texlet lies on it, facing the camera.
  const std::string uri = "pcltexlet:sim=plane;distance=1.2;seed=4";
  const std::string out = file ("texlets");
  std::string err;
  ASSERT_EQ (run (std::string (EXTRACT_APP) + " -q -u analytic 'sensor:" + uri + "' " + out + " --frames 3", &err), 0)
      << err;
  std::vector<fs::path> files;
  for (const auto &entry : fs::directory_iterator (out))
    files.push_back (entry.path ());
  ASSERT_EQ (files.size (), 3u);
  for (const fs::path &path : files)
  {
    pcl::PointCloud<pcl::Texlet> texlets;
    ASSERT_EQ (pcl::io::loadPCDFile (path.string (), texlets), 0) << path;
    std::vector<double> depth_error_mm, normal_error_deg;
    for (const auto &t : texlets)
      if (std::isfinite (t.z) && std::isfinite (t.normal_z))
      {
        depth_error_mm.push_back (std::abs (t.z - 1.2) * 1e3);
        normal_error_deg.push_back (std::acos (std::min (1.0, std::abs (double (t.normal_z)))) * 180 / M_PI);
      }
    ASSERT_GT (depth_error_mm.size (), 1000u) << path;
    std::nth_element (depth_error_mm.begin (), depth_error_mm.begin () + depth_error_mm.size () / 2, depth_error_mm.end ());
    std::nth_element (normal_error_deg.begin (), normal_error_deg.begin () + normal_error_deg.size () / 2,
                      normal_error_deg.end ());
    EXPECT_LT (depth_error_mm[depth_error_mm.size () / 2], 3.0) << path;
    EXPECT_LT (normal_error_deg[normal_error_deg.size () / 2], 3.0) << path;
  }
}

// The library's reader of live devices, in process.
TEST_F (OpenNI2Device, DeviceReaderDeliversTheDevicesFramesWithItsCamera)
{
  OpenNI2DeviceReader reader (kPlaneUri, 4);
  EXPECT_EQ (reader.size (), 4u);
  const sim::KinectSimulator simulator = planeSimulator (640, 480);
  EXPECT_NEAR (reader.cameraInfo ().fx (), simulator.sensor (0).fx, 1e-3);
  EXPECT_NEAR (reader.cameraInfo ().cx (), simulator.sensor (0).cx, 1e-9);
  EXPECT_NEAR (reader.cameraInfo ().baseline_m, simulator.sensor (0).baseline_m, 1e-6);
  DepthFrame frame;
  int read = 0;
  while (reader.next (frame))
  {
    const DepthFrame truth = simulator.simulateFrame (0, static_cast<std::uint32_t> (std::stoul (frame.name) - 1));
    EXPECT_TRUE (frame.depth_mm == truth.depth_mm) << frame.name;
    ++read;
  }
  EXPECT_EQ (read, 4);
}

} // namespace

// --- pcl_texlet_viewer's live-sensor path (issue 8) --------------------------------------------

TEST_F (OpenNI2Device, ViewerShowsTheFirstSensorWhenItIsTheSimulatedOne)
{
  if (std::string (XVFB_RUN).empty ())
    GTEST_SKIP () << "xvfb-run is not installed: no X server for the viewer";
  // Inside this namespace the only OpenNI2 drivers are pcl_texlet's and OniFile, so the first
  // sensor is the listed simulated one: a wall 1.2 m ahead.
  const std::string png = file ("sensor.png");
  std::string err;
  const int code = run ("env PCLTEXLET_DEVICES='pcltexlet:sim=plane;distance=1.2;seed=2' " + std::string (XVFB_RUN) +
                            " -a -s '-screen 0 1280x1024x24' " + VIEWER_APP +
                            " sensor --size 640 --layers cloud,texlets -u none --screenshot " + png,
                        &err, 180);
  ASSERT_EQ (code, 0) << err;
  int width = 0, height = 0;
  const std::vector<std::uint8_t> rgb = readRgbPng (png, width, height);
  ASSERT_GT (width, 100);
  // The wall fills the view: most of the picture away from the text overlays is lit.
  std::size_t lit = 0, all = 0;
  for (int v = 40; v < height - 30; ++v)
    for (int u = 0; u < width; ++u)
    {
      const std::uint8_t *p = &rgb[3 * (std::size_t (v) * width + u)];
      lit += p[0] + p[1] + p[2] > 30;
      ++all;
    }
  EXPECT_GT (double (lit) / all, 0.3) << "the screenshot of the simulated sensor is mostly blank";
}
