#include <pcl_texlet/io/recording.h>

#include <pcl/exceptions.h>

#include <png.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

/** \brief "<path>.tmp", removed again unless commit () renamed it onto the final path, so that a
  * failed or interrupted write never leaves a half-written file under the final name.
  */
class TemporaryFile
{
public:
  TemporaryFile (const std::string &path, const std::string &what)
    : path_ (path), tmp_ (path + ".tmp"), what_ (what)
  {}

  TemporaryFile (const TemporaryFile &) = delete;
  TemporaryFile &
  operator= (const TemporaryFile &) = delete;

  ~TemporaryFile ()
  {
    if (!committed_)
    {
      std::error_code ec;
      fs::remove (tmp_, ec);
    }
  }

  const std::string &
  path () const { return tmp_; }

  void
  commit ()
  {
    if (std::rename (tmp_.c_str (), path_.c_str ()) != 0)
      throw pcl::IOException (what_ + " '" + path_ + "': cannot rename '" + tmp_ + "' onto it: " +
                              std::strerror (errno));
    committed_ = true;
  }

private:
  std::string path_;
  std::string tmp_;
  std::string what_;
  bool committed_ = false;
};

// ---------------------------------------------------------------------------------------------
// camera.yaml

pcl::IOException
cameraYamlError (const std::string &path, const std::string &problem)
{
  return pcl::IOException ("camera.yaml '" + path + "': " + problem);
}

YAML::Node
requiredKey (const YAML::Node &map, const std::string &key, const std::string &path)
{
  const YAML::Node node = map[key];
  if (!node)
    throw cameraYamlError (path, "missing key '" + key + "'");
  return node;
}

template <typename T> T
scalarAs (const YAML::Node &node, const std::string &key, const std::string &kind, const std::string &path)
{
  if (!node.IsScalar ())
    throw cameraYamlError (path, key + " must be " + kind);
  try
  {
    return node.as<T> ();
  }
  catch (const YAML::BadConversion &)
  {
    throw cameraYamlError (path, key + " must be " + kind + " (found '" + node.Scalar () + "')");
  }
}

/** \brief Reads \a key.data of a ROS matrix ({rows, cols, data}) as a list of finite numbers. */
std::vector<double>
matrixData (const YAML::Node &root, const std::string &key, const std::string &path)
{
  const YAML::Node matrix = requiredKey (root, key, path);
  if (!matrix.IsMap ())
    throw cameraYamlError (path, key + " must be a map with rows, cols and data");
  const YAML::Node data = matrix["data"];
  if (!data || !data.IsSequence ())
    throw cameraYamlError (path, key + ".data must be a list of numbers");
  std::vector<double> values;
  for (std::size_t i = 0; i < data.size (); ++i)
  {
    const std::string item = key + ".data[" + std::to_string (i) + "]";
    const double v = scalarAs<double> (data[i], item, "a number", path);
    if (!std::isfinite (v))
      throw cameraYamlError (path, item + " must be finite (found " + data[i].Scalar () + ")");
    values.push_back (v);
  }
  return values;
}

/** \brief rows and cols are redundant with data in ROS files; where present they must agree. */
void
checkMatrixShape (const YAML::Node &root, const std::string &key, int rows, int cols, const std::string &path)
{
  const YAML::Node matrix = root[key];
  const YAML::Node r = matrix["rows"];
  const YAML::Node c = matrix["cols"];
  const int found_rows = r ? scalarAs<int> (r, key + ".rows", "an integer", path) : rows;
  const int found_cols = c ? scalarAs<int> (c, key + ".cols", "an integer", path) : cols;
  if (found_rows != rows || found_cols != cols)
  {
    std::ostringstream msg;
    msg << key << " is declared " << found_rows << "x" << found_cols << " but must be " << rows << "x" << cols;
    throw cameraYamlError (path, msg.str ());
  }
}

/** \brief Optional positive quantity; \a value keeps its default when the key is absent. */
void
optionalPositive (const YAML::Node &root, const std::string &key, double &value, const std::string &path)
{
  const YAML::Node node = root[key];
  if (!node)
    return;
  const double v = scalarAs<double> (node, key, "a number", path);
  if (!(v > 0) || !std::isfinite (v))
    throw cameraYamlError (path, key + " must be positive and finite (found " + node.Scalar () + ")");
  value = v;
}

/** \brief Shortest text that reads back as exactly \a v (0.075 rather than 0.074999999999999997). */
std::string
shortestDecimal (double v)
{
  char buffer[32];
  const std::to_chars_result r = std::to_chars (buffer, buffer + sizeof (buffer), v);
  return std::string (buffer, r.ptr);
}

void
emitMatrix (YAML::Emitter &out, const std::string &key, int rows, int cols, const double *data)
{
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "rows" << YAML::Value << rows;
  out << YAML::Key << "cols" << YAML::Value << cols;
  out << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < rows * cols; ++i)
    out << shortestDecimal (data[i]);
  out << YAML::EndSeq << YAML::EndMap;
}

// ---------------------------------------------------------------------------------------------
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

std::string
sizeText (int width, int height)
{
  return std::to_string (width) + "x" + std::to_string (height);
}

} // namespace

// ---------------------------------------------------------------------------------------------

CameraInfo
loadCameraInfoYaml (const std::string &path)
{
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw cameraYamlError (path, "file does not exist");

  YAML::Node root;
  try
  {
    root = YAML::LoadFile (path);
  }
  catch (const YAML::BadFile &)
  {
    throw cameraYamlError (path, "cannot open");
  }
  catch (const YAML::ParserException &e)
  {
    throw cameraYamlError (path, "not valid YAML (line " + std::to_string (e.mark.line + 1) + ", column " +
                                     std::to_string (e.mark.column + 1) + ": " + e.msg + ")");
  }
  if (!root.IsMap ())
    throw cameraYamlError (path, "not a YAML map of camera_info keys");

  CameraInfo info;
  info.width = scalarAs<int> (requiredKey (root, "image_width", path), "image_width", "an integer", path);
  info.height = scalarAs<int> (requiredKey (root, "image_height", path), "image_height", "an integer", path);
  if (info.width <= 0 || info.height <= 0)
    throw cameraYamlError (path, "image_width and image_height must be positive (found " +
                                     sizeText (info.width, info.height) + ")");
  if (info.width > kMaxImageSide || info.height > kMaxImageSide)
    throw cameraYamlError (path, "image_width and image_height must be at most " + std::to_string (kMaxImageSide) +
                                     " (found " + sizeText (info.width, info.height) + ")");

  const std::vector<double> k = matrixData (root, "camera_matrix", path);
  if (k.size () != 9)
    throw cameraYamlError (path, "camera_matrix.data must have 9 numbers (found " + std::to_string (k.size ()) + ")");
  checkMatrixShape (root, "camera_matrix", 3, 3, path);
  std::copy (k.begin (), k.end (), info.K);
  if (!(info.fx () > 0) || !(info.fy () > 0))
  {
    std::ostringstream msg;
    msg << "focal lengths fx and fy must be positive (found fx " << info.fx () << ", fy " << info.fy () << ")";
    throw cameraYamlError (path, msg.str ());
  }

  info.distortion_model = scalarAs<std::string> (requiredKey (root, "distortion_model", path), "distortion_model",
                                                 "a string", path);
  info.D = matrixData (root, "distortion_coefficients", path);
  if (info.distortion_model == "plumb_bob" && info.D.size () != 5)
    throw cameraYamlError (path, "distortion_coefficients.data must have 5 numbers for plumb_bob (found " +
                                     std::to_string (info.D.size ()) + ")");
  if (info.D.size () > 8)
    throw cameraYamlError (path, "distortion_coefficients.data must have at most 8 numbers (found " +
                                     std::to_string (info.D.size ()) + ")");
  checkMatrixShape (root, "distortion_coefficients", 1, static_cast<int> (info.D.size ()), path);

  optionalPositive (root, "baseline_m", info.baseline_m, path);
  optionalPositive (root, "disparity_subpixel", info.disparity_subpixel, path);
  return info;
}

void
saveCameraInfoYaml (const std::string &path, const CameraInfo &info)
{
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "image_width" << YAML::Value << info.width;
  out << YAML::Key << "image_height" << YAML::Value << info.height;
  emitMatrix (out, "camera_matrix", 3, 3, info.K);
  out << YAML::Key << "distortion_model" << YAML::Value << info.distortion_model;
  emitMatrix (out, "distortion_coefficients", 1, static_cast<int> (info.D.size ()), info.D.data ());
  // ROS's camera_calibration_parsers also require these two; for a depth camera they are the
  // identity rectification and K extended by a zero column.
  const double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double P[12] = {info.K[0], info.K[1], info.K[2], 0, info.K[3], info.K[4], info.K[5], 0,
                        info.K[6], info.K[7], info.K[8], 0};
  emitMatrix (out, "rectification_matrix", 3, 3, R);
  emitMatrix (out, "projection_matrix", 3, 4, P);
  out << YAML::Key << "baseline_m" << YAML::Value << shortestDecimal (info.baseline_m);
  out << YAML::Key << "disparity_subpixel" << YAML::Value << shortestDecimal (info.disparity_subpixel);
  out << YAML::EndMap;
  if (!out.good ())
    throw cameraYamlError (path, "cannot format as YAML: " + out.GetLastError ());

  TemporaryFile tmp (path, "camera.yaml");
  {
    std::ofstream file (tmp.path (), std::ios::binary);
    if (!file)
      throw cameraYamlError (path, "cannot create '" + tmp.path () + "': " + std::strerror (errno));
    file << out.c_str () << '\n';
    file.close ();
    if (!file)
      throw cameraYamlError (path, "cannot write '" + tmp.path () + "'");
  }
  tmp.commit ();
}

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

/** \brief Writes one PNG through \a encode (writeDepthRows or writeRgbRows) into "<path>.tmp",
  * renamed onto \a path once complete.
  */
template <typename Sample, typename Encode> void
writePng (const std::string &path, const char *what, const Sample *pixels, int width, int height, Encode encode)
{
  const std::string prefix = std::string (what) + " '" + path + "': ";
  if (!pixels || width <= 0 || height <= 0)
    throw pcl::BadArgumentException (prefix + "nothing to write (image " + sizeText (width, height) + ")");

  TemporaryFile tmp (path, what);
  {
    PngWriteHandle handle;
    PngContext &ctx = handle.ctx;
    ctx.file = std::fopen (tmp.path ().c_str (), "wb");
    if (!ctx.file)
      throw pcl::IOException (prefix + "cannot create '" + tmp.path () + "': " + std::strerror (errno));
    ctx.png = png_create_write_struct (PNG_LIBPNG_VER_STRING, &ctx, pngError, pngWarning);
    if (ctx.png)
      ctx.info = png_create_info_struct (ctx.png);
    if (!ctx.info)
      throw pcl::IOException (prefix + "libpng could not allocate its write structures");
    if (!encode (&ctx, pixels, width, height))
      throw pcl::IOException (prefix + "cannot write '" + tmp.path () + "' (libpng: " + ctx.error + ")");
    if (!handle.close ())
      throw pcl::IOException (prefix + "cannot write '" + tmp.path () + "': " + std::strerror (errno));
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

// ---------------------------------------------------------------------------------------------

RecordingFolderReader::RecordingFolderReader (const std::string &folder) : folder_ (folder)
{
  const std::string what = "recording folder '" + folder + "': ";
  std::error_code ec;
  if (!fs::exists (folder, ec))
    throw pcl::IOException (what + "does not exist");
  if (!fs::is_directory (folder, ec))
    throw pcl::IOException (what + "is not a folder");

  info_ = loadCameraInfoYaml ((fs::path (folder) / "camera.yaml").string ());

  const fs::path depth_dir = fs::path (folder) / "depth";
  if (!fs::is_directory (depth_dir, ec))
    throw pcl::IOException (what + "has no depth/ subfolder");
  for (fs::directory_iterator it (depth_dir, ec), end; !ec && it != end; it.increment (ec))
    if (it->path ().extension () == ".png" && it->is_regular_file ())
      depth_files_.push_back (it->path ().string ());
  if (ec)
    throw pcl::IOException (what + "cannot list depth/: " + ec.message ());
  if (depth_files_.empty ())
    throw pcl::IOException (what + "depth/ is empty (no .png files)");
  // All in one folder, so sorting the paths sorts by file name.
  std::sort (depth_files_.begin (), depth_files_.end ());
}

bool
RecordingFolderReader::next (DepthFrame &frame)
{
  if (next_ >= depth_files_.size ())
    return false;
  // Advance before reading, so a caller that catches a bad frame's exception can go on past it.
  const std::string depth_path = depth_files_[next_++];
  const std::string camera_yaml = (fs::path (folder_) / "camera.yaml").string ();
  const auto checkSize = [&] (const std::string &path, const char *what, int width, int height) {
    if (width != info_.width || height != info_.height)
      throw pcl::IOException (std::string (what) + " '" + path + "' is " + sizeText (width, height) +
                              " but camera.yaml says " + sizeText (info_.width, info_.height) + " ('" +
                              camera_yaml + "')");
  };

  DepthFrame result;
  result.name = fs::path (depth_path).stem ().string ();
  result.depth_mm = readDepthPng (depth_path, result.width, result.height);
  checkSize (depth_path, "depth PNG", result.width, result.height);

  const fs::path rgb_path = fs::path (folder_) / "rgb" / (result.name + ".png");
  std::error_code ec;
  if (fs::exists (rgb_path, ec))
  {
    int width = 0;
    int height = 0;
    result.rgb = readRgbPng (rgb_path.string (), width, height);
    checkSize (rgb_path.string (), "RGB PNG", width, height);
  }
  frame = std::move (result);
  return true;
}

bool
RecordingFolderReader::isRecordingFolder (const std::string &folder)
{
  std::error_code ec;
  return fs::is_regular_file (fs::path (folder) / "camera.yaml", ec) && fs::is_directory (fs::path (folder) / "depth", ec);
}

} // namespace texlet
} // namespace pcl
