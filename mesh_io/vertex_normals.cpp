#include "mesh_io/vertex_normals.h"

#include "mapping/vec.h"

namespace texbake {

std::vector<Float3> smooth_vertex_normals(const MeshData& mesh) {
  const auto vec = [](Float3 f) { return Vec3{f.x, f.y, f.z}; };
  std::vector<Vec3> acc(mesh.vertex_count());
  for (const auto& tri : mesh.triangles) {
    const Vec3 a = vec(mesh.positions[tri[0]]);
    const Vec3 n = cross(vec(mesh.positions[tri[1]]) - a, vec(mesh.positions[tri[2]]) - a);
    for (uint32_t v : tri) acc[v] += n;
  }
  std::vector<Float3> out(acc.size());
  for (std::size_t v = 0; v < acc.size(); ++v) {
    const double len = length(acc[v]);
    if (len > 0) {
      out[v] = {static_cast<float>(acc[v].x / len), static_cast<float>(acc[v].y / len),
                static_cast<float>(acc[v].z / len)};
    }
  }
  return out;
}

}  // namespace texbake
