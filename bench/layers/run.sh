#!/usr/bin/env bash
# Layers at scale (issue #14): the armadillo subdivided to 832k triangles
# with four layers over base "none" (the Earth map through a fitted sphere,
# the label through a fitted cylinder, a decal through a fitted plane in
# multiply mode, and one photograph as a "cameras" layer), per vertex and
# into a 2048 atlas; then each layer's projection baked alone as the single
# projection it equals (`--filter bilinear --linear`, or `bake --cameras`
# for the photo). A benchmark run by hand, not part of the ctest suite.
#
#   bench/layers/run.sh [-n N] [-w WORKDIR] [-t vertex|atlas|all]
#
#   -n N     repetitions of every bake (default 1; the table shows medians)
#   -w DIR   work folder: mesh, proxies, photo, outputs (default
#            ${TMPDIR:-/tmp}/texbake_layers)
#   -t T     targets to time (default all)
#
# Builds build/texbake (Release) when it is not there. The layers bake's
# per-layer seconds come from its --report (timings.per_layer), compared
# with each single projection's bake (its report's total less load and
# write), the peak memory from /usr/bin/time -v. Prints a Markdown table.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"

# shellcheck source=../common.sh
source "$here/../common.sh"
bench_options 1 "${TMPDIR:-/tmp}/texbake_layers" "$@"
bench_start
data=$TEXBAKE_ROOT/data

mesh=armadillo_832k.ply
[ -f $mesh ] || "$py" "$here/../peers/peers_util.py" mesh "$data/armadillo.off" $mesh
for kind in sphere cylinder; do
  [ -f $kind.json ] || "$texbake" fit $mesh --proxy $kind --up y -o $kind.json >/dev/null
done
[ -f plane.json ] || "$texbake" fit $mesh --proxy plane -o plane.json >/dev/null
# The photo: one unlit 1920 x 1080 view of the Earth bake, as a COLMAP workspace.
[ -f ws/sparse/0/images.txt ] ||
  "$texbake" render $mesh --texture "$data/earth.jpg" --proxy-file sphere.json --up y --unlit \
    --views 1 --samples 4 --size 1920x1080 --colmap ws >/dev/null
cat >layers.json <<EOF
{"base": "none",
 "layers": [
  {"proxy_file": "sphere.json", "texture": "$data/earth.jpg"},
  {"proxy_file": "cylinder.json", "texture": "$data/label.png"},
  {"proxy_file": "plane.json", "texture": "$data/label.png", "mode": "multiply", "opacity": 0.8},
  {"cameras": "ws/sparse/0"}]}
EOF

echo
echo "| target | bake | total s | layer s (report) | peak MB | single projection s | its bake s | peak MB | layer / single bake |"
echo "|---|---|---|---|---|---|---|---|---|"
one="--filter bilinear --linear" # what one layer over "none" equals
singles=("--texture $data/earth.jpg --proxy-file sphere.json $one"
  "--texture $data/label.png --proxy-file cylinder.json $one"
  "--texture $data/label.png --proxy-file plane.json $one"
  "--cameras ws/sparse/0")
names=(sphere cylinder plane camera)
for target in vertex atlas; do
  [ "$which" = all ] || [ "$which" = "$target" ] || continue
  flags=(-q)
  ext=ply
  if [ "$target" = atlas ]; then
    flags+=(--target atlas --uv generate --size 2048)
    ext=obj
  fi
  read -r s p r < <(median "r_${target}_layers" bake $mesh --layers layers.json "${flags[@]}" -o "layers_$target.$ext")
  layer_seconds=$("$py" -c 'import json,sys; print(" ".join(f"{x:.2f}" for x in json.load(open(sys.argv[1]))["timings"]["per_layer"]))' "$r")
  echo "| $target | 4 layers | $s | $layer_seconds | $p | | | | |"
  read -r -a per_layer <<<"$layer_seconds"
  for k in 0 1 2 3; do
    # shellcheck disable=SC2086 # the single projection's flags split on purpose
    read -r ss sp sr < <(median "r_${target}_${names[$k]}" bake $mesh ${singles[$k]} \
      "${flags[@]}" -o "${names[$k]}_$target.$ext")
    # The single projection's bake: its total less reading and writing files.
    bake_s=$("$py" -c 'import json,sys; t=json.load(open(sys.argv[1]))["timings"]; print("%.2f" % (t["total"] - t.get("load", 0) - t.get("write", 0)))' "$sr")
    ratio=$("$py" -c "print(f'{${per_layer[$k]} / $bake_s:.2f}')")
    echo "| $target | ${names[$k]} | | ${per_layer[$k]} | | $ss | $bake_s | $sp | $ratio |"
  done
done
