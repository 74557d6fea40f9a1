/*
 * pcl_texlet tests: running a command-line app and capturing what it says, shared by the apps'
 * end-to-end tests.
 */
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace pcl_texlet_test
{

/** \brief A shell prefix for commands whose peak memory a test bounds. Under AddressSanitizer
  * freed memory waits in a quarantine (256 MB by default) before it is reused, so a longer run's
  * peak grows with what it freed; without the quarantine a bound means what it means in the normal
  * build. Empty elsewhere.
  */
#if defined(__SANITIZE_ADDRESS__)
inline const std::string kPeakMemoryEnvironment = "ASAN_OPTIONS=\"$ASAN_OPTIONS:quarantine_size_mb=0\" ";
#else
inline const std::string kPeakMemoryEnvironment;
#endif

/** \brief What a command did: its exit code (-1 if it did not exit normally), stdout, stderr. */
struct AppResult
{
  int code = -1;
  std::string out, err;
  long peak_rss_kb = 0; ///< the largest resident set of the command and what it ran, KiB
};

/** \brief The bytes of a file ("" when it cannot be read). */
inline std::string
slurp (const std::filesystem::path &p)
{
  std::ifstream f (p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf ();
  return s.str ();
}

/** \brief Runs \a command_line through the shell, its stdout and stderr captured in files
  * "stdout" and "stderr" of \a capture_dir (which must exist).
  */
inline AppResult
runCommand (const std::string &command_line, const std::filesystem::path &capture_dir)
{
  const std::filesystem::path out = capture_dir / "stdout", err = capture_dir / "stderr";
  const std::string cmd = command_line + " > '" + out.string () + "' 2> '" + err.string () + "'";
  AppResult r;
  // fork and wait4 rather than std::system, for the child's resource usage: its ru_maxrss is the
  // largest of the shell and the processes it waited for.
  const pid_t pid = ::fork ();
  if (pid == 0)
  {
    ::execl ("/bin/sh", "sh", "-c", cmd.c_str (), static_cast<char *> (nullptr));
    ::_exit (127);
  }
  int status = 0;
  struct rusage usage = {};
  if (pid > 0 && ::wait4 (pid, &status, 0, &usage) == pid)
  {
    r.code = WIFEXITED (status) ? WEXITSTATUS (status) : -1;
    r.peak_rss_kb = usage.ru_maxrss;
  }
  r.out = slurp (out);
  r.err = slurp (err);
  return r;
}

/** \brief Runs \a app with \a args (already quoted as the shell needs), as runCommand. */
inline AppResult
runApp (const std::string &app, const std::string &args, const std::filesystem::path &capture_dir)
{
  return runCommand (app + " " + args, capture_dir);
}

/** \brief Lines of \a text (newline characters). */
inline std::size_t
lineCount (const std::string &text)
{
  return static_cast<std::size_t> (std::count (text.begin (), text.end (), '\n'));
}

} // namespace pcl_texlet_test
