/*
 * pcl_texlet tests: the fixture of an app's tests. Each test runs the app with its own temporary
 * folder, where the app's stdout and stderr are captured.
 */
#pragma once

#include "support/app_run.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace pcl_texlet_test
{

/** \brief A test of the app at \a app (a path). */
class AppTest : public TempDirTest
{
protected:
  using Result = AppResult;

  explicit AppTest (std::string app) : app_ (std::move (app)) {}

  /** \brief Runs the app with \a args (shell words). */
  AppResult
  run (const std::string &args) const
  {
    return runApp (app_, args, dir_);
  }

  /** \brief Bad input: exit 2, exactly one line on stderr that mentions \a needle, and nothing new
    * left in the test's folder.
    */
  void
  expectRejected (const std::string &args, const std::string &needle) const
  {
    const std::vector<std::string> before = leftovers ();
    const AppResult r = run (args);
    EXPECT_EQ (r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ (std::count (r.err.begin (), r.err.end (), '\n'), 1) << r.err;
    EXPECT_NE (r.err.find (needle), std::string::npos) << "stderr: " << r.err << " should mention " << needle;
    EXPECT_EQ (leftovers (), before) << args;
  }

  std::string app_;
};

} // namespace pcl_texlet_test
