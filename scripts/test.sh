#!/usr/bin/env bash
# The CI entry point. Installs what is missing (setup.sh), then runs, failing
# at the first stage that fails:
#   1. format: clang-format --dry-run --Werror over the tracked C/C++ files
#      (.clang-format); any difference fails;
#   2. release: Release build into build/ and the whole test suite (ctest,
#      then the Python module's pytest tests);
#   3. sanitize: AddressSanitizer + UndefinedBehaviorSanitizer build into
#      build-asan/ (clang, -O1) of the test binaries, the texbake executable
#      (the CLI tests run it) and the libFuzzer targets, and the fast part of
#      the suite;
#   4. tsan: ThreadSanitizer build into build-tsan/ (gcc, -O1) of test_mapping,
#      test_mesh_io and test_bake_threads (test_bake's files that hold a
#      thread-count test), and their tests that compare thread counts;
#   5. fuzz: a short run of each libFuzzer target of build-asan/
#      (TEXBAKE_FUZZ_SECONDS, default 25 s) from its seed corpus and saved
#      regressions (scripts/fuzz.sh's runner; that script alone builds the
#      targets in build-fuzz/).
# The fuzzers share the sanitize stage's build (one clang build of the library
# with ASan, UBSan and the fuzzer's coverage instrumentation) because a third
# whole build of the library does not fit CI's 90 minutes on 2 cores.
# TEXBAKE_QUICK=1 runs only stages 1 and 2 (for local runs); CI=true always
# runs all five. Each stage prints its wall time.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/fuzz.sh"  # sources setup.sh, installs all packages

TEXBAKE_ASAN_BUILD=${TEXBAKE_ASAN_BUILD:-$TEXBAKE_ROOT/build-asan}
texbake_jobs=$(nproc 2>/dev/null || echo 2)

# Tests left out of the sanitizer stage: tests/asan_exclude.txt, one regular
# expression per line with the reason beside it, joined with '|'.
texbake_asan_exclude=$(sed -e 's/#.*//' -e 's/[[:space:]]*$//' -e '/^$/d' \
  "$TEXBAKE_ROOT/tests/asan_exclude.txt" | paste -sd '|')

TEXBAKE_TSAN_BUILD=${TEXBAKE_TSAN_BUILD:-$TEXBAKE_ROOT/build-tsan}
# The tests that run the same work at several thread counts (their names say
# "Thread"; TriangulateFaces.BigMesh... reads a mesh at 1, 2, 3 and 8
# threads): the places where threads share data. Those of test_mapping and
# test_mesh_io (the tiled image read by two threads, the parallel mesh load)
# and of test_bake (every bake, the layers engine, the photo bakes and
# their prefetching reader, the fill, UV generation, the render, the API's
# arenas). The CLI's thread-count tests run the same library code through
# the executable and stay out, to keep this build small; so does the photo
# round trip's (4 minutes under TSan: PhotoBake.AtlasIdenticalWithOneAndTwo-
# Threads runs the same photo atlas passes on a small scene).
texbake_tsan_tests='Thread|TriangulateFaces\.BigMesh'
texbake_tsan_exclude='PhotoRoundTripData\.'

stage() {
  local name=$1
  shift
  local start=$SECONDS
  echo "=== texbake test: $name" >&2
  "$@"
  echo "=== texbake test: $name passed in $((SECONDS - start)) s" >&2
}

release_stage() {
  texbake_build
  (cd "$TEXBAKE_BUILD" && ctest --output-on-failure --parallel "$texbake_jobs" --timeout 600) |
    tee "$TEXBAKE_BUILD/ctest-release.log"
  # The Python module's tests (tests/python, pytest) against this build.
  TEXBAKE_BUILD="$TEXBAKE_BUILD" /usr/bin/python3 -m pytest -q -p no:cacheprovider \
    "$TEXBAKE_ROOT/tests/python"
}

sanitize_stage() {
  # -O1 without NDEBUG: assertions stay on; leaks are reported (LSan;
  # tests/lsan.supp lists the third-party ones).
  # clang, for libFuzzer: the fuzz stage runs the fuzzers built here. Line
  # tables only (file and line in every report's stack) instead of full
  # debug information: a quicker build and link.
  cmake -S "$TEXBAKE_ROOT" -B "$TEXBAKE_ASAN_BUILD" -DCMAKE_CXX_COMPILER=clang++ \
    -DTEXBAKE_SANITIZE=ON -DTEXBAKE_FUZZ=ON -DTEXBAKE_PYTHON=OFF \
    -DTEXBAKE_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only" >/dev/null
  cmake --build "$TEXBAKE_ASAN_BUILD" --parallel "$texbake_jobs" \
    --target texbake test_mapping test_mesh_io test_cli test_bake texbake_fuzzers
  (cd "$TEXBAKE_ASAN_BUILD" &&
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
      LSAN_OPTIONS=suppressions=$TEXBAKE_ROOT/tests/lsan.supp \
      ctest --output-on-failure --parallel "$texbake_jobs" --timeout 600 \
      -E "$texbake_asan_exclude")
}

format_stage() {
  # Every tracked C/C++ file, formatted as .clang-format says; prints the
  # differences and fails on any (fix: clang-format -i FILE).
  (cd "$TEXBAKE_ROOT" &&
    git ls-files -z -- '*.c' '*.cc' '*.cpp' '*.cxx' '*.h' '*.hh' '*.hpp' |
    xargs -0 clang-format --dry-run --Werror)
}

tsan_stage() {
  # -O1 -g without NDEBUG, as the sanitize stage. tests/tsan.supp says why
  # each of its entries is there. Without address-space randomisation
  # (setarch -R) for the build too, whose test discovery runs the binaries:
  # gcc 12's TSan cannot map its shadow memory under kernels with 32 bits of
  # mmap randomisation.
  local no_aslr=(setarch "$(uname -m)" -R)
  cmake -S "$TEXBAKE_ROOT" -B "$TEXBAKE_TSAN_BUILD" -DTEXBAKE_SANITIZE=thread \
    -DTEXBAKE_BUILD_BENCH=OFF -DTEXBAKE_PYTHON=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" >/dev/null
  "${no_aslr[@]}" cmake --build "$TEXBAKE_TSAN_BUILD" --parallel "$texbake_jobs" \
    --target test_mapping test_mesh_io test_bake_threads
  (cd "$TEXBAKE_TSAN_BUILD" &&
    TSAN_OPTIONS="halt_on_error=1 history_size=7 suppressions=$TEXBAKE_ROOT/tests/tsan.supp" \
      "${no_aslr[@]}" ctest --output-on-failure --parallel "$texbake_jobs" --timeout 1200 \
      -R "$texbake_tsan_tests" -E "$texbake_tsan_exclude")
}

fuzz_stage() {
  TEXBAKE_FUZZ_BUILD=$TEXBAKE_ASAN_BUILD fuzz_all "${TEXBAKE_FUZZ_SECONDS:-25}" "${texbake_fuzz_targets[@]}"
}

main() {
  local start=$SECONDS
  stage format format_stage
  stage release release_stage
  if [ "${TEXBAKE_QUICK:-0}" = 1 ] && [ "${CI:-}" != true ]; then
    echo "=== texbake test: TEXBAKE_QUICK=1: sanitizer and fuzz stages skipped" >&2
  else
    stage sanitize sanitize_stage
    stage tsan tsan_stage
    stage fuzz fuzz_stage
  fi
  echo "=== texbake test: all stages passed in $((SECONDS - start)) s" >&2
  # The closing line CI reads: the Release suite's count (ctest's own summary
  # scrolled away under the later stages' output).
  local passed
  passed=$(sed -n 's/.*tests passed, 0 tests failed out of \([0-9]*\).*/\1/p' \
    "$TEXBAKE_BUILD/ctest-release.log" | tail -n 1)
  echo "texbake: ${passed:-0} passed, 0 failed"
}

main "$@"
