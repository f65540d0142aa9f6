#!/usr/bin/env bash
# Cost at scale (issue #17 item 4): the armadillo (data/armadillo.off)
# midpoint-subdivided 1-to-4 twice, three and four times (832k, 3.3M and
# 13.3M triangles, binary PLY), the Earth map (data/earth.jpg) through a
# sphere at the bounding-box centre (pole +z), baked per vertex (--filter
# bilinear, visibility, fill: the defaults otherwise) and into a 4096 atlas
# (--uv generate, 4 samples). Prints each bake's wall-clock seconds, peak
# memory and the stages of its --report, and how each stage grew from the
# smallest mesh to the largest. A benchmark run by hand, not part of the
# ctest suite.
#
#   bench/scale/run.sh [-n N] [-w WORKDIR] [-t vertex|atlas|all]
#
#   -n N     repetitions of every bake (default 1; the table shows medians)
#   -w DIR   work folder: meshes (350 MB), outputs (default
#            ${TMPDIR:-/tmp}/texbake_scale)
#   -t T     targets to time (default all)
#
# Builds build/texbake (Release) when it is not there. Peak memory is the
# process's maximum resident set (/usr/bin/time -v). The 13.3M atlas needs
# about 7 GB of memory.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"

# shellcheck source=../common.sh
source "$here/../common.sh"
bench_options 1 "${TMPDIR:-/tmp}/texbake_scale" "$@"
bench_start python3-numpy # peers_util.py makes the meshes
data=$TEXBAKE_ROOT/data

names=(832k 3.3M 13.3M)
for k in 0 1 2; do
  mesh=armadillo_${names[k]}.ply
  if [ ! -f "$mesh" ]; then
    echo "making $mesh (subdivided $((k + 2)) times)" >&2
    "$py" "$here/../peers/peers_util.py" mesh "$data/armadillo.off" "$mesh.part" $((k + 2)) >&2
    mv "$mesh.part" "$mesh"
  fi
done
# Subdivision keeps the original vertices: every mesh has the same bounding box.
centre=$("$py" "$here/../peers/peers_util.py" center armadillo_832k.ply)
[ -f sphere.json ] ||
  "$texbake" fit armadillo_832k.ply --proxy sphere --center "$centre" --pole 0,0,1 \
    --equator 1,0,0 -o sphere.json >/dev/null

stages='import json,sys
t=json.load(open(sys.argv[1]))["timings"]
print(" ".join(f"{k}={v:.2f}" for k, v in t.items() if k not in ("total", "fit")))'

echo
echo "| target | mesh | total s | peak MB | stages s (report) |"
echo "|---|---|---|---|---|"
for target in vertex atlas; do
  [ "$which" = all ] || [ "$which" = "$target" ] || continue
  flags=(-q --texture "$data/earth.jpg" --proxy-file sphere.json --filter bilinear)
  ext=ply
  if [ "$target" = atlas ]; then
    flags+=(--target atlas --uv generate --size 4096 --samples 4)
    ext=obj
  fi
  first=
  for name in "${names[@]}"; do
    read -r s p r < <(median "r_${target}_$name" bake "armadillo_$name.ply" "${flags[@]}" \
      -o "out_${target}_$name.$ext")
    rest=$("$py" -c "$stages" "$r")
    echo "| $target | $name | $s | $p | ${rest//=/ } |"
    [ -n "$first" ] || first=$r
    last=$r
  done
  # Growth of each stage and of the report's total (without process
  # start-up) from 832k to 13.3M (16x the triangles): linear is 16x, n log n
  # about 19x.
  growth=$("$py" -c 'import json,sys
a=json.load(open(sys.argv[1]))["timings"]; b=json.load(open(sys.argv[2]))["timings"]
print(" ".join(f"{k} {b[k] / a[k]:.1f}x" for k in a if k != "fit" and a[k] > 0))' "$first" "$last")
  echo "| $target | 832k -> 13.3M | | | $growth |"
done
