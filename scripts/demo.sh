#!/usr/bin/env bash
# Install what the demo needs (the build packages only), build the `texbake`
# executable alone (not the tests or benchmarks) into build/, then run the
# demo on data/ and say where its outputs are. Each demo step is one
# function below; the times of set-up, build and demo are printed at the end.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
demo_t0=$SECONDS
texbake_install_packages "${texbake_build_packages[@]}"
demo_t1=$SECONDS
texbake_build texbake
demo_t2=$SECONDS
texbake="$TEXBAKE_BUILD/texbake"
sphere=(--proxy sphere --center 0,0,0 --radius 1 --pole 0,0,1 --equator 1,0,0)

demo_worked_example() {
  echo "== Inverse mapping: the worked example of SPEC section 2 (see docs/proxies.md) =="
  echo "\$ texbake map ${sphere[*]} --dir 1,1,1 --json"
  "$texbake" map "${sphere[@]}" --dir 1,1,1 --json
  echo "   (expected u = 0.125, v = 0.695913)"
  echo
  echo "\$ texbake map ${sphere[*]} --dir 1,-1,1 --image 640x480"
  "$texbake" map "${sphere[@]}" --dir 1,-1,1 --image 640x480
  echo "   (expected u = 0.875, same v; pixel x = 559.5, y = 145.46)"
  echo
}

demo_bake_earth_bunny() {
  # The Stanford bunny (y up, about 1 unit across, centred) inside a sphere
  # projector: the Earth map, north along +y, lands on it per vertex, with
  # occluded vertices (under the ears, between the legs) filled smoothly.
  local data="$TEXBAKE_ROOT/data"
  local out="$TEXBAKE_ROOT/out"
  mkdir -p "$out"
  local args=(bake "$data/bunny00.off" --texture "$data/earth.jpg"
              --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1
              -o "$out/bunny_earth.ply" --report "$out/bunny_earth.json")
  echo "== Per-vertex bake: the Earth map on the Stanford bunny (sphere proxy) =="
  echo "\$ texbake ${args[*]}"
  "$texbake" "${args[@]}"
  echo "   wrote $out/bunny_earth.ply (binary PLY with vertex colours; open it in MeshLab or Blender)"
  echo "   and   $out/bunny_earth.json (what was done: inputs, proxy, counts, timings)"
  echo
}

demo_bake_atlas_bunny() {
  # The same projection baked into a texture atlas: the bunny has no UVs, so
  # --uv generate lays out new charts; OBJ + MTL + PNG, viewable anywhere.
  local data="$TEXBAKE_ROOT/data"
  local out="$TEXBAKE_ROOT/out"
  mkdir -p "$out"
  local args=(bake "$data/bunny00.off" --texture "$data/earth.jpg"
              --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1
              --target atlas --uv generate --size 2048
              -o "$out/bunny_atlas.obj" --report "$out/bunny_atlas.json")
  echo "== Atlas bake: the Earth map on the bunny as a 2048 x 2048 texture (generated UVs) =="
  echo "\$ texbake ${args[*]}"
  "$texbake" "${args[@]}"
  echo "   wrote $out/bunny_atlas.obj, $out/bunny_atlas.mtl and $out/bunny_atlas.png"
  echo "         (OBJ with vt, material, atlas; open the OBJ in Blender or MeshLab)"
  echo "   and   $out/bunny_atlas.json (inputs, proxy, UV charts, utilisation, counts, timings)"
  echo
}

demo_render_previews() {
  # A contact sheet of four views around each bake, beside it in out/
  # (texbake render: Embree ray tracing, Phong shading; the bunny is y up).
  # Look at these before trusting a bake: north up, no seams, no black spots.
  local out="$TEXBAKE_ROOT/out"
  echo "== Previews: four views of each bake (texbake render --views 4) =="
  local mesh
  for mesh in "$out/bunny_earth.ply" "$out/bunny_atlas.obj"; do
    local png="${mesh%.*}_preview.png"
    local args=(render "$mesh" --up y --views 4 --size 512x512 -o "$png")
    echo "\$ texbake ${args[*]}"
    "$texbake" "${args[@]}"
    echo "   wrote $png (2 x 2 views, transparent background)"
  done
  echo
}

demo_photos() {
  # Photographs (SPEC section 9, docs/photographs.md): the demo has no real
  # photos, so texbake makes some with known cameras. It renders the bunny,
  # unlit, with the Earth map projected from the sphere, from 8 views, and
  # writes them as a COLMAP workspace (out/photos_ws/images/view_NN.png,
  # out/photos_ws/sparse/0/{cameras,images,points3D}.txt). Then the cameras
  # are checked against the mesh and the photos are baked back onto it.
  local data="$TEXBAKE_ROOT/data"
  local out="$TEXBAKE_ROOT/out"
  mkdir -p "$out"
  rm -rf "$out/photos_ws"
  echo "== Photographs: 8 photos from known cameras, checked and baked back (bake --cameras) =="
  local render=(render "$data/bunny00.off" --texture "$data/earth.jpg"
                --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1
                --up y --unlit --views 8 --size 960x720 --colmap "$out/photos_ws")
  echo "\$ texbake ${render[*]}"
  "$texbake" "${render[@]}"
  local check=(cameras check "$data/bunny00.off" --cameras "$out/photos_ws/sparse/0")
  echo "\$ texbake ${check[*]}"
  "$texbake" "${check[@]}"
  local bake=(bake "$data/bunny00.off" --cameras "$out/photos_ws/sparse/0"
              -o "$out/bunny_photos.ply" --report "$out/bunny_photos.json")
  echo "\$ texbake ${bake[*]}"
  "$texbake" "${bake[@]}"
  local preview=(render "$out/bunny_photos.ply" --up y --views 4 --size 512x512
                 -o "$out/bunny_photos_preview.png")
  echo "\$ texbake ${preview[*]}"
  "$texbake" "${preview[@]}"
  echo "   wrote $out/bunny_photos.ply (vertex colours blended from the 8 photos),"
  echo "         $out/bunny_photos.json (per camera: vertices in view, visible, weight, gains)"
  echo "   and   $out/bunny_photos_preview.png (compare it with bunny_earth_preview.png)"
  echo
}

demo_layers() {
  # Layers (SPEC section 10, docs/layers.md): a bottle with its own green
  # vertex colours (data/bottle.ply) gets a label with transparent rounded
  # corners (data/label.png) wrapped around it through a cylinder proxy, and
  # the Earth map as a small decal on its shoulder through a plane proxy
  # that fades out towards grazing angles; composited in linear light over
  # the mesh's colours (data/bottle_layers.json; both inputs were made by
  # scripts/make_layers_data.py).
  local data="$TEXBAKE_ROOT/data"
  local out="$TEXBAKE_ROOT/out"
  mkdir -p "$out"
  echo "== Layers: a label and a decal over a bottle's own colours (bake --layers) =="
  local bake=(bake "$data/bottle.ply" --layers "$data/bottle_layers.json"
              -o "$out/bottle_layers.ply" --report "$out/bottle_layers.json")
  echo "\$ texbake ${bake[*]}"
  "$texbake" "${bake[@]}"
  local preview=(render "$out/bottle_layers.ply" --up y --views 4 --size 512x512
                 -o "$out/bottle_layers_preview.png")
  echo "\$ texbake ${preview[*]}"
  "$texbake" "${preview[@]}"
  echo "   wrote $out/bottle_layers.ply (vertex colours), $out/bottle_layers.json (per layer:"
  echo "         samples in its domain, visible, blended, mean alpha)"
  echo "   and   $out/bottle_layers_preview.png"
  echo
}

demo_worked_example
demo_bake_earth_bunny
demo_bake_atlas_bunny
demo_render_previews
demo_photos
demo_layers
demo_t3=$SECONDS
echo "== Done: outputs in $TEXBAKE_ROOT/out; look at out/bunny_earth_preview.png, out/bunny_atlas_preview.png, out/bunny_photos_preview.png and out/bottle_layers_preview.png first =="
echo "   set-up $((demo_t1 - demo_t0)) s, build $((demo_t2 - demo_t1)) s, demo $((demo_t3 - demo_t2)) s"
