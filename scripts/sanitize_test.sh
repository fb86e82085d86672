#!/usr/bin/env bash
# Builds the library, the CLI and the tests with ASan and UBSan (clang, -O1 -g1,
# -DFFD_SANITIZE=ON) into build-asan/ and runs the whole ctest suite under them. The CLI
# tests spawn the sanitized ffdtool of the same build, so its runs are checked too. No
# benchmarks. Any sanitizer report, a leak included, fails the test it happened in.
# FFD_ARCH empty (the compiler's default x86-64, no AVX, no FMA): the portable build,
# whose kernels KernelPortability compares with the default build's; the sanitizers
# check the same code either way.
# clang, not gcc: the same instrumented -O1 build compiles in about 60% of gcc's time
# (cold, 2 cores: 832 s -> 528 s), and the released objects stay gcc's (build/). With
# UBSan's object-size check left to ASan, the tests' own code without line tables and
# the Hausdorff oracles in their own uninstrumented library, cold on 2 cores: build
# 428 s, suite 131-152 s (it was 260-312 s). The tests' own code is not instrumented
# (tests/CMakeLists.txt): the sanitizers check the library and the CLI they call.
# clang's runtimes and OpenMP come from scripts/setup.sh (libclang-rt-dev, libomp-dev).
# A build-asan/ configured with another compiler is configured afresh.
# Run scripts/test.sh first: its default build's kernel outputs are the reference here.
# Usage: scripts/sanitize_test.sh [CTEST ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${FFD_ASAN_BUILD_DIR:-build-asan}"
jobs="${FFD_JOBS:-$(nproc)}"
scripts/setup.sh
# The portable build's lattice kernels are compared with the default build's (build/,
# written by scripts/test.sh): KernelPortability in tests/kernel_portability_test.cpp.
reference="$PWD/${FFD_BUILD_DIR:-build}/kernel_outputs.bin"
if [ ! -f "$build_dir/build.ninja" ] || ! grep -qs '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' "$build_dir/CMakeCache.txt"; then
  CC=clang CXX=clang++ cmake --fresh -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DFFD_SANITIZE=ON \
    -DFFD_BUILD_TESTS=ON -DFFD_BUILD_BENCH=OFF -DFFD_ARCH= -DFFD_KERNEL_REFERENCE="$reference"
else
  cmake "$build_dir" -DFFD_ARCH= -DFFD_KERNEL_REFERENCE="$reference" >/dev/null
fi
cmake --build "$build_dir" -j "$jobs"
# halt_on_error: the first report ends the process (UBSan's too: -fno-sanitize-recover).
# detect_leaks: LeakSanitizer at exit. The test binary's children inherit these.
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="print_suppressions=0"
# clang's OpenMP runtime (libomp 14) loses a thread record each time a parallel region's
# team grows back after shrinking ("hot teams"; Render.OneAndTwoThreadsGiveTheSameBytes
# runs 1, 2 then 7 threads), which LeakSanitizer reports as a direct leak from inside
# libomp. Without hot teams every team is built afresh and nothing leaks; that changes
# only how libomp reuses its threads, so no leak of ours is hidden.
export KMP_HOT_TEAMS_MAX_LEVEL=0
ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" "$@"
