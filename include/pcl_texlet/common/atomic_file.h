/*
 * pcl_texlet common: files (and whole folders) written under a temporary name beside their
 * destination and renamed onto it once complete, so that no reader ever finds a half-written one
 * under the final name, and a failed or interrupted write leaves nothing behind.
 */
#pragma once

#include <pcl/exceptions.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include <unistd.h>

namespace pcl
{
namespace texlet
{

/** \brief The name \a path is written under until it is complete: "<dir>/.<stem>.<pid>.tmp<ext>".
  * Hidden; unique per process; in the destination's folder, so that the rename stays on one file
  * system; and ending in \a path's extension, for writers that go by it (OpenNI2 plays and counts
  * only files named *.oni).
  */
inline std::string
temporaryPathFor (const std::string &path)
{
  const std::filesystem::path p (path);
  return (p.parent_path () / ("." + p.stem ().string () + "." + std::to_string (::getpid ()) + ".tmp" +
                              p.extension ().string ()))
      .string ();
}

/** \brief The temporary of one file or folder being written: temporaryPath () is where the writer
  * writes, commit () renames it onto path (). Until then the destructor removes it (with all it
  * holds), so that an exception on the way leaves no partial output.
  */
class AtomicFile
{
public:
  explicit AtomicFile (const std::string &path) : path_ (path), tmp_ (temporaryPathFor (path)) {}

  AtomicFile (const AtomicFile &) = delete;
  AtomicFile &
  operator= (const AtomicFile &) = delete;

  ~AtomicFile ()
  {
    if (!committed_)
    {
      std::error_code ec;
      std::filesystem::remove_all (tmp_, ec);
    }
  }

  /** \brief The destination. */
  const std::string &
  path () const { return path_; }

  /** \brief Where the writer writes. */
  const std::string &
  temporaryPath () const { return tmp_; }

  /** \brief Renames the complete temporary onto path () (replacing a file there).
    * \throws pcl::IOException naming both; the temporary is then removed by the destructor.
    */
  void
  commit ()
  {
    if (std::rename (tmp_.c_str (), path_.c_str ()) != 0)
      throw pcl::IOException ("cannot rename '" + tmp_ + "' onto '" + path_ + "': " + std::strerror (errno));
    committed_ = true;
  }

private:
  std::string path_;
  std::string tmp_;
  bool committed_ = false;
};

/** \brief Writes \a bytes to \a path through an AtomicFile.
  * \throws pcl::IOException naming \a path when it cannot be written or renamed into place.
  */
inline void
writeFileAtomically (const std::string &path, const std::string &bytes)
{
  AtomicFile file (path);
  {
    std::ofstream out (file.temporaryPath (), std::ios::binary);
    out << bytes;
    out.close ();
    if (!out)
      throw pcl::IOException ("cannot write '" + path + "'");
  }
  file.commit ();
}

} // namespace texlet
} // namespace pcl
