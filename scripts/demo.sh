#!/usr/bin/env bash
# Quick start: installs what is missing, builds, deforms the bundled bunny with the
# bundled demo script, writes out/ (meshes, stats and pictures) and prints the stats summary.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh --target ffdtool
mkdir -p out
build/apps/ffdtool/ffdtool run test_data/bunny.obj test_data/demo.json \
  -o out/bunny_deformed.obj --stats out/stats.json --preview out/lattice.png
build/apps/ffdtool/ffdtool render test_data/bunny.obj -o out/before.png --size 640x480
build/apps/ffdtool/ffdtool render out/bunny_deformed.obj -o out/after.png --size 640x480
echo "demo: wrote out/bunny_deformed.obj, out/bunny_stretched.obj and out/stats.json"
echo "demo: pictures $(pwd)/out/before.png $(pwd)/out/after.png $(pwd)/out/lattice.png"
