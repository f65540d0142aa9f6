#!/usr/bin/env bash
# UV layout against xatlas: texbake's `--uv generate` and the example
# program of xatlas (jpcy/xatlas, MIT licence, with its defaults) on the
# data meshes, timed, and both layouts measured alike by
# bench/uv_quality.py. A benchmark run by hand, not part of the ctest suite;
# bench/RESULTS.md's "UV layout against xatlas" table comes from it.
#
#   bench/uv/xatlas.sh -x XATLAS_DIR [-n N] [-w WORKDIR] [MESH...]
#
#   -x DIR   the xatlas source tree (default $XATLAS_SRC): a clone of
#            https://github.com/jpcy/xatlas, measured at commit f700c77.
#            texbake fetches none of it and vendors none of it: clone it
#            yourself
#   -n N     repetitions of every layout (default 1; the table shows medians)
#   -w DIR   work folder: xatlas's example, the OBJ inputs, both layouts
#            (default ${TMPDIR:-/tmp}/texbake_xatlas)
#   MESH     names of data/*.off (default the six: bunny00 armadillo
#            ChineseDragon-10kv fandisk elephant mushroom)
#
# Builds xatlas's source/examples/example.cpp into the work folder with
# `g++ -O2 -DNDEBUG -std=c++17 -pthread` (with xatlas.cpp and its
# tiny_obj_loader and stb_image_write implementations), and build/texbake
# (Release) when it is not there. Each mesh is written as an OBJ of
# positions and triangles for xatlas; xatlas's seconds are the wall time of
# its whole process from /usr/bin/time (its own "elapsed" adds up its
# threads' CPU time), texbake's the report's atlas.timings.uv_layout of
#   texbake bake data/MESH.off --texture data/earth.jpg --proxy sphere
#     --uv generate --size 2048 -q -o tb/MESH.obj --report tb/MESH.json
# Prints a Markdown table: seconds, their ratio, and each layout's charts,
# UV area used and L2 stretch.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"
# shellcheck source=../common.sh
source "$here/../common.sh"

# -x DIR and the mesh names here; -n, -w and -h to bench_options.
xatlas_src=${XATLAS_SRC:-}
opts=()
meshes=()
while [ $# -gt 0 ]; do
  case $1 in
  -x)
    [ $# -ge 2 ] || { echo "xatlas.sh: -x takes the xatlas source folder" >&2 && exit 2; }
    xatlas_src=$2
    shift 2
    ;;
  -x*) xatlas_src=${1#-x} && shift ;;
  -[nwt])
    opts+=("$1" "${2-}")
    shift $(($# >= 2 ? 2 : 1))
    ;;
  -*) opts+=("$1") && shift ;;
  *) meshes+=("$1") && shift ;;
  esac
done
bench_options 1 "${TMPDIR:-/tmp}/texbake_xatlas" "${opts[@]}"
if [ "$which" != all ]; then
  echo "xatlas.sh: -t does not apply (the layout is the atlas's)" >&2
  exit 2
fi
if [ -z "$xatlas_src" ] || [ ! -f "$xatlas_src/source/xatlas/xatlas.cpp" ]; then
  [ -z "$xatlas_src" ] || echo "xatlas.sh: '$xatlas_src' has no source/xatlas/xatlas.cpp" >&2
  cat >&2 <<EOF
xatlas.sh: this benchmark needs the xatlas source tree (MIT licence), which
texbake does not fetch (-h for the usage).
Clone it yourself and pass its folder as -x DIR or XATLAS_SRC=DIR:
  git clone https://github.com/jpcy/xatlas
  git -C xatlas checkout f700c77   # the commit bench/RESULTS.md measured
EOF
  exit 2
fi
xatlas_src=$(cd "$xatlas_src" && pwd)
[ ${#meshes[@]} -gt 0 ] || meshes=(bunny00 armadillo ChineseDragon-10kv fandisk elephant mushroom)
data=$TEXBAKE_ROOT/data
for m in "${meshes[@]}"; do
  [ -f "$data/$m.off" ] || { echo "xatlas.sh: no data/$m.off" >&2 && exit 2; }
done

bench_start g++ python3-numpy
xatlas_commit=$(git -C "$xatlas_src" rev-parse --short HEAD 2>/dev/null || echo "unknown (not a git clone)")
echo "xatlas: $xatlas_src, commit $xatlas_commit"
echo "compiler: $(g++ --version | head -1)"

# xatlas's example, built again when the source folder or its commit changed.
example=$PWD/xatlas_example
stamp="$xatlas_src $xatlas_commit"
if [ ! -x "$example" ] || [ "$(cat xatlas_example.stamp 2>/dev/null)" != "$stamp" ]; then
  echo "building xatlas's example..." >&2
  s=$xatlas_src/source
  # tiny_obj_loader.cpp and stb_image_write.c only define the headers'
  # IMPLEMENTATION macros; the latter is compiled as C++ with the rest.
  g++ -O2 -DNDEBUG -std=c++17 -pthread -I"$s/xatlas" -I"$s/thirdparty" -o "$example" \
    "$s/examples/example.cpp" "$s/xatlas/xatlas.cpp" "$s/thirdparty/tiny_obj_loader.cpp" \
    -x c++ "$s/thirdparty/stb_image_write.c"
  echo "$stamp" >xatlas_example.stamp
fi

mkdir -p obj tb xa
# off2obj.py OFF OBJ: the OBJ xatlas reads, positions and triangles only.
cat >off2obj.py <<'PY'
import sys

import peers_util

v, t = peers_util.read_off(sys.argv[1])
with open(sys.argv[2], "w") as f:
    f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v.tolist())
    f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in t.tolist())
PY
# row.py NAME TEXBAKE_S XATLAS_S TEXBAKE_OBJ XATLAS_OBJ: the table's row.
cat >row.py <<'PY'
import sys

from uv_quality import quality

name, tb_s, xa_s = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
t, x = quality(sys.argv[4]), quality(sys.argv[5])
if t["triangles"] != x["triangles"]:
    sys.exit(f"xatlas.sh: {name}: {t['triangles']} triangles in texbake's layout, "
             f"{x['triangles']} in xatlas's")
r = xa_s / tb_s
ratio = f"{r:.0f}x" if r >= 10 else f"{r:.1f}x"
xa = f"{xa_s:.1f}" if xa_s >= 10 else f"{xa_s:.2f}"
print(f"| {name} | {t['triangles']:,} | {tb_s:.2f} | {xa} | {ratio} "
      f"| {t['charts']} / {x['charts']} | {t['uv_area']:.3f} / {x['uv_area']:.3f} "
      f"| {t['stretch_l2']:.4f} / {x['stretch_l2']:.4f} |")
PY
median_of() { printf '%s\n' "$@" | sort -g | sed -n "$((($# + 1) / 2))p"; }

echo
echo "| mesh | triangles | texbake s | xatlas s | ratio | charts texbake / xatlas | UV area used texbake / xatlas | L2 stretch texbake / xatlas |"
echo "|---|---|---|---|---|---|---|---|"
for m in "${meshes[@]}"; do
  [ -f "obj/$m.obj" ] || PYTHONPATH="$here/../peers" "$py" -B off2obj.py "$data/$m.off" "obj/$m.obj"
  tb_runs=()
  xa_runs=()
  for ((i = 0; i < reps; i++)); do
    "$texbake" bake "$data/$m.off" --texture "$data/earth.jpg" --proxy sphere --uv generate \
      --size 2048 -q -o "tb/$m.obj" --report "tb/$m.json"
    tb_runs+=("$("$py" -c 'import json,sys; print(json.load(open(sys.argv[1]))["atlas"]["timings"]["uv_layout"])' "tb/$m.json")")
    # The example writes example_output.obj and its .tga pictures into the
    # folder it runs in.
    rm -rf "xa/$m" && mkdir "xa/$m"
    (cd "xa/$m" && /usr/bin/time -f %e -o time.txt "$example" "../../obj/$m.obj" >example.log)
    xa_runs+=("$(cat "xa/$m/time.txt")")
    mv "xa/$m/example_output.obj" "xa/$m.obj"
    rm -f "xa/$m"/*.tga
  done
  # Seconds: medians; the layouts measured are the last run's.
  PYTHONPATH="$here/.." "$py" -B row.py "$m" "$(median_of "${tb_runs[@]}")" \
    "$(median_of "${xa_runs[@]}")" "tb/$m.obj" "xa/$m.obj"
done
