#include <pcl_texlet/report/gnuplot.h>

#include <pcl/exceptions.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

namespace pcl
{
namespace texlet
{

namespace
{

/** \brief Lines of gnuplot's output quoted in an error: its messages name the line and the problem. */
constexpr int kQuotedLines = 5;

/** \brief The outcome of one child process. */
struct ChildExit
{
  int spawn_error = 0; ///< errno of a failed start (0: it ran)
  int status = 0;      ///< waitpid's status, once it ran
};

/** \brief Runs \a argv[0] (looked up in PATH) with the arguments \a argv, stdin from /dev/null,
  * stdout and stderr to \a output_fd, and waits for it.
  */
ChildExit
runChild (const std::vector<std::string> &argv, int output_fd)
{
  std::vector<char *> args;
  for (const std::string &a : argv)
    args.push_back (const_cast<char *> (a.c_str ()));
  args.push_back (nullptr);

  ChildExit child;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init (&actions);
  posix_spawn_file_actions_addopen (&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2 (&actions, output_fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2 (&actions, output_fd, STDERR_FILENO);
  pid_t pid = -1;
  child.spawn_error = posix_spawnp (&pid, args[0], &actions, nullptr, args.data (), environ);
  posix_spawn_file_actions_destroy (&actions);
  if (child.spawn_error != 0)
    return child;
  while (::waitpid (pid, &child.status, 0) < 0)
    if (errno != EINTR)
    {
      child.spawn_error = errno;
      break;
    }
  return child;
}

/** \brief The first non-empty lines of \a path, joined by " | ". */
std::string
firstLines (const std::string &path)
{
  std::ifstream in (path);
  std::string line, text;
  for (int n = 0; n < kQuotedLines && std::getline (in, line);)
  {
    if (line.find_first_not_of (" \t\r") == std::string::npos)
      continue;
    text += (text.empty () ? "" : " | ") + line;
    ++n;
  }
  return text;
}

} // namespace

void
runGnuplot (const std::string &script, const std::string &log)
{
  const std::string what = "gnuplot script '" + script + "': ";
  const int fd = ::open (log.c_str (), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw pcl::IOException (what + "cannot create the log '" + log + "': " + std::strerror (errno));
  const ChildExit child = runChild ({"gnuplot", script}, fd);
  ::close (fd);
  if (child.spawn_error != 0)
    throw pcl::IOException (what + "cannot run gnuplot: " + std::strerror (child.spawn_error));
  if (WIFEXITED (child.status) && WEXITSTATUS (child.status) == 0)
    return;
  const std::string how = WIFEXITED (child.status) ? "gnuplot exited with status " + std::to_string (WEXITSTATUS (child.status))
                          : WIFSIGNALED (child.status) ? "gnuplot was killed by signal " + std::to_string (WTERMSIG (child.status))
                                                       : "gnuplot failed";
  const std::string said = firstLines (log);
  throw pcl::IOException (what + how + (said.empty () ? "" : ": " + said));
}

bool
gnuplotAvailable ()
{
  const int fd = ::open ("/dev/null", O_WRONLY | O_CLOEXEC);
  if (fd < 0)
    return false;
  const ChildExit child = runChild ({"gnuplot", "-e", "set terminal pngcairo"}, fd);
  ::close (fd);
  return child.spawn_error == 0 && WIFEXITED (child.status) && WEXITSTATUS (child.status) == 0;
}

} // namespace texlet
} // namespace pcl
