#!/usr/bin/env bash
# Shared set-up for scripts/test.sh and scripts/demo.sh. Source it; it
# defines TEXBAKE_ROOT and TEXBAKE_BUILD and the functions below, and
# installs nothing by itself:
#   texbake_install_packages PKG...  apt-get install of those missing
#   texbake_build [TARGET...]        configure Release into build/, build the
#                                    targets (all when none is given)
# texbake_build_packages are what the library and the `texbake` executable
# build with (the demo needs only these); texbake_test_packages are added for
# the test suite, the benchmarks and the fuzzers (and the Python module, its
# pytest tests and GNU parallel for the batch shards); texbake_peer_packages
# are the peers bench/peers/run.sh compares with.
set -euo pipefail

TEXBAKE_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
TEXBAKE_BUILD=${TEXBAKE_BUILD:-$TEXBAKE_ROOT/build}

texbake_build_packages=(
  build-essential cmake pkg-config
  libopenmesh-dev libembree-dev libopenimageio-dev openimageio-tools
  libcgal-dev libgmp-dev libmpfr-dev libeigen3-dev libtbb-dev
  libcli11-dev nlohmann-json3-dev libtinygltf-dev libpugixml-dev
)
texbake_test_packages=(
  libgtest-dev libbenchmark-dev
  clang libclang-rt-dev clang-format
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-open3d parallel
  nodejs
)
# Node.js runs the Khronos glTF-Validator of the tests (tests/gltf; the
# suite's GltfValidator.Install fetches it with npm from the npm registry
# into the build folder). Debian's npm only when no npm came with Node.js
# (NodeSource's nodejs ships its own and conflicts with Debian's).
if ! command -v npm >/dev/null 2>&1; then texbake_test_packages+=(npm); fi
# The peers bench/peers/run.sh times texbake against (by hand, not the suite).
texbake_peer_packages=(
  meshlab blender xvfb xauth
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

# texbake_build [TARGET...]: with targets (the demo) the tests and
# benchmarks are not configured, so their packages need not be installed.
texbake_build() {
  local jobs targets=()
  jobs=$(nproc 2>/dev/null || echo 2)
  local suite=ON
  if [ $# -gt 0 ]; then
    suite=OFF
    local t
    for t in "$@"; do targets+=(--target "$t"); done
  fi
  # A build folder configured with the suite keeps it (a demo after the tests
  # must not drop them from build/).
  if [ -f "$TEXBAKE_BUILD/CMakeCache.txt" ] &&
    grep -q '^TEXBAKE_BUILD_TESTS:BOOL=ON' "$TEXBAKE_BUILD/CMakeCache.txt"; then
    suite=ON
  fi
  local extra=()
  if command -v ccache >/dev/null 2>&1; then extra=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  # The whole suite (no targets named) needs the Python module: ask for it,
  # so that a build folder whose cache says otherwise (one configured by the
  # demo before pybind11 was installed, by an older texbake) builds it, and a
  # missing pybind11 fails here instead of in pytest. The demo leaves the
  # choice to CMake (TEXBAKE_PYTHON=AUTO: built when pybind11 is installed).
  if [ $# -eq 0 ]; then extra+=(-DTEXBAKE_PYTHON=ON); fi
  cmake -S "$TEXBAKE_ROOT" -B "$TEXBAKE_BUILD" -DCMAKE_BUILD_TYPE=Release \
    -DTEXBAKE_BUILD_TESTS=$suite -DTEXBAKE_BUILD_BENCH=$suite "${extra[@]}" >/dev/null
  cmake --build "$TEXBAKE_BUILD" --parallel "$jobs" "${targets[@]}"
}
