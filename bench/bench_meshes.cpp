#include "bench/bench_meshes.h"

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
  Expected<LoadedMesh> loaded = read_mesh(std::string(TEXBAKE_SHARED_DATA_DIR) + "/" + file);
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

}  // namespace texbake::bench
