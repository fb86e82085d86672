#!/usr/bin/env bash
# Runs the benchmarks and writes bench_out/bench.json (also printed).
# Usage: scripts/bench.sh [--suite ffd|remesh|bcm|cholesky|all] [--quick]
# The real meshes come from ../shared/meshes when present, else from Debian's
# libcgal-demo package (downloaded once with apt-get download, unpacked into .cache/).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh --target ffdbench
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
mkdir -p bench_out
build/apps/ffdbench/ffdbench --meshes "$meshes" --test-data test_data -o bench_out/bench.json "$@"
cat bench_out/bench.json
