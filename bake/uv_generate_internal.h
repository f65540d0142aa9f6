// Internals of bake/uv_generate.cpp shared with bake/uv_generate_flatten.cpp,
// the one translation unit that includes CGAL (CGAL headers are slow to
// compile; keeping them in one file keeps the build fast). Not a public API.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace texbake::uv_detail {

// One chart as a stand-alone triangle mesh: local vertices (corners of the
// chart's triangles welded across the chart's manifold, consistently oriented
// edges) and faces in the mesh's winding order.
struct ChartMesh {
  std::vector<double> positions;                // x, y, z per local vertex
  std::vector<std::array<uint32_t, 3>> faces;   // local vertex indices
  std::vector<double> initial_uv;               // u, v per local vertex: start of the solver
  uint32_t fixed0 = 0, fixed1 = 0;              // locked at their initial_uv (LSCM needs two)
};

enum class FlattenStatus {
  kOk,
  kNotDisk,      // CGAL could not build it as one manifold disk (or it has holes / handles)
  kSolveFailed,  // the parameterizer reported an error or produced non-finite values
};

// Least-squares conformal map (Levy et al. 2002) of a topological disk through
// CGAL::Surface_mesh_parameterization::LSCM_parameterizer_3, with
// chart.fixed0/fixed1 locked at their initial_uv and every other vertex
// starting from initial_uv (the solver is iterative; a good start saves
// iterations). On kOk, uv holds u, v per local vertex. Flips and overlaps are
// not checked here (the caller checks and splits).
FlattenStatus flatten_lscm(const ChartMesh& chart, std::vector<double>& uv);

}  // namespace texbake::uv_detail
