#!/usr/bin/env bash
# Maps larger than memory (issue #16 item 4, SPEC section 13): the Earth map
# resampled to 65536 x 32768 and to 16384 x 8192 (8-bit RGB, tiled 256 x 256,
# deflate, made once with oiiotool from data/earth.jpg) baked onto the
# armadillo subdivided to 832k triangles through a fitted sphere, per vertex
# (the default --filter area, 16 samples) and into a 2048 atlas (generated
# UVs, 4 samples): time and peak memory with --cache-mb 512 and 2048 for the
# large map, and the 16384 map in memory (--cache-mb 4096) and through the
# cache (--cache-mb 512). Then --filter ewa on the 16384 map: the plain TIFF
# (the bake builds the MIP pyramid in memory; refused at --cache-mb 512,
# where the pyramid does not fit) against the same map MIP-mapped by
# `maketx --filter box` (its levels read in memory or through the cache).
# A benchmark run by hand, not part of the ctest suite.
#
#   bench/large_images/run.sh [-n N] [-w WORKDIR] [-t vertex|atlas|all]
#
#   -n N     repetitions of every bake (default 1; the table shows medians)
#   -w DIR   work folder: mesh, images (7 GB), outputs (default
#            ${TMPDIR:-/tmp}/texbake_large)
#   -t T     targets to time (default all)
#
# Builds build/texbake (Release) when it is not there. Peak memory is the
# process's maximum resident set (/usr/bin/time -v); the stage seconds come
# from each bake's --report. Prints a Markdown table.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source-path=SCRIPTDIR source=../../scripts/setup.sh
source "$here/../../scripts/setup.sh"

# shellcheck source=../common.sh
source "$here/../common.sh"
bench_options 1 "${TMPDIR:-/tmp}/texbake_large" "$@"
bench_start openimageio-tools
data=$TEXBAKE_ROOT/data

mesh=armadillo_832k.ply
[ -f $mesh ] || "$py" "$here/../peers/peers_util.py" mesh "$data/armadillo.off" $mesh
[ -f sphere.json ] || "$texbake" fit $mesh --proxy sphere -o sphere.json >/dev/null
for size in 16384x8192 65536x32768; do
  img=earth_${size%%x*}.tif
  if [ ! -f "$img" ]; then
    echo "making $img (oiiotool --native --resample, bilinear; tiled 256, deflate)" >&2
    # --native: resample in 8 bits (6.4 GB for the large map, not 26 GB of float).
    oiiotool --native "$data/earth.jpg" --resample:interp=1 "$size" --tile 256 256 \
      --compression zip -o "$img.part.tif"
    mv "$img.part.tif" "$img"
  fi
done

if [ ! -f earth_16384.tx ]; then
  echo "making earth_16384.tx (maketx --filter box: tiled, MIP-mapped)" >&2
  maketx --filter box -o earth_16384.part.tx earth_16384.tif >&2
  mv earth_16384.part.tx earth_16384.tx
fi

stages='import json,sys
r=json.load(open(sys.argv[1])); t=r["timings"]; i=r["inputs"]["image"]
print("cached" if i["cached"] else "in memory", i.get("mip_levels", 0),
      " ".join(f"{k} {v:.2f}" for k, v in t.items() if k not in ("total", "fit") and v >= 0.01))'

echo
echo "| target | image | --cache-mb | read | total s | peak MB | stages s (report) |"
echo "|---|---|---|---|---|---|---|"
for target in vertex atlas; do
  [ "$which" = all ] || [ "$which" = "$target" ] || continue
  flags=(-q --proxy-file sphere.json)
  ext=ply
  if [ "$target" = atlas ]; then
    flags+=(--target atlas --uv generate --size 2048)
    ext=obj
  fi
  for job in "16384 4096" "16384 512" "65536 512" "65536 2048"; do
    read -r side budget <<<"$job"
    read -r s p r < <(median "r_${target}_${side}_$budget" bake $mesh --texture "earth_$side.tif" \
      --cache-mb "$budget" "${flags[@]}" -o "out_${target}_${side}_$budget.$ext")
    read -r how _ rest < <("$py" -c "$stages" "$r" | sed 's/^in memory/in_memory/')
    echo "| $target | earth_$side.tif | $budget | ${how/_/ } | $s | $p | $rest |"
  done
done

echo
echo "| target (--filter ewa) | image | --cache-mb | read | file's MIP levels used | total s | peak MB | stages s (report) |"
echo "|---|---|---|---|---|---|---|---|"
for target in vertex atlas; do
  [ "$which" = all ] || [ "$which" = "$target" ] || continue
  flags=(-q --proxy-file sphere.json --filter ewa)
  ext=ply
  if [ "$target" = atlas ]; then
    flags+=(--target atlas --uv generate --size 2048)
    ext=obj
  fi
  for job in "earth_16384.tif 4096" "earth_16384.tx 4096" "earth_16384.tx 512"; do
    read -r img budget <<<"$job"
    tag=ewa_${target}_${img/./_}_$budget
    read -r s p r < <(median "r_$tag" bake $mesh --texture "$img" --cache-mb "$budget" \
      "${flags[@]}" -o "out_$tag.$ext")
    read -r how levels rest < <("$py" -c "$stages" "$r" | sed 's/^in memory/in_memory/')
    echo "| $target | $img | $budget | ${how/_/ } | $levels | $s | $p | $rest |"
  done
  # The plain map's pyramid (683 MiB as float) does not fit 512 MiB: a usage error.
  rc=0
  "$texbake" bake $mesh --texture earth_16384.tif --cache-mb 512 "${flags[@]}" \
    -o "out_ewa_refused.$ext" 2>err.log || rc=$?
  echo "| $target | earth_16384.tif | 512 | exit $rc: $(grep -o 'keeps the MIP levels.*MiB)' err.log) | | | | |"
done
