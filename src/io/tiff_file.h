/*
 * pcl_texlet io, internal: an open TIFF file for the TIFF readers. libtiff reports through
 * handlers; the per-file handlers of TIFFOpenExt keep the first error's text for the exception,
 * instead of libtiff's default of printing it to stderr.
 */
#pragma once

#include <pcl/exceptions.h>

#include <tiffio.h>

#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

namespace pcl
{
namespace texlet
{
namespace detail
{

struct TiffMessages
{
  std::string error;
};

inline int
tiffErrorHandler (TIFF *, void *user_data, const char *module, const char *format, va_list args)
{
  TiffMessages *messages = static_cast<TiffMessages *> (user_data);
  if (messages->error.empty ())
  {
    char text[512];
    std::vsnprintf (text, sizeof (text), format, args);
    messages->error = (module && *module ? std::string (module) + ": " : std::string ()) + text;
  }
  return 1; // handled: libtiff's global handler stays silent
}

/** \brief Warnings (unknown tags, odd but readable files) do not make the pixels wrong. */
inline int
tiffWarningHandler (TIFF *, void *, const char *, const char *, va_list)
{
  return 1;
}

/** \brief An open TIFF file, closed on destruction, with the messages of its handlers. */
class TiffFile
{
public:
  TiffFile (const std::string &path, const std::string &what) : path_ (path), what_ (what)
  {
    std::error_code ec;
    if (!std::filesystem::exists (path, ec))
      throw error ("file does not exist");
    TIFFOpenOptions *options = TIFFOpenOptionsAlloc ();
    if (!options)
      throw error ("libtiff could not allocate its options");
    TIFFOpenOptionsSetErrorHandlerExtR (options, tiffErrorHandler, &messages_);
    TIFFOpenOptionsSetWarningHandlerExtR (options, tiffWarningHandler, nullptr);
    tiff_ = TIFFOpenExt (path.c_str (), "r", options);
    TIFFOpenOptionsFree (options);
    if (!tiff_)
      throw error ("not a TIFF file, or truncated or unreadable (" + libtiffText () + ")");
  }

  TiffFile (const TiffFile &) = delete;
  TiffFile &
  operator= (const TiffFile &) = delete;

  ~TiffFile ()
  {
    if (tiff_)
      TIFFClose (tiff_);
  }

  TIFF *
  get () const { return tiff_; }

  pcl::IOException
  error (const std::string &problem) const
  {
    return pcl::IOException (what_ + " '" + path_ + "': " + problem);
  }

  std::string
  libtiffText () const
  {
    return "libtiff: " + (messages_.error.empty () ? std::string ("no message") : messages_.error);
  }

  /** \brief Image size, checked to be positive and small enough to allocate. */
  void
  size (std::uint32_t &width, std::uint32_t &height) const
  {
    if (!TIFFGetField (tiff_, TIFFTAG_IMAGEWIDTH, &width) || !TIFFGetField (tiff_, TIFFTAG_IMAGELENGTH, &height))
      throw error ("has no image width or length tag");
    // 2^28 pixels (16k x 16k) is far beyond any depth camera; it keeps the allocation sane.
    if (width == 0 || height == 0 || std::uint64_t (width) * height > (std::uint64_t (1) << 28))
      throw error ("has an image size of " + std::to_string (width) + "x" + std::to_string (height));
  }

private:
  std::string path_;
  std::string what_;
  TiffMessages messages_;
  TIFF *tiff_ = nullptr;
};

} // namespace detail
} // namespace texlet
} // namespace pcl
