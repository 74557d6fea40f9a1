/*
 * pcl_texlet report: base64, to embed images in self-contained HTML reports (data: URIs).
 */
#pragma once

#include <string>

namespace pcl
{
namespace texlet
{

/** \brief The standard base64 encoding (RFC 4648, alphabet A-Z a-z 0-9 + /, '=' padding) of
  * \a bytes.
  */
std::string
base64 (const std::string &bytes);

} // namespace texlet
} // namespace pcl
