#!/usr/bin/env bash
# Open3D's colour-map optimisation against texbake's cameras refine, on the
# disturbed cameras of align_refine.sh and measured the same way. A
# benchmark run by hand, not part of the ctest suite.
#
#   bench/photos/open3d_refine.sh [-n N] [-w WORKDIR] [MESH...]
#
#   -n N     repetitions of every Open3D run (default 1; the table shows
#            medians)
#   -w DIR   work folder, shared with align_refine.sh (default
#            ${TMPDIR:-/tmp}/texbake_photos)
#   MESH     bunny.off, armadillo_832k.ply, or both (the default)
#
# The photos, true models and disturbed models ("half": every pose turned
# by 0.25-0.5 degree and moved by 0.5 % of its distance; "full": 0.5-1
# degree and 1 %) are align_refine.sh's, made here the same way when its
# work folder lacks them. Open3D 0.16 (Debian's python3-open3d) gets what a
# calibrated RGB-D rig would give it: every photo with a depth map of the
# mesh at the photo's TRUE pose (a z-buffer in numpy, 16-bit millimetres
# like a depth camera's), the mesh, and the DISTURBED poses, the scene's
# units scaled to the metres its example's defaults assume;
# run_rigid_optimizer with its example's settings (maximum_iteration=300)
# refines them (bench/photos/open3d_refine.py). Its poses, written back as a COLMAP
# model, are baked by texbake and scored as align_refine.sh scores
# texbake's refine: the share of vertices within 8 levels of the direct
# bake. Open3D's own vertex colours are scored too. Beside them, texbake's
# refine from a matching align_refine.sh run (its report's in-process
# seconds, steps, agreement) when the work folder has one. First, a check
# of the pose conversion: the true model through Open3D with 0 iterations
# must bake exactly as the true model does. Prints Markdown tables.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"
# shellcheck source=../common.sh
source "$here/../common.sh"
# The options first (bench_options), the meshes after them.
opts=()
while [ $# -gt 0 ] && [[ $1 == -* ]]; do
  case $1 in
  -n | -w | -t)
    opts+=("$1" "${2-}")
    shift
    [ $# -gt 0 ] && shift
    ;;
  *)
    opts+=("$1")
    shift
    ;;
  esac
done
bench_options 1 "${TMPDIR:-/tmp}/texbake_photos" "${opts[@]}"
meshes=("$@")
[ ${#meshes[@]} -gt 0 ] || meshes=(bunny.off armadillo_832k.ply)
for mesh in "${meshes[@]}"; do
  case $mesh in bunny.off | armadillo_832k.ply) ;; *)
    echo "open3d_refine.sh: the meshes are bunny.off and armadillo_832k.ply, not '$mesh'" >&2
    exit 2
    ;;
  esac
done
bench_start python3-open3d
o3d="$here/open3d_refine.py"
echo "open3d: $("$py" -c 'import open3d; print(open3d.__version__)')"

bench_photo_meshes
# align_refine.sh's model.py (perturb, agree, steps), taken from that script.
sed -n "/^cat >model.py <<'PY'\$/,/^PY\$/p" "$here/align_refine.sh" | sed '1d;$d' >model.py
export PYTHONPATH="$TEXBAKE_BUILD/python${PYTHONPATH:+:$PYTHONPATH}"

# The median of $reps Open3D runs: "seconds peak_MB load_s residual_first
# residual_last" (the models and mesh of the last run kept).
open3d_median() {
  local i
  for ((i = 0; i < reps; i++)); do "$py" "$o3d" refine "$@"; done | sort -n |
    sed -n "$(((reps + 1) / 2))p"
}

check_rows=()
rows=()
pose_rows=()
for mesh in "${meshes[@]}"; do
  name=${mesh%.*}
  model=$name/ws/sparse/0
  images=$name/ws/images
  [ -f "$name/direct.ply" ] ||
    "$texbake" bake "$mesh" --texture "$TEXBAKE_ROOT/data/earth.jpg" --proxy-file "$name/sphere.json" \
      -q -o "$name/direct.ply"
  [ -f "$name/true.ply" ] || "$texbake" bake "$mesh" --cameras "$model" -q -o "$name/true.ply"
  grep -qs units_per_metre "$name/o3d_depth/depth.json" ||
    "$py" "$o3d" depth "$mesh" "$model" "$name/o3d_depth"
  true_agree=$("$py" model.py agree "$name/direct.ply" "$name/true.ply")

  # The conversion check: the true poses through Open3D, 0 iterations.
  rm -rf "$name/o3d_check"
  read -r s _ < <("$py" "$o3d" refine "$mesh" "$model" "$images" "$name/o3d_depth" 0 \
    "$name/o3d_check" "$name/o3d_check.ply")
  "$texbake" bake "$mesh" --cameras "$name/o3d_check" --images "$images" -q -o "$name/o3d_check_bake.ply"
  diff=$("$py" "$o3d" same "$name/true.ply" "$name/o3d_check_bake.ply")
  check_agree=$("$py" model.py agree "$name/direct.ply" "$name/o3d_check_bake.ply")
  check_own=$("$py" model.py agree "$name/direct.ply" "$name/o3d_check.ply")
  check_rows+=("| $mesh | $true_agree / $check_agree % | $diff | $check_own % | $s |")

  for scale in half full; do
    f=0.5
    [ "$scale" = full ] && f=1
    if [ ! -f "$name/moved_$scale/images.txt" ]; then
      mkdir -p "$name/moved_$scale"
      cp "$model/cameras.txt" "$model/points3D.txt" "$name/moved_$scale/"
      "$py" model.py perturb "$model" "$name/moved_$scale" "$f"
    fi
    [ -f "$name/moved_$scale.ply" ] ||
      "$texbake" bake "$mesh" --cameras "$name/moved_$scale" --images "$images" -q -o "$name/moved_$scale.ply"
    rm -rf "$name/o3d_$scale"
    read -r s p load r0 r1 < <(open3d_median "$mesh" "$name/moved_$scale" "$images" "$name/o3d_depth" 300 \
      "$name/o3d_$scale" "$name/o3d_$scale.ply")
    read -r bake_s _ < <(timed bake "$mesh" --cameras "$name/o3d_$scale" --images "$images" -q \
      -o "$name/o3d_${scale}_bake.ply" | tail -n 1)
    moved_agree=$("$py" model.py agree "$name/direct.ply" "$name/moved_$scale.ply")
    o3d_agree=$("$py" model.py agree "$name/direct.ply" "$name/o3d_${scale}_bake.ply")
    own_agree=$("$py" model.py agree "$name/direct.ply" "$name/o3d_$scale.ply")
    # texbake's refine from align_refine.sh, if it refined these cameras.
    tb="- | - | -"
    tb_poses="-"
    report=$name/refine_$scale.json
    if [ -f "$report" ] && [ -f "$name/refined_$scale.ply" ] &&
      grep -q "\"cameras\": *\"$name/moved_$scale\"" "$report"; then
      tb_s=$("$py" -c 'import json, sys; print("%.1f" % json.load(open(sys.argv[1]))["timings"]["total"])' "$report")
      tb="$tb_s | $("$py" model.py steps "$report") | $("$py" model.py agree "$name/direct.ply" "$name/refined_$scale.ply") %"
      tb_poses=$("$py" "$o3d" poses "$model" "$name/refined_$scale" "$mesh")
    fi
    rows+=("| $mesh | $scale | $s | $load | 300 | $p | $r0 → $r1 | $true_agree / $moved_agree / $o3d_agree / $own_agree % | $tb | $bake_s |")
    pose_rows+=("| $mesh | $scale | $("$py" "$o3d" poses "$model" "$name/moved_$scale" "$mesh") | $("$py" "$o3d" poses "$model" "$name/o3d_$scale" "$mesh") | $tb_poses |")
  done
done

echo
echo "| mesh | agreement: true model / through Open3D (0 iterations) | largest colour difference, levels | Open3D's own colours' agreement | Open3D s (0 iterations) |"
echo "|---|---|---|---|---|"
printf '%s\n' "${check_rows[@]}"
echo
echo "| mesh | perturbation | Open3D s | reading photos and depth s | iterations | peak MB | Open3D residual, first → last iteration | agreement: true / disturbed / Open3D's poses (texbake bake) / Open3D's own colours | texbake refine s (in-process) | texbake steps per photo | texbake refined agreement | photo bake s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
printf '%s\n' "${rows[@]}"
echo
echo "Pose errors against the true model: rotation (median / largest of the 24 photos), then camera centre (median / largest, % of the mesh's size):"
echo
echo "| mesh | perturbation | disturbed | Open3D | texbake refine |"
echo "|---|---|---|---|---|"
printf '%s\n' "${pose_rows[@]}"
