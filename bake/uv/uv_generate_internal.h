// Internals of bake/uv_generate.cpp shared with bake/uv_generate_flatten.cpp
// (the LSCM solve, kept apart because the Eigen sparse headers are slow to
// compile). Not a public API.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace texbake::uv_detail {

// One chart as a stand-alone triangle mesh: local vertices (corners of the
// chart's triangles welded across the chart's manifold, consistently oriented
// edges) and faces in the mesh's winding order.
struct ChartMesh {
  std::vector<double> positions;               // x, y, z per local vertex
  std::vector<std::array<uint32_t, 3>> faces;  // local vertex indices
  // Border edges (i, j) in face winding order: every edge of a face that no
  // other face of the chart shares.
  std::vector<std::pair<uint32_t, uint32_t>> border;
  std::vector<double> initial_uv;   // u, v per local vertex (only fixed0/1 are used)
  uint32_t fixed0 = 0, fixed1 = 0;  // locked at their initial_uv (LSCM needs two)
};

enum class FlattenStatus {
  kOk,
  kSolveFailed,  // the factorisation failed or produced non-finite values
};

// Least-squares conformal map (Levy et al. 2002) of a chart that the caller
// has checked to be a topological disk (connected, Euler characteristic 1,
// one border loop), with chart.fixed0/fixed1 locked at their initial_uv
// (direct sparse solve, see uv_generate_flatten.cpp). On kOk, uv holds u, v
// per local vertex. Flips and overlaps are not checked here (the caller
// checks and splits).
FlattenStatus flatten_lscm(const ChartMesh& chart, std::vector<double>& uv);

}  // namespace texbake::uv_detail
