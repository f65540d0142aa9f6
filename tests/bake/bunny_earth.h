// The demo's scene for image tests (golden images, bake fidelity): the
// Stanford bunny (data/bunny00.off, y up, about 1 unit across,
// centred at the origin) inside a unit sphere projector carrying the Earth
// map (earth.jpg, north at the top) with its pole along +y, like
// scripts/demo.sh. Everything is loaded once per test binary.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "bake/atlas/dilate.h"
#include "bake/engine/bake_atlas.h"
#include "bake/render/render_preview.h"
#include "bake/trace/embree_scene.h"
#include "bake/uv/uv_generate.h"
#include "mapping/proxy.h"
#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"

namespace texbake::test {

inline std::filesystem::path shared_data(const std::string& name) {
  return std::filesystem::path(TEXBAKE_DATA_DIR) / name;
}

struct BunnyEarth {
  MeshData mesh;
  Image earth;
  Proxy proxy;
};

// Loaded once; a failed load fails the calling test (ADD_FAILURE) and
// returns nullptr.
inline const BunnyEarth* bunny_earth() {
  static const BunnyEarth* loaded = [] {
    auto mesh = read_mesh(shared_data("bunny00.off"));
    auto earth = read_image(shared_data("earth.jpg"));
    auto proxy = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 1, 0}, Vec3{0, 0, 1}});
    if (!mesh || !earth || !proxy) return static_cast<BunnyEarth*>(nullptr);
    return new BunnyEarth{std::move(mesh->mesh), std::move(earth).value(),
                          std::move(proxy).value()};
  }();
  if (!loaded) ADD_FAILURE() << "cannot load bunny00.off, earth.jpg or the sphere proxy";
  return loaded;
}

// The bunny's render options: y up, seen from azimuth 120 (from +x and -z),
// where the sphere projector puts South America (u = 1/3,
// longitude -60): a recognisable, asymmetric shape to judge north-up and
// not mirrored by eye.
inline RenderOptions bunny_view(int size, int samples_per_pixel) {
  RenderOptions o;
  o.width = o.height = size;
  o.samples_per_pixel = samples_per_pixel;
  o.up = {0, 1, 0};
  o.azimuth_deg = 120;
  o.elevation_deg = 20;
  return o;
}

// The bunny with a generated UV layout (--uv generate) for an atlas of
// `size`, with the CLI's gutter (the default padding, at least 2 texels).
inline Expected<MeshData> bunny_with_generated_uvs(const MeshData& mesh, int size) {
  UvGenerateOptions go;
  go.atlas_size = size;
  go.padding = std::max(2, default_padding(size));
  auto atlas = generate_uv_atlas(mesh, go);
  if (!atlas) return atlas.error();
  return mesh_with_triangle_uvs(mesh, atlas->uvs, atlas->triangle_uvs);
}

}  // namespace texbake::test
