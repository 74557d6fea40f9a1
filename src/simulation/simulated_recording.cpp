#include <pcl_texlet/simulation/simulated_recording.h>
#include <pcl_texlet/simulation/simulation_meta.h>
#include <pcl_texlet/io/recording_writer.h>
#include <pcl_texlet/common/parallel_for.h>

#include <pcl/exceptions.h>

#include <cstdint>
#include <string>

namespace pcl
{
namespace texlet
{
namespace sim
{

void
writeSimulatedRecording (const KinectSimulator &simulator, const SceneSetup &setup, std::size_t sensor,
                         std::uint32_t first_frame, std::uint32_t frames, const std::string &folder)
{
  if (frames == 0)
    throw pcl::BadArgumentException ("recording '" + folder + "': no frames to simulate");
  // Frame names have six digits; beyond a million frames they would stop sorting by number.
  if (first_frame > 999999u || frames > 1000000u - first_frame)
    throw pcl::BadArgumentException ("recording '" + folder + "': frames " + std::to_string (first_frame) + " .. " +
                                     std::to_string (std::uint64_t (first_frame) + frames - 1) +
                                     " do not fit six-digit names (at most 999999)");
  RecordingFolderWriter writer (folder, simulator.cameraInfo (sensor));
  writer.writeMeta (simulationMetaYaml (setup, simulator, sensor, first_frame, frames));

  // Each thread simulates and compresses whole frames; PNG compression costs as much as the
  // simulation, so both belong inside the parallel loop.
  parallelFor (static_cast<int> (frames), simulator.numberOfThreads (), true, [&] (int k) {
    DepthFrame frame;
    simulator.simulateFrameSerial (sensor, first_frame + static_cast<std::uint32_t> (k), frame);
    writer.writeFrame (frame);
  });
  writer.commit ();
}

} // namespace sim
} // namespace texlet
} // namespace pcl
