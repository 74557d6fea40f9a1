#include "support/app_run.h"
#include "support/temp_dir.h"

#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/common/parallel_for.h>
#include <pcl_texlet/common/shortest_decimal.h>

#include <gtest/gtest.h>

#include <pcl/exceptions.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using pcl::texlet::AtomicFile;
using pcl::texlet::parallelFor;
using pcl::texlet::temporaryPathFor;
using pcl::texlet::writeFileAtomically;
using pcl_texlet_test::slurp;
using Files = pcl_texlet_test::TempDirTest;

TEST (ParallelFor, RunsEveryIterationOnce)
{
  for (const bool parallel : {false, true})
  {
    std::vector<std::atomic<int>> runs (1000);
    parallelFor (1000, 4, parallel, [&] (int i) { ++runs[i]; });
    for (int i = 0; i < 1000; ++i)
      ASSERT_EQ (runs[i].load (), 1) << "iteration " << i << (parallel ? " (parallel)" : " (serial)");
  }
}

TEST (ParallelFor, AnExceptionInOneIterationComesOutAfterAllIterationsRan)
{
  for (const bool parallel : {false, true})
  {
    std::atomic<int> runs {0};
    try
    {
      parallelFor (200, 4, parallel, [&] (int i) {
        ++runs;
        if (i == 37)
          throw std::runtime_error ("iteration 37 failed");
      });
      ADD_FAILURE () << "no exception came out of parallelFor";
    }
    catch (const std::runtime_error &e)
    {
      EXPECT_EQ (std::string (e.what ()), "iteration 37 failed");
    }
    EXPECT_EQ (runs.load (), 200) << (parallel ? "parallel" : "serial");
  }
}

TEST (ParallelFor, SeveralFailingIterationsRethrowOneOfTheirExceptions)
{
  std::atomic<int> runs {0};
  try
  {
    parallelFor (100, 4, true, [&] (int i) {
      ++runs;
      if (i % 10 == 3)
        throw std::out_of_range (std::to_string (i));
    });
    ADD_FAILURE () << "no exception came out of parallelFor";
  }
  catch (const std::out_of_range &e)
  {
    const int i = std::stoi (e.what ());
    EXPECT_EQ (i % 10, 3) << e.what ();
  }
  EXPECT_EQ (runs.load (), 100);
}

TEST (ParallelFor, SerialRunsInOrderOnTheCallingThread)
{
  const std::thread::id caller = std::this_thread::get_id ();
  std::vector<int> order;
  bool same_thread = true;
  try
  {
    parallelFor (10, 4, false, [&] (int i) {
      order.push_back (i);
      same_thread = same_thread && std::this_thread::get_id () == caller;
      if (i == 2 || i == 7)
        throw std::runtime_error (std::to_string (i));
    });
    ADD_FAILURE () << "no exception came out of parallelFor";
  }
  catch (const std::runtime_error &e)
  {
    EXPECT_EQ (std::string (e.what ()), "2"); // the first thrown, serially the lowest index
  }
  EXPECT_EQ (order, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_TRUE (same_thread);
}

TEST (ParallelFor, NoIterationsIsNothing)
{
  int runs = 0;
  parallelFor (0, 4, true, [&] (int) { ++runs; });
  parallelFor (-3, 4, true, [&] (int) { ++runs; });
  EXPECT_EQ (runs, 0);
}

// ---------------------------------------------------------------------------------------------
// The atomic writer

TEST (AtomicFile, TemporaryNameIsHiddenBesideTheDestinationWithItsExtension)
{
  const std::string pid = std::to_string (::getpid ());
  EXPECT_EQ (temporaryPathFor ("/a/b/depth.png"), "/a/b/.depth." + pid + ".tmp.png");
  EXPECT_EQ (temporaryPathFor ("out/take.oni"), "out/.take." + pid + ".tmp.oni");
  EXPECT_EQ (temporaryPathFor ("recording"), ".recording." + pid + ".tmp");
}

TEST_F (Files, WriteFileAtomicallyWritesTheBytesAndLeavesNothingElse)
{
  const std::string bytes ("a\0b\nc", 5);
  writeFileAtomically (file ("x.json"), bytes);
  EXPECT_EQ (slurp (file ("x.json")), bytes);
  writeFileAtomically (file ("x.json"), "replaced");
  EXPECT_EQ (slurp (file ("x.json")), "replaced");
  EXPECT_EQ (temp_.entries (), std::vector<std::string>{"x.json"});
}

TEST_F (Files, WriteFileAtomicallyIntoAMissingFolderThrowsNamingThePath)
{
  const std::string path = file ("no/such/x.json");
  try
  {
    writeFileAtomically (path, "text");
    ADD_FAILURE () << "no exception";
  }
  catch (const pcl::IOException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("cannot write '" + path + "'"), std::string::npos) << e.what ();
  }
  EXPECT_TRUE (temp_.entries ().empty ());
}

TEST_F (Files, AnUncommittedFileOrFolderIsRemoved)
{
  {
    AtomicFile f (file ("a.txt"));
    std::ofstream (f.temporaryPath ()) << "half";
    EXPECT_TRUE (fs::exists (f.temporaryPath ()));
  }
  {
    AtomicFile folder (file ("rec"));
    fs::create_directories (fs::path (folder.temporaryPath ()) / "depth");
    std::ofstream (fs::path (folder.temporaryPath ()) / "depth" / "0.png") << "half";
  }
  EXPECT_TRUE (temp_.entries ().empty ());
}

TEST_F (Files, CommitRenamesOntoTheDestinationAndAFailedOneNamesBoth)
{
  {
    AtomicFile f (file ("a.txt"));
    std::ofstream (f.temporaryPath ()) << "whole";
    f.commit ();
  }
  EXPECT_EQ (slurp (file ("a.txt")), "whole");
  EXPECT_EQ (temp_.entries (), std::vector<std::string>{"a.txt"});

  fs::create_directories (file ("busy/inside")); // a folder that is not empty cannot be renamed onto
  {
    AtomicFile f (file ("busy"));
    std::ofstream (f.temporaryPath ()) << "file";
    try
    {
      f.commit ();
      ADD_FAILURE () << "no exception";
    }
    catch (const pcl::IOException &e)
    {
      const std::string text = e.what ();
      EXPECT_NE (text.find ("'" + f.temporaryPath () + "' onto '" + file ("busy") + "'"), std::string::npos) << text;
    }
  }
  EXPECT_EQ (temp_.entries (), (std::vector<std::string>{"a.txt", "busy"}));
}

// ---------------------------------------------------------------------------------------------
// Exact decimal text

TEST (ShortestDecimal, ReadsBackExactlyInTheFewestDigits)
{
  EXPECT_EQ (pcl::texlet::shortestDecimal (0.075), "0.075");
  EXPECT_EQ (pcl::texlet::shortestDecimal (525), "525");
  EXPECT_EQ (pcl::texlet::shortestDecimal (-0.125), "-0.125");
  for (const double v : {1.0 / 3.0, 570.3422241210938, 1e-300, 6.02214076e23, -2.5e-7})
    EXPECT_EQ (std::strtod (pcl::texlet::shortestDecimal (v).c_str (), nullptr), v) << pcl::texlet::shortestDecimal (v);
}
