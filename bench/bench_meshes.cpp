#include "bench/bench_meshes.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <unordered_map>

#include "mesh_io/read_mesh.h"

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
  MeshData out;
  out.positions = in.positions;
  std::unordered_map<uint64_t, uint32_t> midpoints;
  midpoints.reserve(in.triangles.size() * 2);
  auto midpoint = [&](uint32_t a, uint32_t b) {
    const uint64_t key = (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    auto [it, fresh] = midpoints.try_emplace(key, static_cast<uint32_t>(out.positions.size()));
    if (fresh) {
      const Float3 p = in.positions[a], q = in.positions[b];
      out.positions.push_back({(p.x + q.x) / 2, (p.y + q.y) / 2, (p.z + q.z) / 2});
    }
    return it->second;
  };
  out.face_offsets.assign(1, 0);
  out.face_vertices.reserve(in.triangles.size() * 12);
  for (const auto& t : in.triangles) {
    const uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    for (const std::array<uint32_t, 3>& f :
         {std::array<uint32_t, 3>{t[0], ab, ca}, std::array<uint32_t, 3>{ab, t[1], bc},
          std::array<uint32_t, 3>{ca, bc, t[2]}, std::array<uint32_t, 3>{ab, bc, ca}}) {
      out.face_vertices.insert(out.face_vertices.end(), f.begin(), f.end());
      out.face_offsets.push_back(static_cast<uint32_t>(out.face_vertices.size()));
    }
  }
  triangulate_faces(out);
  return out;
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
