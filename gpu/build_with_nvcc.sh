#!/usr/bin/env bash
# Builds the GPU library, test_gpu_texlets, test_gpu_relation_kernels and pcl_texlet_gpu_bench with nvcc alone, for a
# machine without CMake. Dependencies come from .device-deps/ (gpu/stage_device_deps.sh).
# Usage: gpu/build_with_nvcc.sh [build-dir] [sm arch, default 90]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build-gpu-nvcc}
arch=${2:-90}
deps=.device-deps
nvcc=${NVCC:-$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)}
mkdir -p "$out"
flags=(-std=c++17 -O3 -arch=sm_${arch} --expt-relaxed-constexpr -Iinclude -I"$deps/include")
jobs=()
"$nvcc" "${flags[@]}" -c src/gpu/texlet_estimation.cu -o "$out/texlet_estimation.o" & jobs+=($!)
# The relations without FMA contraction: the CPU path's float operations (gpu/CMakeLists.txt).
"$nvcc" "${flags[@]}" --fmad=false -c src/gpu/texlet_relations.cu -o "$out/texlet_relations.o" & jobs+=($!)
"$nvcc" "${flags[@]}" -Iapps -Itest -c bench/gpu/pcl_texlet_gpu_bench.cu -o "$out/pcl_texlet_gpu_bench.o" & jobs+=($!)
gtest=$deps/googletest/googletest
"$nvcc" -std=c++17 -O2 -I"$gtest/include" -I"$gtest" -c "$gtest/src/gtest-all.cc" -o "$out/gtest-all.o" & jobs+=($!)
"$nvcc" -std=c++17 -O2 -I"$gtest/include" -c "$gtest/src/gtest_main.cc" -o "$out/gtest_main.o" & jobs+=($!)
"$nvcc" "${flags[@]}" -Itest -I"$gtest/include" -x cu -c test/gpu/test_gpu_texlets.cpp -o "$out/test_gpu_texlets.o" & jobs+=($!)
"$nvcc" "${flags[@]}" -Itest -I"$gtest/include" -c test/gpu/test_gpu_relation_kernels.cpp -o "$out/test_gpu_relation_kernels.o" & jobs+=($!)
for j in "${jobs[@]}"; do wait "$j"; done
"$nvcc" -arch=sm_${arch} "$out/pcl_texlet_gpu_bench.o" "$out/texlet_estimation.o" "$out/texlet_relations.o" -o "$out/pcl_texlet_gpu_bench"
"$nvcc" -arch=sm_${arch} "$out/test_gpu_texlets.o" "$out/texlet_estimation.o" "$out/gtest-all.o" "$out/gtest_main.o" \
  -lpthread -o "$out/test_gpu_texlets"
"$nvcc" -arch=sm_${arch} "$out/test_gpu_relation_kernels.o" "$out/texlet_relations.o" "$out/gtest-all.o" "$out/gtest_main.o" \
  -lpthread -o "$out/test_gpu_relation_kernels"
echo "built $out/test_gpu_texlets, $out/test_gpu_relation_kernels and $out/pcl_texlet_gpu_bench"
