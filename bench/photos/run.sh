#!/usr/bin/env bash
# Baking from photographs at scale (issue #13): the bunny and the armadillo
# subdivided to 832k triangles, each photographed from 24 known cameras at
# 1920 x 1080 (texbake's own unlit render of the Earth map projected from a
# fitted sphere, written as a COLMAP workspace), then baked back with
# `bake --cameras` per vertex and into a 2048 atlas. A benchmark run by hand,
# not part of the ctest suite.
#
#   bench/photos/run.sh [-n N] [-w WORKDIR] [-t vertex|atlas|all]
#
#   -n N     repetitions of every bake (default 3; the table shows medians)
#   -w DIR   work folder: meshes, photos, outputs (default
#            ${TMPDIR:-/tmp}/texbake_photos)
#   -t T     targets to time (default all)
#
# Builds build/texbake (Release) when it is not there. Every bake writes a
# --report; the stage times (load, scene, photos, fill, write) come from it
# and the peak memory from /usr/bin/time -v (maximum resident set size).
# Prints a Markdown table.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"

# shellcheck source=../common.sh
source "$here/../common.sh"
bench_options 3 "${TMPDIR:-/tmp}/texbake_photos" "$@"
bench_start

# Photos: 24 views around each mesh's up axis, 1920 x 1080, unlit.
bench_photo_meshes

# One timed bake: prints "seconds peak_MB" and leaves its report.
timed_bake() { # mesh target output report
  local name=${1%.*}
  local args=(bake "$1" --cameras "$name/ws/sparse/0" -q -o "$3" --report "$4")
  if [ "$2" = atlas ]; then args+=(--target atlas --uv generate --size 2048); fi
  local start end
  start=$(date +%s%N)
  /usr/bin/time -v -o time.log "$texbake" "${args[@]}"
  end=$(date +%s%N)
  local peak_kb
  peak_kb=$(awk -F': ' '/Maximum resident set size/ {print $2}' time.log)
  local ms=$(((end - start) / 1000000))
  printf '%d.%03d %d\n' $((ms / 1000)) $((ms % 1000)) $((peak_kb / 1024))
}

echo
echo "| mesh | target | total s | stages (s, from the report) | peak MB |"
echo "|---|---|---|---|---|"
for mesh in bunny.off armadillo_832k.ply; do
  for target in vertex atlas; do
    [ "$which" = all ] || [ "$which" = "$target" ] || continue
    out=${mesh%.*}/out_$target.ply
    [ "$target" = atlas ] && out=${mesh%.*}/out_atlas.obj
    : >runs.tsv
    for ((i = 0; i < reps; i++)); do
      read -r seconds peak < <(timed_bake "$mesh" "$target" "$out" "${mesh%.*}/report_$i.json")
      echo "$seconds $peak ${mesh%.*}/report_$i.json" >>runs.tsv
    done
    "$py" - "$mesh" "$target" runs.tsv <<'PY'
import json, statistics, sys
mesh, target, runs = sys.argv[1], sys.argv[2], [l.split() for l in open(sys.argv[3])]
runs.sort(key=lambda r: float(r[0]))
mid = runs[len(runs) // 2]
t = json.load(open(mid[2]))["timings"]
stages = ", ".join(f"{k} {v:.2f}" for k, v in t.items() if k != "total")
print(f"| {mesh} | {target} | {float(mid[0]):.2f} | {stages} | {max(int(r[1]) for r in runs)} |")
PY
  done
done
