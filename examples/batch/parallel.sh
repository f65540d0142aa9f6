#!/usr/bin/env bash
# Runs a texbake batch manifest as N shards at once on one machine with GNU
# parallel (Debian package `parallel`), then merges their results:
#
#   examples/batch/parallel.sh JOBS.jsonl N RESULTS.jsonl [texbake batch options...]
#   e.g. examples/batch/parallel.sh jobs.jsonl 2 results.jsonl --skip-existing
#
# Shard K runs the lines whose index (line number - 1) modulo N is K
# (`texbake batch --shard K/N`), each with nproc / N threads (at least 1).
# RESULTS gets every shard's result lines, ordered by line number. Exit 0
# only if every job of every shard succeeded (or was skipped). The texbake
# executable is $TEXBAKE (default: texbake on PATH).
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 JOBS.jsonl N RESULTS.jsonl [texbake batch options...]" >&2
  exit 2
fi
jobs=$1 shards=$2 results=$3
shift 3
texbake=${TEXBAKE:-texbake}
threads=$(($(nproc) / shards))
if [ "$threads" -lt 1 ]; then threads=1; fi
parts=$(mktemp -d "$(dirname "$results")/.texbake-shards.XXXXXX")
trap 'rm -rf "$parts"' EXIT
status=0
# --halt never: a shard with a failing job must not stop the others.
parallel --halt never --line-buffer \
  "$texbake" batch "$jobs" --shard "{}/$shards" --threads "$threads" \
  --results "$parts/{}.jsonl" "$@" ::: $(seq 0 $((shards - 1))) || status=1
# Each result line starts with {"line":N, : merge by that number.
cat "$parts"/*.jsonl | sort -t: -k2,2n > "$results"
exit $status
