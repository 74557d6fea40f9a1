/*
 * Internal: whole files written under a temporary name beside the destination and renamed when
 * complete, so that no half-written file is ever left under the final name.
 */
#pragma once

#include <pcl/exceptions.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>
#include <filesystem>

#include <unistd.h>

namespace pcl
{
namespace texlet
{
namespace detail
{

/** \brief "<dir>/.<name>.<pid>.tmp<ext>": hidden, unique per process, same file system. */
inline std::string
temporaryPathFor (const std::string &path)
{
  const std::filesystem::path p (path);
  return (p.parent_path () / ("." + p.stem ().string () + "." + std::to_string (::getpid ()) + ".tmp" +
                              p.extension ().string ()))
      .string ();
}

/** \brief Renames \a tmp onto \a path. \throws pcl::IOException (the temporary is removed). */
inline void
commitTemporary (const std::string &tmp, const std::string &path)
{
  if (std::rename (tmp.c_str (), path.c_str ()) != 0)
  {
    const std::string why = std::strerror (errno);
    std::error_code ec;
    std::filesystem::remove (tmp, ec);
    throw pcl::IOException ("cannot rename '" + tmp + "' onto '" + path + "': " + why);
  }
}

/** \brief Writes \a text to \a path through a temporary file. \throws pcl::IOException. */
inline void
writeTextFile (const std::string &path, const std::string &text)
{
  const std::string tmp = temporaryPathFor (path);
  {
    std::ofstream out (tmp, std::ios::binary);
    out << text;
    out.close ();
    if (!out)
    {
      std::error_code ec;
      std::filesystem::remove (tmp, ec);
      throw pcl::IOException ("cannot write '" + path + "'");
    }
  }
  commitTemporary (tmp, path);
}

} // namespace detail
} // namespace texlet
} // namespace pcl
