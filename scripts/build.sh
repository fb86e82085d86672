#!/usr/bin/env bash
# Configures and builds ffdtool (optimized) into build/. Used by demo.sh, test.sh and bench.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${FFD_BUILD_DIR:-build}"
jobs="${FFD_JOBS:-$(nproc)}"
if [ ! -f "$build_dir/build.ninja" ]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build_dir" -j "$jobs" "$@"
