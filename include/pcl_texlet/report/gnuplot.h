/*
 * pcl_texlet report: running gnuplot, without a shell: the reports' plots are drawn by gnuplot
 * scripts (pngcairo), and no path or title in them is ever read by a shell.
 */
#pragma once

#include <string>

namespace pcl
{
namespace texlet
{

/** \brief Runs `gnuplot SCRIPT` as a child process (no shell), its standard output and error
  * going to the file \a log (created or truncated), and waits for it.
  * \throws pcl::IOException naming \a script when gnuplot cannot be started, or when it exits
  *         with a status other than 0 or is killed; the message then holds the first lines of
  *         what gnuplot wrote to \a log.
  */
void
runGnuplot (const std::string &script, const std::string &log);

/** \brief Whether `gnuplot` can be run and has the pngcairo terminal (asked without a shell). */
bool
gnuplotAvailable ();

} // namespace texlet
} // namespace pcl
