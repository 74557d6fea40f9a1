/*
 * pcl_texlet apps: the one error convention every command-line tool keeps.
 *
 * Bad input or options exit with code 2 and one line on stderr; anything unexpected exits 1.
 */
#pragma once

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
  catch (const std::exception &e)
  {
    std::cerr << name << ": internal error: " << e.what () << std::endl;
    return 1;
  }
}

} // namespace pcl_texlet_app
