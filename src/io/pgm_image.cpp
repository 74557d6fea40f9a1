#include <pcl_texlet/io/pgm_image.h>

#include <pcl_texlet/camera/camera_info.h> // kMaxImageSide

#include <pcl/exceptions.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "reader_util.h"

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

pcl::IOException
pgmError (const std::string &path, const std::string &problem)
{
  return pcl::IOException ("PGM '" + path + "': " + problem);
}

/** \brief The next header number of a PGM: whitespace and '#' comments (to the end of the line)
  * before it are skipped, as the specification allows. The whitespace character after the
  * number is consumed: after maxval (\a ends_header) it is the one that ends the header.
  * \throws pcl::IOException naming \a what when there is no number.
  */
long long
headerNumber (std::istream &in, const std::string &what, bool ends_header, const std::string &path)
{
  int c = in.get ();
  while (c != std::char_traits<char>::eof () && (std::isspace (c) || c == '#'))
  {
    if (c == '#')
      while (c != std::char_traits<char>::eof () && c != '\n' && c != '\r')
        c = in.get ();
    c = in.get ();
  }
  if (c == std::char_traits<char>::eof () || !std::isdigit (c))
    throw pgmError (path, "header ends before its " + what + " (truncated or not a PGM)");
  long long value = 0;
  // Digits beyond what any field may hold are counted as too large, not overflowed.
  for (; c != std::char_traits<char>::eof () && std::isdigit (c); c = in.get ())
    value = value > 1000000000LL ? value : value * 10 + (c - '0');
  if (c == '#' && !ends_header)
    in.unget (); // a comment right after the number: the next field skips it
  else if (c != std::char_traits<char>::eof () && !std::isspace (c))
    throw pgmError (path, "header's " + what + " is followed by '" + std::string (1, static_cast<char> (c)) +
                              "' instead of whitespace");
  return value;
}

} // namespace

std::vector<std::uint16_t>
readPgm16 (const std::string &path, int &width, int &height)
{
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw pgmError (path, "file does not exist");
  std::ifstream in (path, std::ios::binary);
  if (!in)
    throw pgmError (path, std::string ("cannot open: ") + std::strerror (errno));

  char magic[2] = {0, 0};
  in.read (magic, 2);
  if (in.gcount () < 2 || magic[0] != 'P' || magic[1] < '1' || magic[1] > '7')
    throw pgmError (path, "not a PGM file (no 'P5' magic number)");
  if (magic[1] != '5')
    throw pgmError (path, std::string ("not a binary grey PGM: magic number 'P") + magic[1] + "', expected 'P5'" +
                              (magic[1] == '2' ? " (P2 is ASCII PGM)" : ""));

  const long long w = headerNumber (in, "width", false, path);
  const long long h = headerNumber (in, "height", false, path);
  const long long maxval = headerNumber (in, "maxval", true, path);
  if (w <= 0 || h <= 0)
    throw pgmError (path, "image size " + std::to_string (w) + "x" + std::to_string (h) + " is not positive");
  if (w > kMaxImageSide || h > kMaxImageSide)
    throw pgmError (path, "image size " + std::to_string (w) + "x" + std::to_string (h) + " beyond " +
                              std::to_string (kMaxImageSide) + " a side");
  if (maxval < 1 || maxval > 65535)
    throw pgmError (path, "maxval " + std::to_string (maxval) + " outside 1..65535");
  if (maxval < 256)
    throw pgmError (path, "8-bit PGM (maxval " + std::to_string (maxval) +
                              "); raw disparity needs 16-bit samples (maxval 256..65535, e.g. 2047 or 65535)");

  const std::size_t count = static_cast<std::size_t> (w) * static_cast<std::size_t> (h);
  std::vector<unsigned char> bytes (2 * count);
  in.read (reinterpret_cast<char *> (bytes.data ()), static_cast<std::streamsize> (bytes.size ()));
  const auto got = static_cast<std::size_t> (in.gcount ());
  if (got < bytes.size ())
    throw pgmError (path, "truncated: " + detail::sizeText (static_cast<int> (w), static_cast<int> (h)) +
                              " of 16-bit samples needs " + std::to_string (bytes.size ()) + " bytes of pixel data, found " +
                              std::to_string (got));

  std::vector<std::uint16_t> samples (count);
  for (std::size_t i = 0; i < count; ++i)
    samples[i] = static_cast<std::uint16_t> ((bytes[2 * i] << 8) | bytes[2 * i + 1]);
  width = static_cast<int> (w);
  height = static_cast<int> (h);
  return samples;
}

} // namespace texlet
} // namespace pcl
