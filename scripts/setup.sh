#!/usr/bin/env bash
# Shared set-up for scripts/test.sh and scripts/demo.sh: install the Debian
# packages texbake builds with (only those missing), then configure and build
# Release into build/. Source it; it defines TEXBAKE_ROOT and TEXBAKE_BUILD.
set -euo pipefail

TEXBAKE_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
TEXBAKE_BUILD=${TEXBAKE_BUILD:-$TEXBAKE_ROOT/build}

texbake_packages=(
  build-essential cmake pkg-config
  libopenmesh-dev libembree-dev libopenimageio-dev openimageio-tools
  libcgal-dev libgmp-dev libmpfr-dev libeigen3-dev libtbb-dev
  libcli11-dev nlohmann-json3-dev libtinygltf-dev
  libgtest-dev libbenchmark-dev
  clang libclang-rt-dev
)

texbake_install_packages() {
  local missing=()
  local p
  for p in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  if [ ${#missing[@]} -eq 0 ]; then
    return 0
  fi
  echo "texbake: installing Debian packages: ${missing[*]}" >&2
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
}

texbake_build() {
  local jobs
  jobs=$(nproc 2>/dev/null || echo 2)
  cmake -S "$TEXBAKE_ROOT" -B "$TEXBAKE_BUILD" -DCMAKE_BUILD_TYPE=Release "$@"
  cmake --build "$TEXBAKE_BUILD" --parallel "$jobs"
}

texbake_install_packages "${texbake_packages[@]}"
