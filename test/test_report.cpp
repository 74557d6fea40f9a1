/*
 * The report module's tools: base64 for embedded images, and gnuplot run without a shell.
 */
#include "support/temp_dir.h"

#include <pcl_texlet/report/base64.h>
#include <pcl_texlet/report/gnuplot.h>

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;
using pcl::texlet::base64;
using Gnuplot = pcl_texlet_test::TempDirTest;

TEST (Base64, Rfc4648TestVectors)
{
  EXPECT_EQ (base64 (""), "");
  EXPECT_EQ (base64 ("f"), "Zg==");
  EXPECT_EQ (base64 ("fo"), "Zm8=");
  EXPECT_EQ (base64 ("foo"), "Zm9v");
  EXPECT_EQ (base64 ("foob"), "Zm9vYg==");
  EXPECT_EQ (base64 ("fooba"), "Zm9vYmE=");
  EXPECT_EQ (base64 ("foobar"), "Zm9vYmFy");
}

TEST (Base64, EveryByteValue)
{
  std::string bytes;
  for (int i = 0; i < 256; ++i)
    bytes += static_cast<char> (i);
  const std::string b = base64 (bytes);
  ASSERT_EQ (b.size (), 344u); // 4 * ceil (256 / 3)
  EXPECT_EQ (b.substr (0, 8), "AAECAwQF");
  EXPECT_EQ (b.substr (b.size () - 8), "/P3+/w==");
  EXPECT_EQ (base64 (std::string ("\xff\xfe\xfd", 3)), "//79");
}

TEST_F (Gnuplot, DrawsAPngFromAScriptWithoutAShell)
{
  if (!pcl::texlet::gnuplotAvailable ())
    GTEST_SKIP () << "gnuplot with the pngcairo terminal is not installed";
  // A name a shell would take apart: gnuplot gets it as one argument.
  const std::string script = file ("it's a $(plot) `script`.gp");
  write (fs::path (script).filename ().string (),
         "set terminal pngcairo size 64,48\nset output '" + file ("p.png") + "'\nplot x\n");
  pcl::texlet::runGnuplot (script, file ("log.txt"));
  EXPECT_GT (fs::file_size (file ("p.png")), 0u);
  EXPECT_TRUE (fs::exists (file ("log.txt")));
}

TEST_F (Gnuplot, AFailingScriptIsAnErrorNamingItAndQuotingGnuplot)
{
  if (!pcl::texlet::gnuplotAvailable ())
    GTEST_SKIP () << "gnuplot with the pngcairo terminal is not installed";
  const std::string script = write ("bad.gp", "set terminal no_such_terminal\n").string ();
  try
  {
    pcl::texlet::runGnuplot (script, file ("log.txt"));
    ADD_FAILURE () << "no exception";
  }
  catch (const pcl::IOException &e)
  {
    const std::string text = e.what ();
    EXPECT_NE (text.find (script), std::string::npos) << text;
    EXPECT_NE (text.find ("exited with status"), std::string::npos) << text;
    EXPECT_NE (text.find ("unknown or ambiguous terminal"), std::string::npos) << text;
  }
}

TEST_F (Gnuplot, NoGnuplotIsAnErrorNotACrash)
{
  const char *path = std::getenv ("PATH");
  const std::string saved = path ? path : "";
  setenv ("PATH", file ("empty").c_str (), 1);
  EXPECT_FALSE (pcl::texlet::gnuplotAvailable ());
  try
  {
    pcl::texlet::runGnuplot (write ("a.gp", "plot x\n").string (), file ("log.txt"));
    ADD_FAILURE () << "no exception";
  }
  catch (const pcl::IOException &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("cannot run gnuplot"), std::string::npos) << e.what ();
  }
  setenv ("PATH", saved.c_str (), 1);
}
