#!/usr/bin/env bash
# Builds pcl_texlet with AddressSanitizer + UndefinedBehaviorSanitizer in build-asan/ and runs the
# test suite there, all but most of the model lab's statistical proofs (below; docs/fuzzing.md).
# Any sanitizer report fails the test that caused it.
#
# The build leaves out what the normal build (scripts/build.sh) already covers and what costs time
# without adding sanitizer coverage: CUDA (nvcc compiles the same kernels there) and the Google
# Benchmark programs. The library, where the tests spend their time, is compiled at -O2; the apps
# and tests at -Og, which halves the compile of their PCL-heavy code (docs/fuzzing.md). -g0 keeps
# compiling cheap (ASan still names functions and files in its reports). A unity build compiles
# each library's sources as one file: their headers (PCL, Eigen, Ceres) are parsed once per
# library, not once per source (docs/fuzzing.md, "In CI").
# Extra arguments go to cmake's configure. Set PCL_TEXLET_SANITIZE_JOBS to change parallelism.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${PCL_TEXLET_SANITIZE_JOBS:-$(nproc 2>/dev/null || echo 2)}
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi

t0=$(date +%s)
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS_RELEASE="-Og -g0 -DNDEBUG" -DCMAKE_C_FLAGS_RELEASE="-Og -g0 -DNDEBUG" \
  -DPCL_TEXLET_LIBRARY_COMPILE_OPTIONS=-O2 \
  -DPCL_TEXLET_SANITIZE=ON -DPCL_TEXLET_WITH_CUDA=OFF -DCMAKE_CUDA_COMPILER= \
  -DPCL_TEXLET_BUILD_BENCHMARKS=OFF -DCMAKE_UNITY_BUILD=ON "${launcher[@]}" "$@"
cmake --build build-asan -j "$jobs"
t1=$(date +%s)

# Leaks in third-party libraries (see test/sanitizer/lsan.supp for each and why) are suppressed;
# everything else, including every UBSan finding, aborts the process with a non-zero exit.
supp_dir=$(pwd)/test/sanitizer
# verify_asan_link_order=0: keep_modules_loaded comes before the ASan runtime (LD_PRELOAD below).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=0:check_initialization_order=1:verify_asan_link_order=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$supp_dir/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# OpenMP threads sleep instead of spinning while they wait: two test processes share the cores.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-PASSIVE}
cd build-asan
status=0
# Shared objects stay mapped until exit, so that LeakSanitizer can name the library of every leak
# (test/sanitizer/keep_modules_loaded.c).
# The model lab's statistical proofs (each ranks every candidate effect, so each runs the same
# lab code) run in the Release suite only: here the same code runs in the lab app's tests (the real
# frames: every candidate ranked, the quantisation on a lattice of the depths' own), the distortion's
# shape search in the few-frame walls' (docs/fuzzing.md, "In CI").
proofs='^ModelLabProof[.]|^ModelLabIndependentProof[.]'
# Of the residual diagnostics' cases (the same code on other walls) the clean walls run here; of the
# terms built from the data, the case without colour frames; of the texlets' banded walls, the
# column stripes (the rows run the same kernels along the other axis; the window's kernels run
# here in PcaSampler.WindowCorrelatedNoise..., the lab's window fit in DataDrivenTerms.WindowTerm...).
proofs+='|^ResidualDiagnostics[.](Finds|StripesInTheModel|DriftInTheModel)|^DataDrivenTerms[.](IntensityTermExplains|RowTermExplains)|^TexletCovariances[.](RowBands|WindowCorrelation)'
# Of the single-frame sets, the generator's distortion (the simulator's and the clean walls run the
# same single-frame code).
proofs+='|^ModelLabFewFrames[.](SingleFrameWallsOfTheSimulator|CleanSingleFrame)'
LD_PRELOAD=$(pwd)/test/sanitizer/libkeep_modules_loaded.so ctest --output-on-failure -j "$jobs" -E "$proofs" || status=$?
t2=$(date +%s)
echo "run_sanitizer_tests: build $((t1 - t0)) s, ctest $((t2 - t1)) s (jobs=$jobs), status $status"
exit $status
