#include "bench_input.h"

#include "../common/app_main.h"
#include "scenes.h"

#include <pcl_texlet/camera/camera_estimation.h>
#include <pcl_texlet/camera/pinhole_model.h>

#include <pcl/io/pcd_io.h>

#include <filesystem>
#include <memory>

namespace fs = std::filesystem;
using pcl_texlet_app::InputError;
using pcl_texlet_app::pclMessage;

namespace pcl_texlet_bench
{

Input
loadInput (const Options &o)
{
  Input in;
  if (!o.scene.empty ())
  {
    const SimulatedScene s = simulateScene (o.scene, o.sim_width, o.sim_height, 1);
    in.cloud = s.cloud;
    in.camera = s.camera;
    in.description = "simulated " + o.scene + " " + std::to_string (o.sim_width) + "x" + std::to_string (o.sim_height);
    return in;
  }
  if (o.input.empty ())
    throw InputError ("no INPUT given and no bundled frame known: give an organised PCD file or --scene");
  if (!fs::is_regular_file (o.input))
    throw InputError ("input '" + o.input + "' does not exist or is not a file");
  pcl::PCLPointCloud2 header;
  int version, type;
  unsigned int offset;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  if (pcl::PCDReader ().readHeader (o.input, header, origin, orientation, version, type, offset) != 0)
    throw InputError ("cannot read '" + o.input + "': not a PCD file or a corrupt header");
  if (header.height <= 1)
    throw InputError ("'" + o.input + "' is not an organised cloud (height " + std::to_string (header.height) + ")");
  in.cloud = std::make_shared<Cloud> ();
  if (pcl::io::loadPCDFile (o.input, *in.cloud) != 0 ||
      in.cloud->size () != static_cast<std::size_t> (header.width) * header.height)
    throw InputError ("cannot read '" + o.input + "': corrupt or truncated PCD data");
  try
  {
    in.camera = std::make_shared<pcl::texlet::PinholeModel> (pcl::texlet::estimatePinholeModel (*in.cloud));
  }
  catch (const pcl::PCLException &e)
  {
    throw InputError ("'" + o.input + "': " + pclMessage (e.what ()));
  }
  in.description = fs::path (o.input).filename ().string () + " " + std::to_string (in.cloud->width) + "x" +
                   std::to_string (in.cloud->height);
  return in;
}

} // namespace pcl_texlet_bench
