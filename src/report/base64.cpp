#include <pcl_texlet/report/base64.h>

namespace pcl
{
namespace texlet
{

std::string
base64 (const std::string &bytes)
{
  static const char *const table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto byte = [&] (std::size_t i) { return static_cast<unsigned> (static_cast<unsigned char> (bytes[i])); };
  std::string out;
  out.reserve ((bytes.size () + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size (); i += 3)
  {
    const unsigned v = byte (i) << 16 | byte (i + 1) << 8 | byte (i + 2);
    out += table[v >> 18 & 63];
    out += table[v >> 12 & 63];
    out += table[v >> 6 & 63];
    out += table[v & 63];
  }
  // The last one or two bytes: two or three characters, padded with '=' to four.
  if (i < bytes.size ())
  {
    const bool two = i + 1 < bytes.size ();
    const unsigned v = byte (i) << 16 | (two ? byte (i + 1) << 8 : 0u);
    out += table[v >> 18 & 63];
    out += table[v >> 12 & 63];
    out += two ? table[v >> 6 & 63] : '=';
    out += '=';
  }
  return out;
}

} // namespace texlet
} // namespace pcl
