#!/usr/bin/env bash
# tests/gltf/validate_suite_glbs.sh TEXBAKE DATA_DIR PREFIX OUT_DIR
# ctest GltfValidator.SuiteGlbs: writes with the built TEXBAKE every kind of
# GLB the suite and the README write (vertex colours and atlases; --uv
# generate, proxy and mesh; png8 and png16; meshes without normals, with
# per-corner OBJ normals, with missing normals, polygons, an unreferenced
# vertex and a degenerate face; every --up axis; --proxy-file + --up; a kind
# without pole/axis with --up) into OUT_DIR, then validates all of them with
# the Khronos glTF-Validator installed in PREFIX by install_validator.sh
# (validate_glb.mjs: no error, no warning, no unlisted info or hint).
# Exit 77 (ctest SKIP_RETURN_CODE) with a message when node or the
# validator is missing; 1 when a bake or a validation fails.
set -euo pipefail
texbake=${1:?usage: validate_suite_glbs.sh TEXBAKE DATA_DIR PREFIX OUT_DIR}
data=${2:?} prefix=${3:?} out=${4:?}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if ! command -v node >/dev/null 2>&1; then
  echo "texbake: skipped: node not found, so no GLB is validated (scripts/setup.sh installs nodejs)"
  exit 77
fi
if [ ! -f "$prefix/node_modules/gltf-validator/package.json" ]; then
  echo "texbake: skipped: gltf-validator is not installed in $prefix" \
    "(GltfValidator.Install: needs npm and the npm registry)"
  exit 77
fi
rm -rf "$out"
mkdir -p "$out"
img=$data/earth.jpg

# A closed tetrahedron, counter-clockwise seen from outside.
cat >"$out/tetra.off" <<'MESH'
OFF
4 4 0
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
MESH
# A pentagon with a normal, a quad without (the reader pads a zero normal),
# a degenerate triangle and an unreferenced vertex (8), all with vt.
cat >"$out/messy.obj" <<'MESH'
v 0 0 0
v 1 0 0
v 1.5 1 0
v 0.5 1.6 0
v -0.5 1 0
v 0 -1 0
v 1 -1 0
v 5 5 5
vt 0 0.4
vt 1 0.4
vt 1 0.7
vt 0.5 1
vt 0 0.7
vt 0 0
vt 1 0
vn 0 0 1
f 1/1/1 2/2/1 3/3/1 4/4/1 5/5/1
f 6/6 7/7 2/2 1/1
f 1/1 2/2 2/2
MESH

bake() {
  echo "+ texbake bake $*"
  "$texbake" bake "$@" --texture "$img" -q
}
bake "$data/bunny00.off" --proxy sphere --up y --target vertex -o "$out/bunny_vertex.glb"
bake "$data/bunny00.off" --proxy sphere --up y --uv generate --size 256 -o "$out/bunny_generate.glb"
bake "$data/suzanne_uv.obj" --proxy cylinder --up y -o "$out/suzanne_uvmesh.glb"
bake "$data/suzanne_uv.obj" --proxy cylinder --up y --format png16 --size 128 \
  -o "$out/suzanne_png16.glb"
bake "$data/suzanne_uv.obj" --proxy sphere --up y --target vertex -o "$out/suzanne_vertex.glb"
bake "$out/tetra.off" --proxy sphere --uv proxy --size 64 -o "$out/tetra_uvproxy.glb"
for up in x -x y -y z -z; do
  bake "$out/tetra.off" --proxy sphere --up "$up" --target vertex -o "$out/tetra_up$up.glb"
done
"$texbake" fit "$data/elephant.off" --proxy sphere -o "$out/elephant_sphere.json"
bake "$data/elephant.off" --proxy-file "$out/elephant_sphere.json" --up y --target vertex \
  -o "$out/elephant_file.glb"
bake "$out/messy.obj" --proxy quad --up -z --uv mesh --size 64 -o "$out/messy_atlas.glb"
bake "$out/messy.obj" --proxy quad --up -z --target vertex -o "$out/messy_vertex.glb"

node "$here/validate_glb.mjs" "$prefix" "$out"

# The check can fail: a GLB cut short must be refused.
mkdir -p "$out/cut"
head -c $(($(wc -c <"$out/tetra_upz.glb") / 2)) "$out/tetra_upz.glb" >"$out/cut/tetra_upz_cut.glb"
if node "$here/validate_glb.mjs" "$prefix" "$out/cut" >"$out/cut/report.txt"; then
  echo "texbake: the validator passed a truncated GLB:" && cat "$out/cut/report.txt"
  exit 1
fi
echo "a truncated GLB is refused, as it must be: $(grep -m1 -o 'error [A-Z_]*' "$out/cut/report.txt")"
