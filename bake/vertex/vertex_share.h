// A vertex's share of its adjacent triangles (SPEC section 4): in each
// triangle (v, a, b) the quad v, (v+a)/2, centroid, (v+b)/2, one third of
// the triangle (the shares of a triangle's three vertices tile it). The
// vertex area filter spreads its samples over it and the EWA filter takes
// it as the vertex's footprint on the surface. The engine's vertex filter
// (bake/vertex/vertex_filter.h) calls these for every bake.
#pragma once

#include <cstdint>
#include <vector>

#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// Vertex -> adjacent triangles (CSR), by counting sort over MeshData::triangles.
struct Adjacency {
  std::vector<uint32_t> offsets;    // size vertex_count + 1
  std::vector<uint32_t> triangles;  // triangle indices, ascending per vertex
};

Adjacency build_adjacency(const MeshData& mesh);

// The adjacent triangles' areas of vertex v, summed in adjacency order.
struct VertexShare {
  uint32_t first = 0, count = 0;  // the triangles: adjacency.triangles[first, first + count)
  double total = 0;               // the triangles' summed area (three times the share's)
  Vec3 normal;                    // the sum of their area vectors (twice their areas)
  std::vector<double> cdf;        // the cumulative areas, per triangle
};

// Fills `share` (its cdf reused: no allocation once grown).
void vertex_share(const MeshData& mesh, const Adjacency& adjacency, uint32_t v, VertexShare& share);

// The area filter's sample points over the share (share.total > 0): x
// stratified along the cumulative area and jittered by a hash of (v, s), y a
// rotated van der Corput point (a jittered Hammersley set), so the pattern is
// deterministic and does not depend on the thread count. Calls point(p) for
// s = 0 .. samples - 1 in order.
template <class F>
void for_share_points(const MeshData& mesh, const Adjacency& adjacency, uint32_t v,
                      const VertexShare& share, int samples, F&& point);

// One sample point of the pattern (for_share_points' body); j walks the
// triangles (start at 0, non-decreasing with s).
Vec3 share_point(const MeshData& mesh, const Adjacency& adjacency, uint32_t v,
                 const VertexShare& share, int s, int samples, uint32_t& j);

template <class F>
void for_share_points(const MeshData& mesh, const Adjacency& adjacency, uint32_t v,
                      const VertexShare& share, int samples, F&& point) {
  uint32_t j = 0;
  for (int s = 0; s < samples; ++s) point(share_point(mesh, adjacency, v, share, s, samples, j));
}

}  // namespace texbake
