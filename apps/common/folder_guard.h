/*
 * pcl_texlet apps: no half-written output folder is left behind by a failed run.
 */
#pragma once

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

/** \brief The last step of writing an output folder under a temporary name: renames the
  * complete folder \a tmp (held by \a guard) onto \a out and releases the guard. An \a out that
  * appeared while the run was writing (another run, a user) is not replaced: that is an error,
  * and the guard then removes \a tmp. \a shown names \a out in messages as the user gave it.
  * \throws pcl::IOException when \a out appeared meanwhile or the rename fails
  */
inline void
publishFolder (const std::filesystem::path &tmp, const std::filesystem::path &out, const std::string &shown,
               FolderGuard &guard)
{
  std::error_code ec;
  if (std::filesystem::exists (out, ec))
    throw pcl::IOException ("OUTPUT '" + shown + "' appeared while writing; not replaced");
  std::filesystem::rename (tmp, out, ec);
  if (ec)
    throw pcl::IOException ("cannot rename '" + tmp.string () + "' onto '" + shown + "': " + ec.message ());
  guard.release ();
}

} // namespace pcl_texlet_app
