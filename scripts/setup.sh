#!/usr/bin/env bash
# Installs every build and test dependency of ffdtool from Debian's packages.
# Idempotent: packages already present are left alone and apt is not touched at all
# when nothing is missing. Nothing is downloaded at build time.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libcgal-dev libeigen3-dev libsuitesparse-dev libsleef-dev libnanoflann-dev
  libcli11-dev nlohmann-json3-dev libtinyobjloader-dev libtinygltf-dev libpng-dev
  libdraco-dev libmeshoptimizer-dev
  libpugixml-dev zlib1g-dev libfmt-dev
  libgtest-dev libgmock-dev libssl-dev
  libcgal-demo
  libxml2-utils
  python3
  python3-dev pybind11-dev python3-numpy python3-scipy python3-pytest
  python3-meshio
  assimp-utils
  gmsh tetgen
  # clang, its sanitizer runtimes and OpenMP: the sanitizers' build
  # (scripts/sanitize_test.sh) and the fuzzers (scripts/fuzz.sh)
  clang libclang-rt-dev libomp-dev
)
# Node (Debian's nodejs, with npm) runs Khronos' glTF-Validator; a machine that has node
# and npm from elsewhere keeps them.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then packages+=(nodejs npm); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
else
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Khronos' glTF-Validator, from npm's registry (the glTF tests run it with node), into a
# cache outside the repository; tests/gltf/validate.js finds it there.
validator_version=2.0.0-dev.3.10
npm_prefix="${FFD_NPM_PREFIX:-$HOME/.cache/ffdtool/npm}"
if ! grep -qs "\"version\": \"$validator_version\"" "$npm_prefix/node_modules/gltf-validator/package.json"; then
  echo "setup: installing gltf-validator $validator_version into $npm_prefix"
  mkdir -p "$npm_prefix"
  npm install --prefix "$npm_prefix" --no-audit --no-fund --no-save "gltf-validator@$validator_version"
fi
echo "setup: done"
