/*
 * pcl_texlet common: the description a PCL exception was made with (what () prefixes ": " when no
 * function or file is named), for re-throwing with more context.
 */
#pragma once

#include <pcl/exceptions.h>

#include <string>

namespace pcl
{
namespace texlet
{

inline std::string
errorText (const pcl::PCLException &e)
{
  const std::string what = e.what ();
  return what.rfind (": ", 0) == 0 ? what.substr (2) : what;
}

} // namespace texlet
} // namespace pcl
