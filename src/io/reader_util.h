/*
 * pcl_texlet io, internal: small pieces the readers share: image sizes and exception texts for
 * messages, file names by extension or suffix, and sorted listings of a folder.
 */
#pragma once

#include <pcl/exceptions.h>

#include <algorithm>
#include <cctype>
#include <exception>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace detail
{

/** \brief "640x480". */
inline std::string
sizeText (int width, int height)
{
  return std::to_string (width) + "x" + std::to_string (height);
}

/** \brief The text of an exception without PCL's "function in file @ line : " prefix, on one line. */
inline std::string
description (const std::exception &e)
{
  std::string text = e.what ();
  if (text.rfind (": ", 0) == 0)
    text.erase (0, 2);
  else if (const auto cut = text.find (" : "); cut != std::string::npos && dynamic_cast<const pcl::PCLException *> (&e))
    text.erase (0, cut + 3);
  // OpenNI2's messages come with tabs and newlines; the callers report on one line.
  std::string line;
  for (const char c : text)
  {
    if (std::isspace (static_cast<unsigned char> (c)))
    {
      if (!line.empty () && line.back () != ' ')
        line += ' ';
    }
    else
      line += c;
  }
  while (!line.empty () && line.back () == ' ')
    line.pop_back ();
  return line;
}

/** \brief Checks that \a folder exists and is a folder.
  * \throws pcl::IOException "<what>does not exist" or "<what>is not a folder" otherwise.
  */
inline void
requireFolder (const std::string &folder, const std::string &what)
{
  std::error_code ec;
  if (!std::filesystem::exists (folder, ec))
    throw pcl::IOException (what + "does not exist");
  if (!std::filesystem::is_directory (folder, ec))
    throw pcl::IOException (what + "is not a folder");
}

/** \brief The extension of \a path in lower case (".pcd" for "A.PCD"). */
inline std::string
lowerExtension (const std::filesystem::path &path)
{
  std::string ext = path.extension ().string ();
  std::transform (ext.begin (), ext.end (), ext.begin (), [] (unsigned char c) { return std::tolower (c); });
  return ext;
}

inline bool
endsWith (const std::string &text, const std::string &suffix)
{
  return text.size () >= suffix.size () && text.compare (text.size () - suffix.size (), suffix.size (), suffix) == 0;
}

/** \brief The regular files of \a folder whose name satisfies \a keep, sorted (one folder, so by
  * name); empty when \a folder is not a folder.
  * \throws pcl::IOException naming the folder when it cannot be listed.
  */
template <typename Keep> std::vector<std::string>
listFiles (const std::filesystem::path &folder, Keep keep)
{
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory (folder, ec))
    return files;
  for (fs::directory_iterator it (folder, ec), end; !ec && it != end; it.increment (ec))
  {
    std::error_code type_ec; // a dangling link is skipped, not an error of the listing
    if (keep (it->path ().filename ().string ()) && it->is_regular_file (type_ec))
      files.push_back (it->path ().string ());
  }
  if (ec)
    throw pcl::IOException ("folder '" + folder.string () + "': cannot list its files: " + ec.message ());
  std::sort (files.begin (), files.end ());
  return files;
}

} // namespace detail
} // namespace texlet
} // namespace pcl
