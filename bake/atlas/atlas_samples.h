// The atlas target's pieces that every kind of atlas bake shares (the
// proxy's, bake/engine/bake_atlas.h; the photos', bake/engine/photo_atlas.h;
// the layers', bake/engine/layers_bake.h), written once:
//  - a supersample's surface point and smooth normal;
//  - the fill's per-vertex colours interpolated at a supersample;
//  - a texel as the plain mean of its samples, with the --occluded colour
//    kept exact where every sample takes it;
//  - the check of --padding.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// A point of the surface under an atlas supersample: its position, its unit
// smooth normal (the vertex normals interpolated barycentrically, then
// normalised; the face's direction where they cancel, zero on a degenerate
// triangle) and the face's unnormalised normal (b - a) x (c - a).
struct SurfaceSample {
  Vec3 p, n, face;
};

// The point at barycentrics (1 - b1 - b2, b1, b2) of `triangle` of mesh
// (surface_sample's p, the same bits).
inline Vec3 surface_point(const MeshData& mesh, uint32_t triangle, double b1, double b2) {
  const auto vec = [](Float3 f) { return Vec3{f.x, f.y, f.z}; };
  const auto& tri = mesh.triangles[triangle];
  const double b0 = 1 - b1 - b2;
  return vec(mesh.positions[tri[0]]) * b0 + vec(mesh.positions[tri[1]]) * b1 +
         vec(mesh.positions[tri[2]]) * b2;
}

// The sample at barycentrics (1 - b1 - b2, b1, b2) of `triangle` of mesh;
// normals: the mesh's smooth vertex normals (mesh_io/vertex_normals.h).
inline SurfaceSample surface_sample(const MeshData& mesh, const std::vector<Float3>& normals,
                                    uint32_t triangle, double b1, double b2) {
  const auto vec = [](Float3 f) { return Vec3{f.x, f.y, f.z}; };
  const auto& tri = mesh.triangles[triangle];
  const double b0 = 1 - b1 - b2;
  const Vec3 a = vec(mesh.positions[tri[0]]), b = vec(mesh.positions[tri[1]]),
             c = vec(mesh.positions[tri[2]]);
  SurfaceSample out;
  out.p = surface_point(mesh, triangle, b1, b2);
  out.face = cross(b - a, c - a);
  const Vec3 n = vec(normals[tri[0]]) * b0 + vec(normals[tri[1]]) * b1 + vec(normals[tri[2]]) * b2;
  const double len = length(n), face_len = length(out.face);
  // Opposite vertex normals can cancel: the face's direction then.
  out.n = len > 1e-12 ? n / len : (face_len > 0 ? out.face / face_len : Vec3{0, 0, 0});
  return out;
}

// acc += the per-vertex colours (the fill's) interpolated barycentrically at
// the sample, for the first N channels.
template <std::size_t N>
inline void add_interpolated(const MeshData& mesh, const std::vector<Rgba>& per_vertex,
                             uint32_t triangle, double b1, double b2, std::array<double, N>& acc) {
  static_assert(N >= 1 && N <= 4);
  const auto& tri = mesh.triangles[triangle];
  const double b0 = 1 - b1 - b2;
  for (std::size_t ch = 0; ch < N; ++ch) {
    acc[ch] +=
        b0 * per_vertex[tri[0]][ch] + b1 * per_vertex[tri[1]][ch] + b2 * per_vertex[tri[2]][ch];
  }
}

// A texel of the single-projection bakes (a proxy, photos): the plain mean
// of its `samples` values summed in `acc` (the working encoding), brought to
// the stored encoding by `to_stored`; when all of its samples take the
// --occluded colour (constants == samples) that colour exactly, not its
// round trip through the working encoding (which may move 0.5 off 127.5 / 255).
template <class ToStored>
inline Rgba plain_texel(const std::array<double, 4>& acc, std::size_t samples,
                        std::size_t constants, const Rgba& occluded_color, ToStored to_stored) {
  if (constants == samples) return occluded_color;
  Rgba mean;
  for (int ch = 0; ch < 4; ++ch) {
    mean[ch] = static_cast<float>(acc[ch] / static_cast<double>(samples));
  }
  return to_stored(mean);
}

}  // namespace texbake
