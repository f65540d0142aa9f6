#!/usr/bin/env bash
# texbake against MeshLab 2020.09 and Blender 3.4 on the same jobs, alternating
# (bench/peers/README.md). A benchmark run by hand, not part of the ctest suite.
#
#   bench/peers/run.sh [-n N] [-j vertex|atlas|all] [-w WORKDIR]
#
#   -n N     repetitions of every job and tool (default 3)
#   -j JOBS  vertex, atlas or all (default all)
#   -w DIR   work folder: the 832k mesh, outputs and logs
#            (default ${TMPDIR:-/tmp}/texbake_peers)
#
# Installs the peers (meshlab, blender, xvfb, xauth) with apt-get when missing
# and builds build/texbake (Release) when it is not there (TEXBAKE_BUILD picks
# another build folder). Each run is one whole process timed by the wall
# clock; its output is checked afterwards (untimed) so a silent failure cannot
# pass as a fast time. Prints a Markdown table of medians and ratios; exits 1
# if any output failed its check.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"

reps=3
jobs=all
work=${TMPDIR:-/tmp}/texbake_peers
while getopts "n:j:w:h" opt; do
  case $opt in
  n) reps=$OPTARG ;;
  j) jobs=$OPTARG ;;
  w) work=$OPTARG ;;
  *)
    sed -n '2,16p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    [ "$opt" = h ] && exit 0
    exit 2
    ;;
  esac
done
case $jobs in vertex | atlas | all) ;; *)
  echo "run.sh: -j takes vertex, atlas or all, not '$jobs'" >&2
  exit 2
  ;;
esac
if ! [[ $reps =~ ^[1-9][0-9]*$ ]]; then
  echo "run.sh: -n takes a positive count, not '$reps'" >&2
  exit 2
fi

texbake_install_packages "${texbake_peer_packages[@]}"
texbake=$TEXBAKE_BUILD/texbake
if [ ! -x "$texbake" ]; then
  texbake_install_packages "${texbake_build_packages[@]}"
  texbake_build texbake
fi
py=/usr/bin/python3
util=$here/peers_util.py

mkdir -p "$work/logs"
cd "$work"
mesh=armadillo_832k.ply
[ -f "$mesh" ] || "$py" "$util" mesh "$TEXBAKE_ROOT/data/armadillo.off" "$mesh"
# MeshLab's Set Texture takes a file name beside the mesh, without a path.
cp "$TEXBAKE_ROOT/data/earth.jpg" earth.jpg
oiiotool earth.jpg -o earth.ppm
center=$("$py" "$util" center "$mesh")
IFS=, read -r cx cy cz <<<"$center"
"$texbake" fit "$mesh" --proxy sphere --center "$center" --pole 0,0,1 --equator 1,0,0 -o sphere.json
sed -e "s/@CX@/$cx/g" -e "s/@CY@/$cy/g" -e "s/@CZ@/$cz/g" -e "s/@TEXTURE@/earth.jpg/g" \
  "$here/meshlab_vertex.mlx" >meshlab_vertex.mlx

echo "texbake: $("$texbake" --version | head -1)"
echo "meshlab: $(dpkg-query -W -f='${Version}' meshlab), blender: $(blender --version 2>/dev/null | head -1)"
echo "machine: $(nproc) cores, $(uptime | sed 's/.*load average/load average/')"
echo "mesh: $mesh ($("$texbake" info "$mesh" | grep '^triangles' | tr -d ' ')), sphere centre $center, pole +z"

# One command per tool and job; each writes the output the check then reads.
run_tool() { # job tool output
  case $1/$2 in
  vertex/texbake-*)
    local filter=${2#texbake-} visibility=first
    if [ "$filter" = bilinear-novis ]; then filter=bilinear visibility=all; fi
    "$texbake" bake "$mesh" --texture earth.jpg --proxy-file sphere.json --target vertex \
      --filter "$filter" --visibility "$visibility" -q -o "$3"
    ;;
  vertex/meshlab)
    xvfb-run -a meshlabserver -i "$mesh" -o "$3" -m vc -s meshlab_vertex.mlx
    ;;
  atlas/texbake)
    "$texbake" bake "$mesh" --texture earth.jpg --proxy-file sphere.json --target atlas \
      --uv generate --size 2048 --samples 4 -q -o "$3"
    ;;
  */blender | */blender-numpy)
    local io=addon
    [ "$2" = blender ] || io=numpy
    blender -b --factory-startup -P "$here/blender_bake.py" -- "$1" "$io" "$work/$mesh" \
      "$work/earth.jpg" "$center" "$work/$3" 2048
    ;;
  esac
}

check_output() { # job output
  case $1 in
  vertex) "$py" "$util" check-vertex "$2" earth.ppm "$center" ;;
  atlas)
    local image=${2%.*}.png
    oiiotool "$image" --ch R,G,B -o "${image%.png}.ppm" && "$py" "$util" check-image "${image%.png}.ppm"
    ;;
  esac
}

declare -A tools=(
  [vertex]="texbake-bilinear texbake-area texbake-bilinear-novis meshlab blender blender-numpy"
  [atlas]="texbake blender blender-numpy"
)
selected=(vertex atlas)
[ "$jobs" = all ] || selected=("$jobs")

times=$work/times.tsv
: >"$times"
for ((rep = 1; rep <= reps; rep++)); do
  for job in "${selected[@]}"; do
    read -r -a order <<<"${tools[$job]}"
    # Alternate: every repetition starts one tool later, so no tool always
    # runs right after the same one.
    n=${#order[@]}
    for ((k = 0; k < n; k++)); do
      tool=${order[$(((k + rep - 1) % n))]}
      case $job/$tool in
      atlas/texbake) out=${job}_${tool}.obj ;;
      atlas/*) out=${job}_${tool}.png ;;
      *) out=${job}_${tool}.ply ;;
      esac
      rm -f "$out" "${out%.*}".png "${out%.*}".ppm "${out%.*}".mtl
      log=logs/${job}_${tool}_$rep.log
      start=$(date +%s.%N)
      rc=0
      run_tool "$job" "$tool" "$out" >"$log" 2>&1 || rc=$?
      end=$(date +%s.%N)
      seconds=$("$py" -c "print(f'{$end - $start:.3f}')")
      status=ok
      if [ $rc -ne 0 ]; then
        status=FAILED
        echo "$job $tool: exit $rc, see $work/$log" >&2
      elif ! check_output "$job" "$out" >>"$log" 2>&1; then
        status=FAILED
      fi
      echo "rep $rep $job $tool: $seconds s, $status ($(tail -1 "$log"))"
      printf '%s\t%s\t%s\t%s\t%s\n' "$job" "$tool" "$rep" "$seconds" "$status" >>"$times"
    done
  done
done

echo
"$py" "$util" summary "$times"
