#!/usr/bin/env bash
# Installs every build and test dependency of ffdtool from Debian's packages.
# Idempotent: packages already present are left alone and apt is not touched at all
# when nothing is missing. Nothing is downloaded at build time.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libcgal-dev libeigen3-dev libsuitesparse-dev libsleef-dev libnanoflann-dev
  libcli11-dev nlohmann-json3-dev libtinyobjloader-dev libtinygltf-dev libpng-dev
  libgtest-dev libgmock-dev libssl-dev
  libcgal-demo
  libxml2-utils
  python3
  python3-dev pybind11-dev python3-numpy python3-scipy python3-pytest
  python3-meshio
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
