#include "bake/atlas/atlas_common.h"

#include <cmath>
#include <string>

#include "bake/atlas/dilate.h"
#include "mesh_io/image_io.h"  // kMaxAtlasSize

namespace texbake {

// --filter ewa: the surface footprint of a supersample on triangle t, the
// 3D vectors of one cell step in the atlas's u and in its v (the triangle's
// UV-to-3D map is affine: P = P0 + s dP/ds + t dP/dt over UV (s, t)).
void cell_tangents(const MeshData& mesh, uint32_t t, double cell, Vec3& ts, Vec3& tt) {
  const auto& tri = mesh.triangles[t];
  const auto& corners = mesh.triangle_corners[t];
  Vec3 p[3];
  double s[3], v[3];
  for (int k = 0; k < 3; ++k) {
    const Float3 q = mesh.positions[tri[k]];
    p[k] = {q.x, q.y, q.z};
    const Float2 uv = mesh.uvs[mesh.corner_uv[corners[k]]];
    s[k] = uv.u;
    v[k] = uv.v;
  }
  const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  const double s1 = s[1] - s[0], s2 = s[2] - s[0], v1 = v[1] - v[0], v2 = v[2] - v[0];
  const double det = s1 * v2 - s2 * v1;
  if (!(std::abs(det) > 0) || !std::isfinite(det)) {
    ts = tt = Vec3{};
    return;
  }
  ts = (e1 * v2 - e2 * v1) * (cell / det);
  tt = (e2 * s1 - e1 * s2) * (cell / det);
}

double ewa_cell(int size, int samples) {  // see bake_atlas for the 0.85
  constexpr double kOneSampleEllipse = 0.85;
  return 1.0 / (size * std::sqrt(2.0 * samples)) * (samples == 1 ? kOneSampleEllipse : 1.0);
}

Status check_padding(int padding) {
  if (padding == kPaddingDefault || padding == kPaddingInfinite) return ok_status();
  if (padding >= 0 && padding <= kMaxAtlasSize) return ok_status();
  return make_error(ErrorCode::kInvalidArgument, "--padding " + std::to_string(padding) +
                                                     " is not a texel count (0 .. " +
                                                     std::to_string(kMaxAtlasSize) + ") or 'inf'");
}

std::size_t pad_atlas(std::span<float> rgba, std::span<const uint8_t> baked, int size,
                      int padding) {
  if (padding == kPaddingInfinite) return push_pull_fill(rgba, baked, size, size);
  const int rings = padding == kPaddingDefault ? default_padding(size) : padding;
  std::vector<uint8_t> mask(baked.begin(), baked.end());
  std::size_t padded = dilate(rgba, mask, size, size, rings);
  if (padding == kPaddingDefault) {
    // The rest of the background: colour by the mip-safe push-pull from
    // the charts and their rings, alpha 0 (coverage).
    padded += push_pull_fill(rgba, mask, size, size, PushPullMode::kMipSafe);
  }
  return padded;
}

MeshData mesh_with_triangle_uvs(const MeshData& mesh, const std::vector<Float2>& uvs,
                                const std::vector<std::array<uint32_t, 3>>& triangle_uvs) {
  MeshData out;
  out.positions = mesh.positions;
  out.uvs = uvs;
  const bool normals = !mesh.corner_normal.empty();
  if (normals) out.normals = mesh.normals;
  out.face_offsets.push_back(0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uint32_t base = static_cast<uint32_t>(out.face_vertices.size());
    for (int k = 0; k < 3; ++k) {
      out.face_vertices.push_back(mesh.triangles[t][k]);
      out.corner_uv.push_back(triangle_uvs[t][k]);
      if (normals) out.corner_normal.push_back(mesh.corner_normal[mesh.triangle_corners[t][k]]);
    }
    out.face_offsets.push_back(base + 3);
    out.triangles.push_back(mesh.triangles[t]);
    out.triangle_corners.push_back({base, base + 1, base + 2});
    out.triangle_face.push_back(static_cast<uint32_t>(t));
  }
  return out;
}

}  // namespace texbake
