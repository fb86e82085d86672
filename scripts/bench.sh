#!/usr/bin/env bash
# Runs the benchmarks and writes bench_out/bench.json (also printed).
# Usage: scripts/bench.sh [--suite ffd|remesh|bcm|cholesky|io|pictures|multires|seam|deformers|compare|python|users|volume|all] [--quick]
# The io and users suites run Blender side by side when `blender` is on PATH (not a setup.sh
# package: it is a benchmark peer, ~90 MB); without it those rows say it is missing.
# The users suite runs PyGeM's FFD beside ffdtool when PYGEM_SOURCE names PyGeM's source
# tree (github mathLab/PyGeM; no default); without it its rows say "PYGEM_SOURCE not set".
# The real meshes come from ../shared/meshes when present, else from Debian's
# libcgal-demo package (downloaded once with apt-get download, unpacked into .cache/).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh --target ffdbench ffdtool  # the io suite runs ffdtool
meshes="${FFD_MESHES:-../shared/meshes}"
if [ ! -f "$meshes/bunny00.off" ]; then
  meshes=.cache/meshes
  if [ ! -f "$meshes/bunny00.off" ]; then
    mkdir -p .cache/deb "$meshes"
    (cd .cache/deb && { apt-get download libcgal-demo >/dev/null 2>&1 ||
      { apt-get update -qq && apt-get download libcgal-demo >/dev/null; }; } && dpkg-deb -x libcgal-demo_*.deb root)
    tar -xzf .cache/deb/root/usr/share/doc/libcgal-dev/data.tar.gz -C .cache/deb \
      data/meshes/armadillo.off data/meshes/bunny00.off data/meshes/refined_elephant.off
    cp .cache/deb/data/meshes/*.off "$meshes/"
  fi
fi
suite=all
for ((i = 1; i <= $#; i++)); do
  if [ "${!i}" = --suite ] && [ $i -lt $# ]; then j=$((i + 1)); suite="${!j}"; fi
done
if { [ "$suite" = io ] || [ "$suite" = users ] || [ "$suite" = all ]; } && ! command -v blender >/dev/null 2>&1; then
  echo "bench: no blender on PATH; apt-get install blender gives the io and users suites' side-by-side rows"
fi
mkdir -p bench_out
build/apps/ffdbench/ffdbench --meshes "$meshes" --test-data test_data -o bench_out/bench.json "$@"
cat bench_out/bench.json
