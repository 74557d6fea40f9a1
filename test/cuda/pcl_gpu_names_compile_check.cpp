/*
 * Compile check: a program that uses PCL's own gpu modules (PCL built from source, as GPU users
 * have it) and pcl_texlet's public GPU headers in one translation unit. PCL declares
 * pcl::gpu::DeviceArray and pcl::gpu::DeviceArray2D (pcl/gpu/containers/device_array.h); the
 * declarations below stand in for them, since Debian's PCL does not ship its gpu modules.
 * pcl_texlet's backend lives in pcl::texlet::gpu, so both sets of names must coexist.
 * Built in every CUDA build (test/CMakeLists.txt); it is never linked or run.
 */
#include <cstddef>
#include <type_traits>
#include <vector>

// --- a stand-in of PCL's pcl/gpu/containers/device_array.h: its names, a few members ----------
namespace pcl
{
namespace gpu
{
class DeviceMemory
{
public:
  std::size_t sizeBytes () const;
};

class DeviceMemory2D
{
public:
  std::size_t step () const;
};

template <class T>
class DeviceArray : public DeviceMemory
{
public:
  explicit DeviceArray (std::size_t size);
  void upload (const std::vector<T> &host);
  std::size_t size () const;
};

template <class T>
class DeviceArray2D : public DeviceMemory2D
{
public:
  DeviceArray2D (int rows, int cols);
  int rows () const;
};
} // namespace gpu

namespace device
{
using pcl::gpu::DeviceArray;
using pcl::gpu::DeviceArray2D;
} // namespace device
} // namespace pcl

// --- pcl_texlet's public GPU headers ----------------------------------------------------------
#include <pcl_texlet/gpu/containers/cuda_error.h>
#include <pcl_texlet/gpu/containers/device_array.h>
#include <pcl_texlet/gpu/frame_texlet.h>
#include <pcl_texlet/gpu/texlet_estimation.h>
#include <pcl_texlet/gpu/texlet_estimation_pcl.h>
#include <pcl_texlet/gpu/texlet_relations.h>

static_assert (!std::is_same<pcl::gpu::DeviceArray<float>, pcl::texlet::gpu::DeviceArray<float>>::value,
               "PCL's DeviceArray and pcl_texlet's are different types");
static_assert (!std::is_same<pcl::gpu::DeviceArray2D<float>, pcl::texlet::gpu::DeviceArray2D<float>>::value,
               "PCL's DeviceArray2D and pcl_texlet's are different types");

/** Code as a PCL gpu user writes it: PCL's names unqualified, pcl_texlet's by their namespace. */
void
pclGpuNamesCompileCheck ()
{
  using namespace pcl::gpu;
  DeviceArray<int> pcl_array (16);
  DeviceArray2D<unsigned short> pcl_image (480, 640);
  pcl::device::DeviceArray<float> pcl_device_array (8);

  pcl::texlet::gpu::TexletEstimation est;
  pcl::texlet::gpu::DeviceArray2D<std::uint16_t> depth;
  pcl::texlet::gpu::DeviceArray<pcl::texlet::gpu::DeviceTexlet> texlets;
  est.compute (depth, texlets);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  pcl::PointCloud<pcl::Texlet> out;
  est.compute (cloud, out);
  (void) pcl_array.size ();
  (void) pcl_image.rows ();
  (void) pcl_device_array.size ();
}
