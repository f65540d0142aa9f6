// The vertex target's last step, written once for every kind of bake (a
// proxy, bake/engine/bake_vertex.h; photos, bake/engine/photo_vertex.h;
// layers, bake/engine/layers_bake.h): what becomes of the vertices the projections
// left without a colour (SPEC section 3 --occluded, section 10 `occluded`),
// and the colours' way back to the sRGB encoding.
//
// Given per vertex a colour in the bake's working encoding (linear light or
// the stored sRGB encoding) and an `unknown` flag:
//  - fill (--occluded fill, and project for the vertices that have no
//    projection): the harmonic fill of bake/vertex/occlusion_fill.h over the
//    unknown vertices; a component of them that touches no known vertex
//    takes fallback(v) (a proxy's projected colour, or the image's mean), or
//    without a fallback the constant;
//  - no fill (--occluded R,G,B[,A]): every unknown vertex takes the constant.
// Then every colour is encoded to sRGB (from linear light when `linear`),
// and the vertices that take the constant get it exactly as given (sRGB),
// not its round trip through the working encoding.
// With `coverage` (layers) alpha is the vertex's coverage, not a colour
// channel: the fill works on RGB alone, and an unknown vertex ends with
// alpha 0 (the constant gives its RGB only).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "bake/vertex/occlusion_fill.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct VertexResolve {
  bool fill = true;
  Rgba constant{0, 0, 0, 1};  // sRGB-encoded, as given
  bool coverage = false;
  bool linear = false;  // the working encoding is linear light
  // An unanchored vertex's colour in the working encoding; empty: the constant.
  std::function<Rgba(uint32_t vertex)> fallback;
};

// In two steps, so that a caller can free what only the fallback needs (the
// image) before the fill's solve, the memory peak: plan_resolve decides
// every unknown vertex's fate (the fill's plan, the fallbacks, the
// constants); finish_resolve solves the fill and encodes.
// resolve_vertices = finish_resolve(plan_resolve(...)).
struct VertexResolvePlan {
  VertexResolve how;
  FillPlan plan;
  bool solve = false;              // some vertex is filled
  std::vector<uint32_t> constant;  // the vertices that take the constant
  std::vector<uint8_t> unknown;    // coverage: the flags (their alpha ends at 0)
  std::vector<Rgba> coverage_rgb;  // coverage: the colours the fill works on (alpha 1)
};

// colors: per vertex of mesh, the working encoding (read for the known
// vertices; plan_resolve writes the fallbacks' colours).
VertexResolvePlan plan_resolve(const MeshData& mesh, std::vector<Rgba>& colors,
                               const std::vector<uint8_t>& unknown, VertexResolve how);
// Errors: kInternal (the fill's solver).
Expected<FillResult> finish_resolve(const MeshData& mesh, std::vector<Rgba>& colors,
                                    VertexResolvePlan plan);
Expected<FillResult> resolve_vertices(const MeshData& mesh, std::vector<Rgba>& colors,
                                      const std::vector<uint8_t>& unknown, VertexResolve how);

}  // namespace texbake
