/* Preloaded (LD_PRELOAD) by scripts/run_sanitizer_tests.sh into every process of the sanitizer
 * test run: dlclose() leaves shared objects mapped until the process exits.
 *
 * Why: LeakSanitizer checks for leaks at exit, after OpenNI2's shutdown has unloaded its drivers
 * (libOniFile, libPS1080, libPSLink and pcl_texlet's own simulated-device driver). The frames of
 * an unloaded module can no longer be named, so a leak inside a vendor driver could not be told
 * from one in ours, and test/sanitizer/lsan.supp could not name the vendor's library. With the
 * modules kept, every leak names the library it came from. Nothing else changes: no library here
 * relies on being unloaded before exit. Built without instrumentation, so it is harmless in the
 * uninstrumented programs the tests start (gnuplot, Xvfb). */
int
dlclose (void *handle)
{
  (void) handle;
  return 0;
}
