#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang into build-fuzz/ and
# runs them, two at a time (or nproc), each for SECONDS.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]      default: 25 s, every target
#
# Each target starts from its seed corpus (tests/fuzz/corpus/<target>) and
# the inputs that once failed (tests/fuzz/regressions/<target>), with its
# dictionary (tests/fuzz/dict/<target>.dict) when it has one; new corpus
# entries go to build-fuzz/corpus/<target>, never into the source tree.
# Crashes, leaks, hangs (-timeout=10 s per input) and inputs needing more than
# 2 GB (-rss_limit_mb=2048) are failures: the input is saved under
# build-fuzz/artifacts/<target>/ and the script exits 1. A summary line per
# target gives executions and time (build-fuzz/logs/<target>.log has the rest).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
texbake_install_packages "${texbake_build_packages[@]}" "${texbake_test_packages[@]}"

TEXBAKE_FUZZ_BUILD=${TEXBAKE_FUZZ_BUILD:-$TEXBAKE_ROOT/build-fuzz}
texbake_fuzz_targets=(fuzz_mesh_obj fuzz_mesh_ply fuzz_mesh_off fuzz_mesh_stl fuzz_mesh_glb fuzz_mesh_gltf fuzz_proxy_json fuzz_layers_json fuzz_camera_list fuzz_batch_line fuzz_cli)

# Largest input per target: a few hundred lines of a mesh, a JSON object, a
# command line.
fuzz_max_len() {
  case "$1" in
    fuzz_mesh_*) echo 4096 ;;
    fuzz_proxy_json) echo 1024 ;;
    fuzz_layers_json | fuzz_camera_list | fuzz_batch_line) echo 2048 ;;
    fuzz_cli) echo 512 ;;
  esac
}

fuzz_build() {
  # -O1 -g without NDEBUG: assertions stay on while fuzzing.
  cmake -S "$TEXBAKE_ROOT" -B "$TEXBAKE_FUZZ_BUILD" -DCMAKE_CXX_COMPILER=clang++ \
    -DTEXBAKE_FUZZ=ON -DTEXBAKE_BUILD_TESTS=OFF -DTEXBAKE_BUILD_BENCH=OFF \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" >/dev/null
  cmake --build "$TEXBAKE_FUZZ_BUILD" --parallel "$(nproc 2>/dev/null || echo 2)" \
    --target texbake_fuzzers
}

# fuzz_run TARGET SECONDS: one libFuzzer run; prints a summary line.
fuzz_run() {
  local target=$1 seconds=$2
  local corpus=$TEXBAKE_FUZZ_BUILD/corpus/$target
  local artifacts=$TEXBAKE_FUZZ_BUILD/artifacts/$target
  local log=$TEXBAKE_FUZZ_BUILD/logs/$target.log
  local regressions=$TEXBAKE_ROOT/tests/fuzz/regressions/$target
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  cp -n "$TEXBAKE_ROOT/tests/fuzz/corpus/$target"/* "$corpus"/ 2>/dev/null || true
  local inputs=("$corpus")
  if [ -d "$regressions" ]; then inputs+=("$regressions"); fi
  local dict=$TEXBAKE_ROOT/tests/fuzz/dict/$target.dict options=()
  if [ -f "$dict" ]; then options+=("-dict=$dict"); fi
  local status=0
  "$TEXBAKE_FUZZ_BUILD/$target" -max_total_time="$seconds" -max_len="$(fuzz_max_len "$target")" \
    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 "${options[@]}" \
    -artifact_prefix="$artifacts/" "${inputs[@]}" >"$log" 2>&1 || status=$?
  local execs
  execs=$(grep -a -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  if [ "$status" -ne 0 ]; then
    echo "fuzz: $target FAILED (exit $status) after $execs executions; see $log and $artifacts" >&2
    grep -m3 -E 'ERROR|runtime error|SUMMARY' "$log" >&2 || true
    return 1
  fi
  echo "fuzz: $target ok: $execs executions in ${seconds} s"
}

# fuzz_all SECONDS TARGET...: runs the targets nproc at a time; fails if any did.
fuzz_all() {
  local seconds=$1
  shift
  local jobs
  jobs=$(nproc 2>/dev/null || echo 2)
  local pids=() failed=0 t pid
  for t in "$@"; do
    fuzz_run "$t" "$seconds" &
    pids+=($!)
    if [ ${#pids[@]} -ge "$jobs" ]; then
      wait "${pids[0]}" || failed=1
      pids=("${pids[@]:1}")
    fi
  done
  for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
  return $failed
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
  seconds=${1:-25}
  shift || true
  targets=("$@")
  if [ ${#targets[@]} -eq 0 ]; then targets=("${texbake_fuzz_targets[@]}"); fi
  fuzz_build
  fuzz_all "$seconds" "${targets[@]}"
fi
