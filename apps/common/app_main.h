/*
 * pcl_texlet apps: the one error convention every command-line tool keeps.
 *
 * Bad input or options (InputError, or the library's pcl::PCLException) exit with code 2 and
 * one line on stderr; anything unexpected exits 1.
 */
#pragma once

#include <CLI/CLI.hpp>
// The GPU benchmark uses this header on machines without PCL: the PCL parts are then left out.
#if __has_include(<pcl/exceptions.h>)
#include <pcl/console/print.h>
#include <pcl/exceptions.h>
#define PCL_TEXLET_APP_WITH_PCL 1
#endif

#include <iostream>
#include <stdexcept>
#include <string>

namespace pcl_texlet_app
{

/** \brief Bad input or options: reported on one line, exit code 2. */
struct InputError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/** \brief PCL's exceptions prefix their text with ": " when no function is named. */
inline std::string
pclMessage (const std::string &what)
{
  return what.rfind (": ", 0) == 0 ? what.substr (2) : what;
}

/** \brief Parses the command line into \a app's options.
  * \return false when --help was asked for: the help (and \a help_extra) is printed, and the
  *         app should exit 0.
  * \throws InputError for a bad option or argument.
  * Also quiets PCL's console: errors come from the app, on one line.
  */
inline bool
parseCommandLine (CLI::App &app, int argc, char **argv, const std::string &help_extra = "")
{
  try
  {
    app.parse (argc, argv);
  }
  catch (const CLI::CallForHelp &)
  {
    std::cout << app.help () << help_extra;
    return false;
  }
  catch (const CLI::ParseError &e)
  {
    throw InputError (e.what ());
  }
#ifdef PCL_TEXLET_APP_WITH_PCL
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
#endif
  return true;
}

/** \brief Runs \a run (argc, argv) and turns its exceptions into the exit codes above. */
template <typename Run> int
runApp (const char *name, Run &&run, int argc, char **argv)
{
  try
  {
    return run (argc, argv);
  }
  catch (const InputError &e)
  {
    std::cerr << name << ": error: " << e.what () << std::endl;
    return 2;
  }
#ifdef PCL_TEXLET_APP_WITH_PCL
  catch (const pcl::PCLException &e) // the library's exceptions name the input and the problem
  {
    std::cerr << name << ": error: " << pclMessage (e.what ()) << std::endl;
    return 2;
  }
#endif
  catch (const std::exception &e)
  {
    std::cerr << name << ": internal error: " << e.what () << std::endl;
    return 1;
  }
}

} // namespace pcl_texlet_app
