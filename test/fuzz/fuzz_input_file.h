/*
 * pcl_texlet fuzzing: the loaders that take a path get the fuzz input as a file. One file per
 * fuzzing process (the pid in its name), rewritten for every input, in $TMPDIR or /tmp.
 *
 * The library's documented failure is a pcl::PCLException (IOException, BadArgumentException)
 * naming the input: the targets catch only that. Any other exception escapes to libFuzzer,
 * which reports it as a crash: a finding like a sanitizer report.
 */
#pragma once

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

namespace pcl_texlet_fuzz
{

/** \brief A folder of this process's own under $TMPDIR (created once). */
inline const std::string &
scratchFolder ()
{
  static const std::string folder = [] {
    const char *tmp = std::getenv ("TMPDIR");
    std::string f = std::string (tmp && *tmp ? tmp : "/tmp") + "/pcl_texlet_fuzz_" + std::to_string (::getpid ());
    std::string cmd = "mkdir -p '" + f + "'";
    if (std::system (cmd.c_str ()) != 0)
      std::abort ();
    return f;
  }();
  return folder;
}

/** \brief Writes the fuzz input to \a name in the scratch folder; returns its path. */
inline std::string
writeInput (const std::string &name, const std::uint8_t *data, std::size_t size)
{
  const std::string path = scratchFolder () + "/" + name;
  std::ofstream out (path, std::ios::binary | std::ios::trunc);
  out.write (reinterpret_cast<const char *> (data), static_cast<std::streamsize> (size));
  out.close ();
  if (!out)
    std::abort ();
  return path;
}

} // namespace pcl_texlet_fuzz
