# Sanitizer and fuzzing builds (docs/fuzzing.md).
#
# PCL_TEXLET_SANITIZE: every target (library, apps, tests) with AddressSanitizer and
# UndefinedBehaviorSanitizer; any undefined behaviour aborts (-fno-sanitize-recover), so the test
# suite fails on it. GCC or clang. scripts/run_sanitizer_tests.sh builds it in build-asan/.
#
# PCL_TEXLET_FUZZ: the libFuzzer targets in test/fuzz/ (needs clang). The library is compiled
# with coverage instrumentation for libFuzzer (-fsanitize=fuzzer-no-link) and with ASan+UBSan, so
# the fuzzers see into it; each target links -fsanitize=fuzzer.
option(PCL_TEXLET_SANITIZE "Build everything with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(PCL_TEXLET_FUZZ "Build the libFuzzer targets in test/fuzz (needs clang; implies ASan+UBSan)" OFF)

if(PCL_TEXLET_SANITIZE OR PCL_TEXLET_FUZZ)
  set(_pcl_texlet_san_flags -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_compile_options(${_pcl_texlet_san_flags})
  # Under ASan Eigen stops trusting malloc's 16-byte alignment and switches to its own offset
  # allocator (Eigen/src/Core/util/Memory.h tests __SANITIZE_ADDRESS__), while Debian's
  # uninstrumented PCL keeps plain malloc/free: a PointCloud or grabber allocated on one side and
  # freed on the other would be freed at the wrong address. ASan's malloc is 16-byte aligned on
  # x86-64 (glibc's ABI), so the instrumented build keeps PCL's allocator.
  add_compile_definitions(EIGEN_MALLOC_ALREADY_ALIGNED=1)
  add_link_options(-fsanitize=address,undefined)
endif()

# Extra compile options for the library alone (appended after CMAKE_CXX_FLAGS_<CONFIG>, so an -O
# here wins). The sanitizer run (scripts/run_sanitizer_tests.sh) compiles everything at -Og, which
# halves the compile of the PCL-heavy apps and tests, and the library, where the tests spend their
# time, at -O2.
set(PCL_TEXLET_LIBRARY_COMPILE_OPTIONS "" CACHE STRING
  "Extra compile options for the pcl_texlet library only (the sanitizer build: -O2)")

if(PCL_TEXLET_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "PCL_TEXLET_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
