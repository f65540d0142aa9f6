#include "mesh_io/vertex_normals.h"

#include "mapping/vec.h"
#include "mesh_io/weld.h"

namespace texbake {

std::vector<Float3> smooth_vertex_normals(const MeshData& mesh) {
  const auto vec = [](Float3 f) { return Vec3{f.x, f.y, f.z}; };
  // Split vertices sum into their first copy (mesh_io/weld.h).
  const std::vector<uint32_t> weld = weld_by_position(mesh);
  const auto rep = [&](uint32_t v) { return weld.empty() ? v : weld[v]; };
  std::vector<Vec3> acc(mesh.vertex_count());
  for (const auto& tri : mesh.triangles) {
    const Vec3 a = vec(mesh.positions[tri[0]]);
    const Vec3 n = cross(vec(mesh.positions[tri[1]]) - a, vec(mesh.positions[tri[2]]) - a);
    for (uint32_t v : tri) acc[rep(v)] += n;
  }
  std::vector<Float3> out(acc.size());
  for (std::size_t v = 0; v < acc.size(); ++v) {
    const Vec3& sum = acc[rep(static_cast<uint32_t>(v))];
    const double len = length(sum);
    if (len > 0) {
      out[v] = {static_cast<float>(sum.x / len), static_cast<float>(sum.y / len),
                static_cast<float>(sum.z / len)};
    }
  }
  return out;
}

}  // namespace texbake
