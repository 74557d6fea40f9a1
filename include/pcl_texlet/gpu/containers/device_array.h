/*
 * pcl_texlet GPU: device memory containers in the style of PCL's gpu module
 * (pcl/gpu/containers/device_array.h, which Debian's PCL does not ship).
 *
 * DeviceArray<T> is a typed 1D buffer, DeviceArray2D<T> a pitched 2D one. Like PCL's, copies
 * are shallow and share the buffer (reference counted); the memory is freed when the last
 * copy goes. Every CUDA error becomes a pcl::texlet::gpu::CudaError naming the call. Sizes are
 * in elements unless a name says bytes. They live in pcl::texlet::gpu, not in PCL's pcl::gpu,
 * so a program can use PCL's gpu modules and these side by side.
 */
#pragma once

#include <pcl_texlet/gpu/containers/cuda_error.h>

#include <cuda_runtime_api.h>

#include <cstddef>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace gpu
{
namespace detail
{
/** \brief Frees device memory; never throws (used from destructors). */
struct CudaFree
{
  void
  operator() (void *p) const noexcept
  {
    if (p)
      cudaFree (p);
  }
};
} // namespace detail

/** \brief A typed 1D device buffer: create, upload, download, shared by shallow copies. */
template <typename T>
class DeviceArray
{
  static_assert (std::is_trivially_copyable<T>::value, "DeviceArray holds trivially copyable types only");

public:
  using type = T;

  /** \brief Empty array, no device memory. */
  DeviceArray () = default;

  /** \brief Allocates \a size elements (uninitialised). */
  explicit DeviceArray (std::size_t size) { create (size); }

  /** \brief (Re)allocates \a size elements unless it already holds exactly that many. */
  void
  create (std::size_t size)
  {
    if (size == size_ && data_)
      return;
    release ();
    if (size == 0)
      return;
    void *p = nullptr;
    PCL_TEXLET_CUDA_CHECK (cudaMalloc (&p, size * sizeof (T)));
    data_.reset (p, detail::CudaFree ());
    size_ = size;
  }

  /** \brief Drops this reference to the buffer (freed when it was the last). */
  void
  release ()
  {
    data_.reset ();
    size_ = 0;
  }

  /** \brief Copies \a size host elements to the device, (re)allocating as needed. */
  void
  upload (const T *host, std::size_t size)
  {
    create (size);
    if (size)
      PCL_TEXLET_CUDA_CHECK (cudaMemcpy (ptr (), host, size * sizeof (T), cudaMemcpyHostToDevice));
  }

  template <typename A> void
  upload (const std::vector<T, A> &host) { upload (host.data (), host.size ()); }

  /** \brief Copies the whole array to \a host, which must hold size() elements. */
  void
  download (T *host) const
  {
    if (size_)
      PCL_TEXLET_CUDA_CHECK (cudaMemcpy (host, ptr (), size_ * sizeof (T), cudaMemcpyDeviceToHost));
  }

  template <typename A> void
  download (std::vector<T, A> &host) const
  {
    host.resize (size_);
    download (host.data ());
  }

  /** \brief Deep copy into \a other (allocated to this size). */
  void
  copyTo (DeviceArray &other) const
  {
    other.create (size_);
    if (size_)
      PCL_TEXLET_CUDA_CHECK (cudaMemcpy (other.ptr (), ptr (), size_ * sizeof (T), cudaMemcpyDeviceToDevice));
  }

  void
  swap (DeviceArray &other) noexcept
  {
    data_.swap (other.data_);
    std::swap (size_, other.size_);
  }

  T *
  ptr () { return static_cast<T *> (data_.get ()); }
  const T *
  ptr () const { return static_cast<const T *> (data_.get ()); }
  operator T * () { return ptr (); }
  operator const T * () const { return ptr (); }

  std::size_t
  size () const { return size_; }
  std::size_t
  sizeBytes () const { return size_ * sizeof (T); }
  bool
  empty () const { return !data_; }

private:
  std::shared_ptr<void> data_;
  std::size_t size_ = 0;
};

/** \brief A typed pitched 2D device buffer of rows x cols elements (cudaMallocPitch). */
template <typename T>
class DeviceArray2D
{
  static_assert (std::is_trivially_copyable<T>::value, "DeviceArray2D holds trivially copyable types only");

public:
  using type = T;

  DeviceArray2D () = default;

  /** \brief Allocates \a rows x \a cols elements (uninitialised). */
  DeviceArray2D (int rows, int cols) { create (rows, cols); }

  /** \brief (Re)allocates unless it already has this shape. \throws std::invalid_argument for negative sizes. */
  void
  create (int rows, int cols)
  {
    if (rows < 0 || cols < 0)
    {
      std::ostringstream msg;
      msg << "pcl::texlet::gpu::DeviceArray2D::create: negative size " << rows << " x " << cols;
      throw std::invalid_argument (msg.str ());
    }
    if (rows == rows_ && cols == cols_ && data_)
      return;
    release ();
    if (rows == 0 || cols == 0)
      return;
    void *p = nullptr;
    std::size_t pitch = 0;
    PCL_TEXLET_CUDA_CHECK (cudaMallocPitch (&p, &pitch, static_cast<std::size_t> (cols) * sizeof (T), rows));
    data_.reset (p, detail::CudaFree ());
    step_ = pitch;
    rows_ = rows;
    cols_ = cols;
  }

  void
  release ()
  {
    data_.reset ();
    step_ = 0;
    rows_ = cols_ = 0;
  }

  /** \brief Copies a host image of \a rows x \a cols elements, \a host_step bytes per row. */
  void
  upload (const void *host, std::size_t host_step, int rows, int cols)
  {
    create (rows, cols);
    if (data_)
      PCL_TEXLET_CUDA_CHECK (cudaMemcpy2D (data_.get (), step_, host, host_step, colsBytes (), rows_,
                                           cudaMemcpyHostToDevice));
  }

  /** \brief Copies a dense host vector of \a cols columns (its size must be a multiple). */
  template <typename A> void
  upload (const std::vector<T, A> &host, int cols)
  {
    if (cols <= 0 || host.size () % static_cast<std::size_t> (cols) != 0)
    {
      std::ostringstream msg;
      msg << "pcl::texlet::gpu::DeviceArray2D::upload: " << host.size () << " elements are not rows of " << cols << " columns";
      throw std::invalid_argument (msg.str ());
    }
    upload (host.data (), cols * sizeof (T), static_cast<int> (host.size () / cols), cols);
  }

  /** \brief Copies the image to \a host, \a host_step bytes per row. */
  void
  download (void *host, std::size_t host_step) const
  {
    if (data_)
      PCL_TEXLET_CUDA_CHECK (cudaMemcpy2D (host, host_step, data_.get (), step_, colsBytes (), rows_,
                                           cudaMemcpyDeviceToHost));
  }

  /** \brief Copies the image into a dense vector; \a cols receives the width. */
  template <typename A> void
  download (std::vector<T, A> &host, int &cols) const
  {
    host.resize (static_cast<std::size_t> (rows_) * cols_);
    cols = cols_;
    download (host.data (), cols_ * sizeof (T));
  }

  void
  copyTo (DeviceArray2D &other) const
  {
    other.create (rows_, cols_);
    if (data_)
      PCL_TEXLET_CUDA_CHECK (cudaMemcpy2D (other.data_.get (), other.step_, data_.get (), step_, colsBytes (), rows_,
                                           cudaMemcpyDeviceToDevice));
  }

  void
  swap (DeviceArray2D &other) noexcept
  {
    data_.swap (other.data_);
    std::swap (step_, other.step_);
    std::swap (rows_, other.rows_);
    std::swap (cols_, other.cols_);
  }

  /** \brief Row \a y. */
  T *
  ptr (int y = 0) { return reinterpret_cast<T *> (static_cast<char *> (data_.get ()) + y * step_); }
  const T *
  ptr (int y = 0) const { return reinterpret_cast<const T *> (static_cast<const char *> (data_.get ()) + y * step_); }

  /** \brief Bytes from one row to the next (the pitch). */
  std::size_t
  step () const { return step_; }
  int
  rows () const { return rows_; }
  int
  cols () const { return cols_; }
  std::size_t
  colsBytes () const { return static_cast<std::size_t> (cols_) * sizeof (T); }
  bool
  empty () const { return !data_; }

private:
  std::shared_ptr<void> data_;
  std::size_t step_ = 0;
  int rows_ = 0, cols_ = 0;
};

} // namespace gpu
} // namespace texlet
} // namespace pcl
