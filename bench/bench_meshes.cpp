#include "bench/bench_meshes.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "mesh_io/read_mesh.h"
#include "tests/bake/test_meshes.h"

namespace texbake::bench {

void die(const std::string& what) {
  std::fprintf(stderr, "texbake_bench: %s\n", what.c_str());
  std::exit(1);
}

MeshData load_shared_mesh(const std::string& file) {
  Expected<LoadedMesh> loaded = read_mesh(std::string(TEXBAKE_DATA_DIR) + "/" + file);
  if (!loaded) die(loaded.error().message);
  return std::move(loaded->mesh);
}

MeshData subdivide(const MeshData& in) {
  return test::subdivide(in);
}

const MeshData& bunny() {
  static const MeshData mesh = load_shared_mesh("bunny00.off");
  return mesh;
}

const MeshData& armadillo_832k() {
  static const MeshData mesh = subdivide(subdivide(load_shared_mesh("armadillo.off")));
  return mesh;
}

const Image& earth() {
  static const Image image = [] {
    Expected<Image> img = read_image(std::string(TEXBAKE_DATA_DIR) + "/earth.jpg");
    if (!img) die(img.error().message);
    return std::move(img).value();
  }();
  return image;
}

Proxy sphere_around(const MeshData& mesh) {
  Float3 lo = mesh.positions[0], hi = lo;
  for (const Float3& p : mesh.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const Vec3 c{(lo.x + hi.x) / 2.0, (lo.y + hi.y) / 2.0, (lo.z + hi.z) / 2.0};
  const double r = length(Vec3{hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / 2;
  Expected<Proxy> p = make_proxy(SphereParams{c, r, {0, 1, 0}, Vec3{0, 0, 1}});
  if (!p) die(p.error().message);
  return *p;
}

}  // namespace texbake::bench
