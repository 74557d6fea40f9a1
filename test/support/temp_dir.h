/*
 * pcl_texlet tests: a fresh, empty folder for each test, removed again after it, and the fixture
 * that gives one to every test of a suite.
 */
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

namespace pcl_texlet_test
{

/** \brief The names in \a folder (none when it does not exist) that are temporaries of an
  * unfinished write: every writer's temporary name holds ".tmp" (include/pcl_texlet/common/atomic_file.h),
  * and so did the older schemes.
  */
inline std::vector<std::string>
temporariesIn (const std::filesystem::path &folder)
{
  std::vector<std::string> names;
  std::error_code ec;
  for (std::filesystem::directory_iterator it (folder, ec), end; !ec && it != end; it.increment (ec))
    if (it->path ().filename ().string ().find (".tmp") != std::string::npos)
      names.push_back (it->path ().filename ().string ());
  return names;
}

/** \brief A folder of its own under the system's temporary folder, created empty and removed with
  * all it holds on destruction. Its name holds the process id and \a name, so that test processes
  * running side by side (ctest -j) never share one.
  */
class TempDir
{
public:
  explicit TempDir (const std::string &name)
  {
    std::string leaf = "pcl_texlet_" + name + "_" + std::to_string (::getpid ());
    std::replace (leaf.begin (), leaf.end (), '/', '_'); // parameterised tests' names hold '/'
    path_ = std::filesystem::temp_directory_path () / leaf;
    std::filesystem::remove_all (path_);
    std::filesystem::create_directories (path_);
  }

  /** \brief A folder named after the running test (suite and test name). */
  TempDir () : TempDir (currentTestName ()) {}

  TempDir (const TempDir &) = delete;
  TempDir &
  operator= (const TempDir &) = delete;

  ~TempDir ()
  {
    std::error_code ec;
    std::filesystem::remove_all (path_, ec);
  }

  const std::filesystem::path &
  path () const { return path_; }

  /** \brief The path of \a name in the folder, as a string. */
  std::string
  file (const std::string &name) const { return (path_ / name).string (); }

  /** \brief Writes \a bytes to \a name in the folder and returns its path. */
  std::filesystem::path
  write (const std::string &name, const std::string &bytes) const
  {
    const std::filesystem::path p = path_ / name;
    std::ofstream (p, std::ios::binary) << bytes;
    return p;
  }

  /** \brief The names of what \a folder (by default this one) holds, sorted, but for \a ignored. */
  std::vector<std::string>
  entries (const std::vector<std::string> &ignored = {}, const std::filesystem::path &folder = {}) const
  {
    std::vector<std::string> names;
    for (const auto &e : std::filesystem::directory_iterator (folder.empty () ? path_ : folder))
    {
      const std::string name = e.path ().filename ().string ();
      if (std::find (ignored.begin (), ignored.end (), name) == ignored.end ())
        names.push_back (name);
    }
    std::sort (names.begin (), names.end ());
    return names;
  }

  /** \brief "<suite>_<test>" of the running test. */
  static std::string
  currentTestName ()
  {
    const ::testing::TestInfo *test = ::testing::UnitTest::GetInstance ()->current_test_info ();
    return test ? std::string (test->test_suite_name ()) + "_" + test->name () : std::string ("no_test");
  }

private:
  std::filesystem::path path_;
};

/** \brief Fixture: every test gets a fresh TempDir named after it; dir_ is its path. */
class TempDirTest : public ::testing::Test
{
protected:
  TempDir temp_;
  const std::filesystem::path dir_ = temp_.path ();

  /** \brief The path of \a name in the test's folder. */
  std::string
  file (const std::string &name) const { return temp_.file (name); }

  /** \brief Writes \a bytes to \a name in the test's folder and returns its path. */
  std::filesystem::path
  write (const std::string &name, const std::string &bytes) const { return temp_.write (name, bytes); }

  /** \brief What a run left in the test's folder: its entries but the captured stdout and stderr
    * of runCommand (app_run.h).
    */
  std::vector<std::string>
  leftovers () const { return temp_.entries ({"stdout", "stderr"}); }
};

} // namespace pcl_texlet_test
