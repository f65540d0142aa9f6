// The filtered lookup of one vertex (SPEC section 4, --filter): the one
// implementation of the vertex target's bilinear, area and EWA filters,
// through any projector: the engine's vertex target's
// (bake/engine/layers_bake.cpp), and through it the single-proxy vertex
// bake's (bake/engine/bake_vertex.cpp), so every bake filters a vertex the
// same way.
//
//  - kEwa: one lookup at the vertex through rule.project() with the
//    footprint of the vertex's share of its triangles (a third of each,
//    share.total / 3) as a square of that area in the plane of the
//    area-weighted normal (two perpendicular tangents of length
//    sqrt(total / 3)), carried into (u, v) by the projector's Jacobian at
//    the vertex. A vertex without triangles has a zero footprint.
//  - kArea, a vertex with a share of positive area: the mean of `samples`
//    rule.project() lookups at the share's points (for_share_points), in
//    double sums with one division; samples without a mapping are left out
//    (nullopt when none has one).
//  - otherwise (kBilinear, or a vertex in no non-degenerate triangle): one
//    rule.project() lookup at the vertex.
// Outside points follow the rule (ShadeRule::project: the constant or the
// clamped lookup). `counts` adds the lookups taken and those outside.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "bake/shade/footprint.h"
#include "bake/shade/options.h"
#include "bake/shade/shade.h"
#include "bake/vertex/vertex_share.h"
#include "mapping/image_view.h"
#include "mapping/projector.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct FilterCounts {
  std::size_t samples = 0;  // lookups taken (mapped or not)
  std::size_t outside = 0;  // of those, outside the projector's (u, v) domain
};

// map(Vec3) -> MapResult and jacobian(Vec3) -> UvJacobian are the
// projector's (the Jacobian is called under kEwa only). adjacency may be
// null under kBilinear. vertex_map is map(position of v).
template <class Map, class Jacobian>
std::optional<Rgba> filter_vertex(const ShadeRule& rule, VertexFilter filter, int samples,
                                  const Map& map, const Jacobian& jacobian, const MeshData& mesh,
                                  const Adjacency* adjacency, uint32_t v,
                                  const MapResult& vertex_map, VertexShare& share,
                                  FilterCounts& counts) {
  double sum[4] = {0, 0, 0, 0};
  int count = 0;
  const auto add = [&](const MapResult& m, const UvFootprint& footprint) {
    ++counts.samples;
    const Shaded s = rule.project(m, footprint);
    if (s.kind == Shade::kNone) return;
    if (s.kind == Shade::kOutside) ++counts.outside;
    for (int k = 0; k < 4; ++k) sum[k] += s.color[k];
    ++count;
  };
  if (adjacency && filter != VertexFilter::kBilinear) {
    vertex_share(mesh, *adjacency, v, share);
  } else {
    share.count = 0;
    share.total = 0;
    share.normal = Vec3{};
  }
  const Float3& f = mesh.positions[v];
  if (filter == VertexFilter::kEwa) {
    Vec3 t1, t2;
    isotropic_tangents(share.normal, share.total / 3, t1, t2);
    add(vertex_map, uv_footprint(jacobian(Vec3{f.x, f.y, f.z}), t1, t2));
  } else if (filter == VertexFilter::kArea && share.total > 0) {
    for_share_points(mesh, *adjacency, v, share, samples,
                     [&](const Vec3& p) { add(map(p), UvFootprint{}); });
  } else {
    add(vertex_map, UvFootprint{});
  }
  if (count == 0) return std::nullopt;
  const double inv = 1.0 / count;
  return Rgba{static_cast<float>(sum[0] * inv), static_cast<float>(sum[1] * inv),
              static_cast<float>(sum[2] * inv), static_cast<float>(sum[3] * inv)};
}

}  // namespace texbake
