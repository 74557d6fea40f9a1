/*
 * pcl_texlet apps: no half-written output folder is left behind by a failed run.
 */
#pragma once

#include <filesystem>
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

} // namespace pcl_texlet_app
