#!/usr/bin/env bash
# Installs the Debian 12 packages anisurf needs (only those missing).
# Usage: scripts/install-deps.sh [--no-gl]
set -euo pipefail

packages=(cmake ninja-build g++ pkg-config libeigen3-dev libtinygltf-dev doctest-dev
          libmuparser-dev nlohmann-json3-dev python3
          python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest)
if [[ "${1:-}" != "--no-gl" ]]; then
  packages+=(libglfw3-dev libglm-dev libimgui-dev libosmesa6-dev libstb-dev libgl-dev xvfb xauth fonts-dejavu-core)
fi
packages+=(zlib1g-dev)  # zlib-compressed VTK XML data arrays (engine/io/vtk_xml_encoding.cpp)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
