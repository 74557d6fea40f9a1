/*
 * pcl_texlet common: numbers written to text files so that they read back exactly, and as a
 * person would write them (0.075 rather than 0.074999999999999997).
 */
#pragma once

#include <charconv>
#include <string>

namespace pcl
{
namespace texlet
{

/** \brief The shortest decimal text that reads back as exactly \a v (std::to_chars). */
inline std::string
shortestDecimal (double v)
{
  char buffer[32];
  const std::to_chars_result r = std::to_chars (buffer, buffer + sizeof (buffer), v);
  return std::string (buffer, r.ptr);
}

} // namespace texlet
} // namespace pcl
