/*
 * pcl_texlet apps: no half-written output folder is left behind by a failed run. A folder written
 * whole (a recording set, a study) goes through an OutputFolder, under the one temporary name of
 * include/pcl_texlet/common/atomic_file.h; an app that writes complete files into a folder it may
 * have created guards that folder with a FolderGuard.
 */
#pragma once

#include "app_main.h"

#include <pcl_texlet/common/atomic_file.h>

#include <pcl/exceptions.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <utility>

namespace pcl_texlet_app
{

/** \brief Removes a folder on destruction unless released: the output of a failed run. */
class FolderGuard
{
public:
  explicit FolderGuard (std::filesystem::path p) : path_ (std::move (p)) {}
  FolderGuard (const FolderGuard &) = delete;
  FolderGuard &
  operator= (const FolderGuard &) = delete;
  ~FolderGuard ()
  {
    std::error_code ec;
    if (!path_.empty ())
      std::filesystem::remove_all (path_, ec);
  }
  void
  release () { path_.clear (); }

private:
  std::filesystem::path path_;
};

/** \brief The absolute path of the output folder \a output that a run is to create, checked before
  * any work so that bad input costs nothing: it must not exist yet (\a never_replaced says why an
  * existing one is not written over), and the folder that holds it must.
  * \throws InputError naming \a output
  */
inline std::filesystem::path
newOutputFolder (const std::string &output, const std::string &never_replaced)
{
  std::error_code ec;
  const std::filesystem::path out = std::filesystem::absolute (output, ec);
  if (std::filesystem::exists (out, ec))
    throw InputError ("OUTPUT '" + output + "' already exists (" + never_replaced + ")");
  if (!std::filesystem::is_directory (out.parent_path (), ec))
    throw InputError ("the folder that should hold OUTPUT '" + output + "' does not exist");
  return out;
}

/** \brief An output folder written under a temporary name (pcl::texlet::temporaryPathFor, beside
  * the destination) and renamed onto the destination by publish () once complete. Until then the
  * destructor removes the temporary folder with all it holds.
  */
class OutputFolder
{
public:
  /** \brief Creates the empty temporary folder of \a out; \a shown names \a out in messages as
    * the user gave it.
    * \throws pcl::IOException when the temporary folder cannot be created
    */
  OutputFolder (const std::filesystem::path &out, std::string shown) : folder_ (out.string ()), shown_ (std::move (shown))
  {
    std::error_code ec;
    std::filesystem::remove_all (folder_.temporaryPath (), ec); // left by an earlier process of the same id
    if (!std::filesystem::create_directory (folder_.temporaryPath (), ec))
      throw pcl::IOException ("cannot create the temporary folder '" + folder_.temporaryPath () + "': " + ec.message ());
  }

  /** \brief Where the files go until publish (). */
  std::filesystem::path
  temporary () const { return folder_.temporaryPath (); }

  /** \brief Renames the complete temporary folder onto the destination. A destination that
    * appeared while the run was writing (another run, a user) is not replaced: that is an error,
    * and the destructor then removes the temporary folder.
    * \throws pcl::IOException when the destination appeared meanwhile or the rename fails
    */
  void
  publish ()
  {
    std::error_code ec;
    if (std::filesystem::exists (folder_.path (), ec))
      throw pcl::IOException ("OUTPUT '" + shown_ + "' appeared while writing; not replaced");
    folder_.commit ();
  }

private:
  pcl::texlet::AtomicFile folder_;
  std::string shown_;
};

} // namespace pcl_texlet_app
