// Helpers shared by the atlas tests: tiny meshes built in code.
#pragma once

#include <array>
#include <vector>

#include "mesh_io/mesh_data.h"

namespace texbake::test {

// A mesh of independent triangles (no shared vertices): triangle t has
// positions pos[3t..3t+2] and per-corner UVs uv[3t..3t+2]. Faces are the
// triangles.
inline MeshData make_triangle_soup(const std::vector<Float3>& pos, const std::vector<Float2>& uv) {
  MeshData m;
  m.positions = pos;
  m.uvs = uv;
  const uint32_t tris = static_cast<uint32_t>(pos.size() / 3);
  m.face_offsets.push_back(0);
  for (uint32_t t = 0; t < tris; ++t) {
    for (uint32_t k = 0; k < 3; ++k) {
      m.face_vertices.push_back(3 * t + k);
      m.corner_uv.push_back(3 * t + k);
    }
    m.face_offsets.push_back(3 * (t + 1));
    m.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    m.triangle_corners.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    m.triangle_face.push_back(t);
  }
  return m;
}

// Same with positions (u, v, 0) taken from the UVs.
inline MeshData make_flat_uv_soup(const std::vector<Float2>& uv) {
  std::vector<Float3> pos;
  for (const Float2& q : uv) pos.push_back({q.u, q.v, 0});
  return make_triangle_soup(pos, uv);
}

}  // namespace texbake::test
