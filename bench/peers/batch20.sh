#!/usr/bin/env bash
# Many assets per process: the 832k per-vertex job of run.sh twenty times,
# as one `texbake batch` (one process; the jobs share the mesh and texture
# they read, texbake::JobCache), as 20 `texbake bake` processes, and as 20
# MeshLab processes on one Xvfb display (started once, so no X start-up
# counts against MeshLab). A benchmark run by hand, not part of the suite.
#
#   bench/peers/batch20.sh [-n N] [-w WORKDIR] [-m]
#
#   -n N     repetitions, alternating the three (default 3)
#   -w DIR   work folder (default ${TMPDIR:-/tmp}/texbake_peers, run.sh's)
#   -m       leave MeshLab out (no apt-get of meshlab and xvfb)
#
# Prints the median wall time of each and the ratios, Markdown.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"

reps=3
work=${TMPDIR:-/tmp}/texbake_peers
meshlab=1
while getopts "n:w:mh" opt; do
  case $opt in
  n) reps=$OPTARG ;;
  w) work=$OPTARG ;;
  m) meshlab=0 ;;
  *)
    sed -n '2,14p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    [ "$opt" = h ] && exit 0
    exit 2
    ;;
  esac
done
if ! [[ $reps =~ ^[1-9][0-9]*$ ]]; then
  echo "batch20.sh: -n takes a positive count, not '$reps'" >&2
  exit 2
fi
if [ "$meshlab" = 1 ]; then texbake_install_packages meshlab xvfb xauth; fi
texbake=$TEXBAKE_BUILD/texbake
if [ ! -x "$texbake" ]; then
  texbake_install_packages "${texbake_build_packages[@]}"
  texbake_build texbake
fi
py=/usr/bin/python3
util=$here/peers_util.py

mkdir -p "$work/batch20"
cd "$work"
mesh=armadillo_832k.ply
[ -f "$mesh" ] || "$py" "$util" mesh "$TEXBAKE_ROOT/data/armadillo.off" "$mesh"
cp "$TEXBAKE_ROOT/data/earth.jpg" earth.jpg
center=$("$py" "$util" center "$mesh")
IFS=, read -r cx cy cz <<<"$center"
"$texbake" fit "$mesh" --proxy sphere --center "$center" --pole 0,0,1 --equator 1,0,0 \
  -o sphere.json >/dev/null
sed -e "s/@CX@/$cx/g" -e "s/@CY@/$cy/g" -e "s/@CZ@/$cz/g" -e "s/@TEXTURE@/earth.jpg/g" \
  "$here/meshlab_vertex.mlx" >meshlab_vertex.mlx
jobs=batch20/jobs.jsonl
: >"$jobs"
for i in $(seq -w 1 20); do
  printf '{"mesh": "%s", "texture": "earth.jpg", "proxy_file": "sphere.json", "target": "vertex", "filter": "bilinear", "output": "batch20/batch_%s.ply"}\n' \
    "$mesh" "$i" >>"$jobs"
done

echo "texbake: $("$texbake" --version | head -1); machine: $(nproc) cores," \
  "$(uptime | sed 's/.*load average/load average/')"

run() { # tool
  case $1 in
  batch) "$texbake" batch "$jobs" -q ;;
  processes)
    for i in $(seq -w 1 20); do
      "$texbake" bake "$mesh" --texture earth.jpg --proxy-file sphere.json --target vertex \
        --filter bilinear -q -o "batch20/process_$i.ply"
    done
    ;;
  meshlab)
    # One display for the twenty (DISPLAY set by the xvfb-run around the loop).
    xvfb-run -a bash -c 'for i in $(seq -w 1 20); do
      meshlabserver -i "$0" -o "batch20/meshlab_$i.ply" -m vc -s meshlab_vertex.mlx >/dev/null 2>&1
    done' "$mesh"
    ;;
  esac
}

tools=(batch processes)
[ "$meshlab" = 1 ] && tools+=(meshlab)
declare -A times
for ((rep = 1; rep <= reps; rep++)); do
  n=${#tools[@]}
  for ((k = 0; k < n; k++)); do
    tool=${tools[$(((k + rep - 1) % n))]}
    start=$(date +%s.%N)
    run "$tool"
    end=$(date +%s.%N)
    times[$tool]+="$("$py" -c "print(f'{$end - $start:.3f}')") "
  done
done
# The outputs must agree: every batch output equals its process twin.
for i in $(seq -w 1 20); do
  cmp -s "batch20/batch_$i.ply" "batch20/process_$i.ply" ||
    { echo "batch20.sh: batch_$i.ply differs from process_$i.ply" >&2 && exit 1; }
done
median() { tr ' ' '\n' <<<"$1" | sed '/^$/d' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
echo
echo "| 20 x the 832k per-vertex job | median s (of $reps) | vs batch |"
echo "|---|---|---|"
b=$(median "${times[batch]}")
for tool in "${tools[@]}"; do
  m=$(median "${times[$tool]}")
  echo "| $tool | $m | $("$py" -c "print(f'{$m / $b:.2f}x')") |"
done
