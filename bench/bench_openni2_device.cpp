/*
 * Speed of pcl_texlet's simulated OpenNI2 device (src/openni2_driver): can it sustain 30 Hz VGA
 * depth on one core while the simulator computes its effects on the fly?
 *
 *   bench_openni2_device [SECONDS]
 *
 * The process is pinned to one core (CPU 0, or the first allowed), so the device's clock thread
 * shares it with everything else.
 * 1. The driver's frame source alone: the time to make one VGA frame, with no effect and with
 *    every effect of the catalogue on (90 frames each): mean and worst.
 * 2. As root, the device itself through libOpenNI2 (the built driver bound over OpenNI2's driver
 *    folder in a private mount namespace, as the tests do): frames delivered over SECONDS
 *    (default 5) of a live VGA depth stream with every effect on, the rate, and frames lost
 *    (gaps in the frame index).
 * Not a test: nothing is asserted; the numbers are printed.
 */
#include "../src/openni2_driver/frame_source.h"

#include <pcl_texlet/simulation/effects.h>

#include <OpenNI.h>

#include <sched.h>
#include <sys/mount.h>

#include <algorithm>
#include <ctime>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace
{

std::string
allEffectsUri ()
{
  std::string names;
  for (const auto &effect : pcl::texlet::sim::effectCatalogue ())
    names += (names.empty () ? "" : ",") + effect.name;
  return "pcltexlet:sim=plane;distance=1.5;tilt_x=20;effects=" + names + ";seed=1";
}

double
threadCpuMs ()
{
  timespec t;
  clock_gettime (CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

void
timeSource (const std::string &label, const std::string &uri)
{
  const auto source = pcl::texlet::oni_device::openFrameSource (uri);
  const pcl::texlet::oni_device::SourceMode vga {640, 480};
  pcl::texlet::DepthFrame frame;
  source->frame (0, vga, frame); // first touch of the buffers
  double total = 0, worst = 0, cpu_total = 0;
  const int frames = 90;
  for (int i = 1; i <= frames; ++i)
  {
    const double cpu_start = threadCpuMs ();
    const auto start = Clock::now ();
    source->frame (i, vga, frame);
    const double ms = std::chrono::duration<double, std::milli> (Clock::now () - start).count ();
    cpu_total += threadCpuMs () - cpu_start;
    total += ms;
    worst = std::max (worst, ms);
  }
  // CPU time is what the frame costs the core; wall time also holds the waits for a core on a
  // loaded machine.
  std::printf ("  %-22s CPU %6.2f ms per VGA frame (up to %5.1f Hz on one core); wall %6.2f ms, worst %6.2f ms\n",
               label.c_str (), cpu_total / frames, 1000.0 * frames / cpu_total, total / frames, worst);
}

std::string bench_folder; ///< removed before exit (a loaded driver's file may be deleted)

bool
bindDriver (std::string &why)
{
  char pattern[] = "/tmp/pcl_texlet_bench_XXXXXX";
  if (!mkdtemp (pattern))
    return why = "no temporary folder", false;
  const fs::path drivers = fs::path (pattern) / "drivers";
  fs::create_directories (drivers);
  fs::copy_file (DRIVER_FILE, drivers / "libPclTexletDevice.so.0");
  if (unshare (CLONE_NEWNS) != 0 || mount ("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
      mount (drivers.c_str (), SYSTEM_DRIVER_DIR, nullptr, MS_BIND, nullptr) != 0)
  {
    why = std::string ("a private mount namespace is not permitted here (") + std::strerror (errno) + "; run as root)";
    fs::remove_all (pattern);
    return false;
  }
  bench_folder = pattern;
  return true;
}

void
timeDevice (const std::string &uri, double seconds)
{
  if (openni::OpenNI::initialize () != openni::STATUS_OK)
    return (void)std::printf ("  cannot initialise OpenNI2: %s\n", openni::OpenNI::getExtendedError ());
  openni::Device device;
  openni::VideoStream depth;
  if (device.open (uri.c_str ()) != openni::STATUS_OK || depth.create (device, openni::SENSOR_DEPTH) != openni::STATUS_OK ||
      depth.start () != openni::STATUS_OK)
    return (void)std::printf ("  cannot open the device: %s\n", openni::OpenNI::getExtendedError ());
  int first = -1, last = -1, read = 0, lost = 0;
  const auto start = Clock::now ();
  while (std::chrono::duration<double> (Clock::now () - start).count () < seconds)
  {
    openni::VideoStream *streams[] = {&depth};
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream (streams, 1, &ready, 2000) != openni::STATUS_OK)
      break;
    openni::VideoFrameRef frame;
    if (depth.readFrame (&frame) != openni::STATUS_OK)
      break;
    if (first < 0)
      first = frame.getFrameIndex ();
    else
      lost += frame.getFrameIndex () - last - 1;
    last = frame.getFrameIndex ();
    ++read;
    if (read % 30 == 0)
      std::fprintf (stderr, "  ... %d frames\n", read);
  }
  const double elapsed = std::chrono::duration<double> (Clock::now () - start).count ();
  std::printf ("  %d VGA depth frames in %.2f s: %.2f Hz; frame indices %d..%d, %d not read (gaps)\n", read, elapsed,
               read / elapsed, first, last, lost);
  depth.stop ();
  depth.destroy ();
  device.close ();
}

} // namespace

int
main (int argc, char **argv)
{
  const double seconds = argc > 1 ? std::atof (argv[1]) : 5.0;
  cpu_set_t allowed;
  CPU_ZERO (&allowed);
  sched_getaffinity (0, sizeof (allowed), &allowed);
  int cpu = 0;
  while (cpu < CPU_SETSIZE && !CPU_ISSET (cpu, &allowed))
    ++cpu;
  cpu_set_t one;
  CPU_ZERO (&one);
  CPU_SET (cpu, &one);
  sched_setaffinity (0, sizeof (one), &one);
  std::printf ("pinned to CPU %d\n1. frame source (the driver's work per frame):\n", cpu);
  timeSource ("plane, no effect", "pcltexlet:sim=plane;distance=1.5;tilt_x=20;seed=1");
  timeSource ("plane, every effect", allEffectsUri ());
  timeSource ("box, every effect", "pcltexlet:sim=box;effects=temporal_drift,vertical_stripes,interference,"
                                   "disparity_quantization;seed=1");
  std::printf ("2. the device through libOpenNI2, every effect on:\n");
  std::string why;
  if (!bindDriver (why))
    return std::printf ("  skipped: %s\n", why.c_str ()), 0;
  timeDevice (allEffectsUri (), seconds);
  std::fflush (stdout);
  std::error_code ec;
  fs::remove_all (bench_folder, ec);
  std::_Exit (0); // libOpenNI2 2.2 can crash tearing itself down at exit
}
