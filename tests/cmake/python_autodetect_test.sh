#!/usr/bin/env bash
# python_autodetect_test.sh SOURCE_DIR WORK_DIR: the README's order of set-up
# (scripts/demo.sh, then scripts/test.sh) in one build folder, with pybind11
# first missing and then installed. A folder configured while pybind11 could
# not be found (CMAKE_DISABLE_FIND_PACKAGE_pybind11 stands in for "not
# installed yet") has no Python module target and TEXBAKE_PYTHON stays AUTO
# in its cache; configured again once pybind11 can be found, the same folder
# has the target without being told. A cache holding the OFF that older
# texbakes wrote there is overridden by TEXBAKE_PYTHON=ON (what test.sh
# passes), and TEXBAKE_PYTHON=ON with pybind11 missing fails the configure.
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: python_autodetect_test.sh SOURCE_DIR WORK_DIR" >&2
  exit 2
fi
src=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
common=(-S "$src" -B "$work" -DCMAKE_BUILD_TYPE=Release -DTEXBAKE_BUILD_TESTS=OFF
        -DTEXBAKE_BUILD_BENCH=OFF -DTEXBAKE_STARTUP_ORDER=OFF)

has_module_target() {
  local targets
  targets=$(cmake --build "$work" --target help)
  grep -q '^\.\.\. texbake_python$' <<<"$targets"
}
cached() {
  sed -n "s/^$1:[A-Z]*=//p" "$work/CMakeCache.txt"
}
fail() {
  echo "python autodetect: $*" >&2
  exit 1
}

# 1. As the demo on a fresh machine: pybind11 not there yet.
cmake "${common[@]}" -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=ON >/dev/null
[ "$(cached TEXBAKE_PYTHON)" = AUTO ] || fail "after a configure without pybind11 the cache says TEXBAKE_PYTHON=$(cached TEXBAKE_PYTHON), not AUTO"
if has_module_target; then fail "texbake_python is a target although pybind11 was not found"; fi

# 2. pybind11 installed, the same folder configured again, nothing said.
cmake "${common[@]}" -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=OFF >/dev/null
has_module_target || fail "pybind11 now found, but the reconfigured folder has no texbake_python target"

# 3. A cache with the OFF an older texbake wrote: test.sh's ON wins.
sed -i 's/^TEXBAKE_PYTHON:.*/TEXBAKE_PYTHON:BOOL=OFF/' "$work/CMakeCache.txt"
cmake "${common[@]}" >/dev/null
if has_module_target; then fail "TEXBAKE_PYTHON=OFF in the cache still made the target"; fi
cmake "${common[@]}" -DTEXBAKE_PYTHON=ON >/dev/null
has_module_target || fail "TEXBAKE_PYTHON=ON did not make the texbake_python target"

# 4. ON with pybind11 missing: the configure fails and says why.
if out=$(cmake "${common[@]}" -DTEXBAKE_PYTHON=ON -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=ON 2>&1); then
  fail "TEXBAKE_PYTHON=ON without pybind11 configured"
fi
grep -q 'TEXBAKE_PYTHON=ON needs pybind11' <<<"$out" || fail "no reason given: $out"
rm -rf "$work"
echo "python autodetect: ok"
