#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) into build-fuzz/ and runs each for
# SECONDS (default 60) from the seed corpus tests/fuzz/corpus/<target>/. New inputs go to
# build-fuzz/corpus/<target>/, findings to build-fuzz/findings/<target>/; copy a finding,
# once fixed, to tests/fuzz/regressions/<target>/ so that ctest replays it.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
#   (targets: obj off ply stl gltf gltf_draco gltf_meshopt vtu vtk msh su2 foam script run)
# run: a script run on a small sphere by the runner (tests/fuzz/run_input.h);
# gltf_draco, gltf_meshopt: the compressed stream of a small glTF (tests/fuzz/compressed_input.h).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(obj off ply stl gltf gltf_draco gltf_meshopt vtu vtk msh su2 foam script run)
scripts/setup.sh
if [ ! -f build-fuzz/build.ninja ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFFD_FUZZ=ON \
    -DFFD_BUILD_TESTS=OFF -DFFD_BUILD_BENCH=OFF -DFFD_ARCH=
fi
cmake --build build-fuzz --target $(printf 'fuzz_%s ' "${targets[@]}")
status=0
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$t" "build-fuzz/findings/$t"
  log="build-fuzz/fuzz_$t.log"
  touch "build-fuzz/.start_$t"
  # The run target's private folders go here, so that one a crash leaves stays in build-fuzz/.
  mkdir -p build-fuzz/tmp
  if ! TMPDIR="$PWD/build-fuzz/tmp" ASAN_OPTIONS=detect_leaks=0 "build-fuzz/tests/fuzz/fuzz_$t" "build-fuzz/corpus/$t" "tests/fuzz/corpus/$t" \
      -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
      -artifact_prefix="build-fuzz/findings/$t/" >"$log" 2>&1; then
    status=1
  fi
  execs=$(grep -E "stat::number_of_executed_units" "$log" | awk '{print $2}')
  found=$(find "build-fuzz/findings/$t" -type f -newer "build-fuzz/.start_$t" | wc -l)
  echo "fuzz $t: ${execs:-?} runs in ${seconds} s, corpus $(find "build-fuzz/corpus/$t" -type f | wc -l), new findings $found"
done
exit $status
