#include <pcl_texlet/io/png_image.h>

#include <pcl_texlet/camera/camera_info.h> // kMaxImageSide
#include <pcl_texlet/common/atomic_file.h>

#include <pcl/exceptions.h>

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "reader_util.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

using detail::sizeText;

// PNG
//
// libpng reports errors by longjmp. A longjmp that skips the destructor of a C++ automatic object
// is undefined behaviour, so every function below that calls setjmp holds only trivially
// destructible locals and reaches the caller's objects through pointers; the C++ wrappers around
// them own the resources (RAII) and turn the error text into a pcl::IOException.

/** \brief libpng state shared with the error callback; trivially destructible on purpose. */
struct PngContext
{
  std::FILE *file = nullptr;
  png_structp png = nullptr;
  png_infop info = nullptr;
  char error[256] = "";
  bool libpng_error = false; ///< error holds libpng's own message (else one of ours)
};

void
pngError (png_structp png, png_const_charp message)
{
  PngContext *ctx = static_cast<PngContext *> (png_get_error_ptr (png));
  std::snprintf (ctx->error, sizeof (ctx->error), "%s", message);
  ctx->libpng_error = true;
  png_longjmp (png, 1);
}

/** \brief Warnings (unknown chunks, odd colour profiles) do not make the pixels wrong. */
void
pngWarning (png_structp, png_const_charp)
{}

bool
hostIsLittleEndian ()
{
  const std::uint16_t probe = 1;
  unsigned char first_byte;
  std::memcpy (&first_byte, &probe, 1);
  return first_byte == 1;
}

const char *
colourTypeName (int colour_type)
{
  switch (colour_type)
  {
    case PNG_COLOR_TYPE_GRAY: return "grey";
    case PNG_COLOR_TYPE_GRAY_ALPHA: return "grey+alpha";
    case PNG_COLOR_TYPE_PALETTE: return "palette";
    case PNG_COLOR_TYPE_RGB: return "RGB";
    case PNG_COLOR_TYPE_RGB_ALPHA: return "RGBA";
    default: return "unknown colour type";
  }
}

enum class PngKind { depth, rgb };

struct PngHeader
{
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int colour_type = 0;
};

struct PngReadHandle
{
  PngContext ctx;

  PngReadHandle () = default;
  PngReadHandle (const PngReadHandle &) = delete;
  PngReadHandle &
  operator= (const PngReadHandle &) = delete;

  ~PngReadHandle ()
  {
    if (ctx.png)
      png_destroy_read_struct (&ctx.png, &ctx.info, nullptr);
    if (ctx.file)
      std::fclose (ctx.file);
  }
};

/** \brief Reads the chunks up to the image data. Only trivially destructible locals (setjmp). */
bool
readPngHeader (PngContext *ctx, PngHeader *header)
{
  if (setjmp (png_jmpbuf (ctx->png)))
    return false;
  png_init_io (ctx->png, ctx->file);
  png_set_sig_bytes (ctx->png, 8);
  png_read_info (ctx->png, ctx->info);
  header->width = png_get_image_width (ctx->png, ctx->info);
  header->height = png_get_image_height (ctx->png, ctx->info);
  header->bit_depth = png_get_bit_depth (ctx->png, ctx->info);
  header->colour_type = png_get_color_type (ctx->png, ctx->info);
  return true;
}

/** \brief Decodes the image row by row straight into \a pixels (\a row_bytes per row), after
  * the caller checked the header. Only trivially destructible locals (setjmp).
  */
bool
readPngRows (PngContext *ctx, const PngHeader *header, unsigned char *pixels, std::size_t row_bytes)
{
  if (setjmp (png_jmpbuf (ctx->png)))
    return false;
  // PNG stores 16-bit samples big-endian.
  if (header->bit_depth == 16 && hostIsLittleEndian ())
    png_set_swap (ctx->png);
  if (header->colour_type == PNG_COLOR_TYPE_RGB_ALPHA)
    png_set_strip_alpha (ctx->png);
  const int passes = png_set_interlace_handling (ctx->png);
  png_read_update_info (ctx->png, ctx->info);
  if (png_get_rowbytes (ctx->png, ctx->info) != row_bytes)
  {
    std::snprintf (ctx->error, sizeof (ctx->error), "decoded row is %zu bytes, expected %zu",
                   static_cast<std::size_t> (png_get_rowbytes (ctx->png, ctx->info)), row_bytes);
    return false;
  }
  // Interlaced images come in several passes over the same rows; libpng merges each pass in.
  for (int pass = 0; pass < passes; ++pass)
    for (png_uint_32 y = 0; y < header->height; ++y)
      png_read_row (ctx->png, pixels + y * row_bytes, nullptr);
  // Reading to IEND catches files cut short after the last row and CRC errors in the tail.
  png_read_end (ctx->png, nullptr);
  return true;
}

template <typename T> std::vector<T>
readPng (const std::string &path, PngKind kind, int &width, int &height)
{
  const std::string what = kind == PngKind::depth ? "depth PNG" : "RGB PNG";
  const auto error = [&] (const std::string &problem) {
    return pcl::IOException (what + " '" + path + "': " + problem);
  };
  const auto libpngFailure = [&] (const PngContext &ctx) {
    if (!ctx.libpng_error)
      return error (ctx.error);
    if (std::feof (ctx.file))
      return error (std::string ("file is truncated (libpng: ") + ctx.error + ")");
    return error (std::string ("corrupt PNG data (libpng: ") + ctx.error + ")");
  };

  std::error_code ec;
  if (!fs::exists (path, ec))
    throw error ("file does not exist");

  PngReadHandle handle;
  PngContext &ctx = handle.ctx;
  ctx.file = std::fopen (path.c_str (), "rb");
  if (!ctx.file)
    throw error (std::string ("cannot open: ") + std::strerror (errno));
  png_byte signature[8];
  if (std::fread (signature, 1, sizeof (signature), ctx.file) != sizeof (signature) ||
      png_sig_cmp (signature, 0, sizeof (signature)) != 0)
    throw error ("not a PNG file (no PNG signature)");

  ctx.png = png_create_read_struct (PNG_LIBPNG_VER_STRING, &ctx, pngError, pngWarning);
  if (ctx.png)
    ctx.info = png_create_info_struct (ctx.png);
  if (!ctx.info)
    throw error ("libpng could not allocate its read structures");

  PngHeader header;
  if (!readPngHeader (&ctx, &header))
    throw libpngFailure (ctx);

  int channels = 1;
  if (kind == PngKind::depth)
  {
    if (header.bit_depth != 16 || header.colour_type != PNG_COLOR_TYPE_GRAY)
      throw error ("expected 16-bit grey depth, found " + std::to_string (header.bit_depth) + "-bit " +
                   colourTypeName (header.colour_type));
  }
  else
  {
    if (header.bit_depth != 8 ||
        (header.colour_type != PNG_COLOR_TYPE_RGB && header.colour_type != PNG_COLOR_TYPE_RGB_ALPHA))
      throw error ("expected 8-bit RGB or RGBA, found " + std::to_string (header.bit_depth) + "-bit " +
                   colourTypeName (header.colour_type));
    channels = 3;
  }

  // libpng caps both sizes at 1,000,000 by default, so they fit in an int; the header of a
  // corrupt or hostile file could still ask for terabytes before a row is read.
  if (header.width > static_cast<png_uint_32> (kMaxImageSide) || header.height > static_cast<png_uint_32> (kMaxImageSide))
    throw error ("image size " + std::to_string (header.width) + "x" + std::to_string (header.height) +
                 " is beyond the " + std::to_string (kMaxImageSide) + " pixels a side of any depth sensor (corrupt header?)");
  const std::size_t row_elements = std::size_t (header.width) * channels;
  // A header of a few bytes may claim up to 10^12 pixels (found by fuzz_depth_png). Deflate
  // expands at most 1032:1, so a file cannot hold more than 1032 times its size of filtered rows
  // (a row is its samples plus one filter byte); a larger claim is corrupt, and refusing it here
  // keeps a tiny file from making us allocate terabytes.
  const std::uintmax_t file_bytes = fs::file_size (path, ec);
  const double row_bytes = double (row_elements) * sizeof (T) + 1.0;
  if (!ec && double (header.height) * row_bytes > 1032.0 * double (file_bytes) + 1024.0)
    throw error ("the header's " + std::to_string (header.width) + " x " + std::to_string (header.height) +
                 " pixels cannot be held in the file's " + std::to_string (file_bytes) + " bytes (corrupt header)");
  std::vector<T> pixels (row_elements * header.height);
  if (!readPngRows (&ctx, &header, reinterpret_cast<unsigned char *> (pixels.data ()), row_elements * sizeof (T)))
    throw libpngFailure (ctx);

  width = static_cast<int> (header.width);
  height = static_cast<int> (header.height);
  return pixels;
}

struct PngWriteHandle
{
  PngContext ctx;

  PngWriteHandle () = default;
  PngWriteHandle (const PngWriteHandle &) = delete;
  PngWriteHandle &
  operator= (const PngWriteHandle &) = delete;

  ~PngWriteHandle ()
  {
    if (ctx.png)
      png_destroy_write_struct (&ctx.png, &ctx.info);
    if (ctx.file)
      std::fclose (ctx.file);
  }

  /** \brief Closes the file, reporting what fclose found (a full disk shows up here). */
  bool
  close ()
  {
    const int rc = std::fclose (ctx.file);
    ctx.file = nullptr;
    return rc == 0;
  }
};

/** \brief Encodes an 8-bit RGB image row by row. Only trivially destructible locals (setjmp). */
bool
writeRgbRows (PngContext *ctx, const std::uint8_t *rgb, int width, int height)
{
  if (setjmp (png_jmpbuf (ctx->png)))
    return false;
  png_init_io (ctx->png, ctx->file);
  png_set_IHDR (ctx->png, ctx->info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info (ctx->png, ctx->info);
  for (int y = 0; y < height; ++y)
    png_write_row (ctx->png, rgb + std::size_t (y) * width * 3);
  png_write_end (ctx->png, nullptr);
  return true;
}

/** \brief Encodes a 16-bit grey image row by row. Only trivially destructible locals (setjmp). */
bool
writeDepthRows (PngContext *ctx, const std::uint16_t *depth_mm, int width, int height)
{
  if (setjmp (png_jmpbuf (ctx->png)))
    return false;
  png_init_io (ctx->png, ctx->file);
  png_set_IHDR (ctx->png, ctx->info, width, height, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info (ctx->png, ctx->info);
  // PNG stores 16-bit samples big-endian; libpng swaps a copy of each row, never our buffer.
  if (hostIsLittleEndian ())
    png_set_swap (ctx->png);
  for (int y = 0; y < height; ++y)
    png_write_row (ctx->png, reinterpret_cast<png_const_bytep> (depth_mm + std::size_t (y) * width));
  png_write_end (ctx->png, nullptr);
  return true;
}
} // namespace

std::vector<std::uint16_t>
readDepthPng (const std::string &path, int &width, int &height)
{
  return readPng<std::uint16_t> (path, PngKind::depth, width, height);
}

std::vector<std::uint8_t>
readRgbPng (const std::string &path, int &width, int &height)
{
  return readPng<std::uint8_t> (path, PngKind::rgb, width, height);
}

namespace
{

/** \brief Writes one PNG through \a encode (writeDepthRows or writeRgbRows) into a temporary
  * file, renamed onto \a path once complete.
  */
template <typename Sample, typename Encode> void
writePng (const std::string &path, const char *what, const Sample *pixels, int width, int height, Encode encode)
{
  const std::string prefix = std::string (what) + " '" + path + "': ";
  if (!pixels || width <= 0 || height <= 0)
    throw pcl::BadArgumentException (prefix + "nothing to write (image " + sizeText (width, height) + ")");

  AtomicFile tmp (path);
  {
    PngWriteHandle handle;
    PngContext &ctx = handle.ctx;
    ctx.file = std::fopen (tmp.temporaryPath ().c_str (), "wb");
    if (!ctx.file)
      throw pcl::IOException (prefix + "cannot create '" + tmp.temporaryPath () + "': " + std::strerror (errno));
    ctx.png = png_create_write_struct (PNG_LIBPNG_VER_STRING, &ctx, pngError, pngWarning);
    if (ctx.png)
      ctx.info = png_create_info_struct (ctx.png);
    if (!ctx.info)
      throw pcl::IOException (prefix + "libpng could not allocate its write structures");
    if (!encode (&ctx, pixels, width, height))
      throw pcl::IOException (prefix + "cannot write '" + tmp.temporaryPath () + "' (libpng: " + ctx.error + ")");
    if (!handle.close ())
      throw pcl::IOException (prefix + "cannot write '" + tmp.temporaryPath () + "': " + std::strerror (errno));
  }
  tmp.commit ();
}

} // namespace

void
writeDepthPng (const std::string &path, const std::uint16_t *depth_mm, int width, int height)
{
  writePng (path, "depth PNG", depth_mm, width, height, writeDepthRows);
}

void
writeRgbPng (const std::string &path, const std::uint8_t *rgb, int width, int height)
{
  writePng (path, "RGB PNG", rgb, width, height, writeRgbRows);
}

} // namespace texlet
} // namespace pcl
