// The per-vertex target (SPEC section 4): one RGBA colour per vertex of a
// mesh, from an image carried through a proxy's inverse mapping. It is the
// engine's vertex target (bake/engine/layers_bake.h) over a one-layer stack
// with ResultAlpha::kImage; this header states the rules it follows.
//
// For every vertex, in the input's order (unreferenced vertices included):
//  1. Filter. kBilinear: one bilinear sample at the vertex. kArea: the average
//     of options.samples bilinear samples spread uniformly (so area-weighted)
//     over the vertex's share of its adjacent triangles: in each triangle
//     (v, a, b), the quad v, (v+a)/2, centroid, (v+b)/2 (one third of the
//     triangle; the shares of a triangle's three vertices tile it). The pattern
//     is stratified along the cumulative area and jittered by a hash of
//     (vertex, sample index), so it is deterministic and never depends on the
//     thread count. A vertex in no non-degenerate triangle samples bilinearly
//     at itself. kEwa: one footprint-filtered lookup at the vertex
//     (mapping/mipmap.h sample_ewa over the working image's MIP pyramid);
//     the footprint on the surface is the vertex's share of its triangles
//     (a third of each) as a square of that area, i.e. two perpendicular
//     tangents of length sqrt(share) in the plane of the area-weighted
//     normal, carried into (u, v) by the inverse mapping's Jacobian at the
//     vertex (mapping/derivatives.h, bake/shade/footprint.h).
//  2. Each sample point goes through the proxy's inverse_map: kOk samples the
//     image; kOutside follows options.outside (clamp: the sampler's edge
//     texel; colour: the constant enters the average); kUndefined samples are
//     left out of the average. A plane with plane_wrap = kRepeat has no outside.
//  3. Visibility (options.visibility = kFirst) is decided once per vertex: the
//     ray from the vertex along its d(P) (bake/trace/visibility.h). Deciding it per
//     sample would cost `samples` times the rays for a difference confined to
//     the one-ring of shadow boundaries, which the fill smooths anyway; a
//     vertex is the unit that --occluded acts on and the report counts.
//  4. Occluded vertices follow options.occluded: kFill (bake/vertex/occlusion_fill.h),
//     kProject (the projected colour) or kColor. Vertices without any mapping
//     (every sample undefined, or the vertex itself undefined, e.g. at a
//     sphere's centre) are treated as occluded, except that kProject fills
//     them (there is nothing to project); an unfilled one gets the image's
//     mean colour.
//
// With options.linear the image is converted to linear once, samples, averages
// and the fill happen in linear, and each result is converted back to sRGB.
// A linear image (ImageView::color_space kLinear) is sampled, averaged and
// filled as it is, in linear light, and each result converted to sRGB:
// results are always sRGB-encoded (issue #11). Under --occluded R,G,B the
// constant (sRGB-encoded) replaces the result of every occluded or unmapped
// vertex exactly, whatever the working encoding.
#pragma once

#include <cstddef>
#include <vector>

#include "bake/shade/options.h"
#include "bake/trace/embree_scene.h"
#include "bake/util/progress.h"
#include "bake/vertex/vertex_resolve.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/proxy.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct VertexBakeCounts {
  std::size_t vertices = 0;
  std::size_t triangles = 0;  // non-degenerate triangles (MeshData::triangles)
  std::size_t samples = 0;    // bilinear samples taken (the unfilled fallbacks included)
  std::size_t occluded = 0;   // vertices whose visibility ray is blocked
  std::size_t undefined = 0;  // vertices without any defined mapping
  std::size_t outside = 0;    // samples outside the proxy's (u, v) domain
  std::size_t filled = 0;     // vertices coloured by the fill
  std::size_t unfilled = 0;   // fill-bound vertices in components with no visible vertex
};

struct VertexBakeTimings {  // seconds
  double scene_build = 0;   // Embree BVH (0 with Visibility::kAll)
  double bake = 0;          // mapping, visibility rays, sampling
  double fill = 0;          // occluded handling
};

struct VertexBakeResult {
  std::vector<Rgba> colors;  // one per vertex, in the input's order, RGBA in [0, 1]
  VertexBakeCounts counts;
  VertexBakeTimings timings;
};

// Preconditions: mesh.triangles index mesh.positions. Errors:
// kInvalidArgument (an empty image; kArea with samples < 1), kParse (a
// tiled image's tiles could not be read), kInternal (Embree or the fill solver failed),
// kCancelled (progress's callback returned false: the remaining chunks are
// skipped). progress may be null; it hears the stage "bake".
Expected<VertexBakeResult> bake_vertex(const MeshData& mesh, const ImageView& image,
                                       const Proxy& proxy, const VertexBakeOptions& options,
                                       Progress* progress = nullptr);

// The same in two steps, for callers that free the image before the fill's
// solve (the memory peak): bake_vertex_sample does everything that reads the
// image (scene, visibility, sampling, the fill's fallbacks); the image may be
// released once it returns. bake_vertex_finish solves the fill and converts
// back from linear. bake_vertex(...) == bake_vertex_finish(mesh, bake_vertex_sample(...)).
struct VertexBakeStage {
  VertexBakeResult result;  // colours still in the working encoding
  VertexResolvePlan plan;   // the occluded and undefined vertices' (bake/vertex/vertex_resolve.h)
};
// shared_scene: a scene already built over mesh (EmbreeScene::build), used
// for the visibility rays instead of building one (the atlas's --occluded
// fill shares its scene); not owned. Results are the same either way.
Expected<VertexBakeStage> bake_vertex_sample(const MeshData& mesh, const ImageView& image,
                                             const Proxy& proxy, const VertexBakeOptions& options,
                                             Progress* progress = nullptr,
                                             const EmbreeScene* shared_scene = nullptr);
Expected<VertexBakeResult> bake_vertex_finish(const MeshData& mesh, VertexBakeStage stage);

}  // namespace texbake
