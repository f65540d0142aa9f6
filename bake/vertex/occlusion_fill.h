// Smooth inpainting of vertex colours over a mesh (SPEC section 3,
// --occluded fill): the colours of "unknown" vertices (occluded, or without a
// projection) are the discrete harmonic extension of the known ones.
//
// Method: on the graph of the mesh's triangle edges, with weight w_ij = the
// number of triangles containing edge ij (the uniform "graph" Laplacian, every
// weight positive), solve  sum_j w_ij (c_i - c_j) = 0  for every unknown i,
// with the known vertices as Dirichlet boundary. Positive weights give the
// discrete maximum principle: every filled channel lies between the smallest
// and largest known value bordering its region, so nothing is black unless
// its neighbours are. (Cotangent weights go negative on obtuse triangles and
// lose that guarantee; harmonic colours need no metric accuracy.) The sparse
// symmetric positive definite system is solved per connected component: a
// small one with Eigen's SimplicialLDLT (one factorisation for the four
// channels), a large one by multigrid-preconditioned conjugate gradients
// (bake/vertex/laplace_multigrid.h) to a relative residual of 1e-6, whose
// cost grows linearly with its size; the two agree far below one 8-bit level
// (tests/bake/vertex/occlusion_fill_test.cpp).
//
// Vertices at one position (split at UV or normal seams, as glTF stores
// them) are welded into one point of the graph (mesh_io/weld.h): a seam does
// not cut the fill into pieces, and every copy gets the point's colour. A
// point with a known copy is known; its unknown copies take the mean of the
// known copies. Counts (filled, unfilled) are of vertices, copies included.
//
// A connected component of unknown vertices that touches no known vertex
// (e.g. a separate part entirely in shadow, or a vertex in no triangle) has no
// boundary: its vertices get `fallback(v)` (the projected colour) and are
// counted as unfilled.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// Which solver a component gets: the direct one up to direct_rows unknowns,
// the multigrid one beyond, to the residual relative_tolerance * |b|.
struct FillSolverOptions {
  std::size_t direct_rows = 20000;
  double relative_tolerance = 1e-6;
};

struct FillResult {
  std::size_t filled = 0;    // unknown vertices given a harmonic colour
  std::size_t unfilled = 0;  // unknown vertices in components with no known vertex
  int iterations = 0;        // most CG iterations of a multigrid-solved component (0: none)
};

// The fill in two steps, so a caller can free what only the fallback needs
// (the image) before the solve, the memory peak: plan_fill numbers the
// unknowns, finds the components and gives unanchored ones their fallback;
// solve_fill solves for the rest. fill_harmonic = solve_fill(plan_fill(...)).
struct FillPlan {
  FillResult result;
  std::vector<uint32_t> slot;             // per vertex: index of its unknown point, or ~0u
  std::vector<uint32_t> row;              // per unknown point: row of the system, or ~0u (unfilled)
  std::vector<uint32_t> vertex_of;        // per unknown point: its first vertex
  std::vector<uint32_t> component_start;  // rows of component c: [start[c], start[c+1])
};
FillPlan plan_fill(const MeshData& mesh, std::vector<Rgba>& colors,
                   const std::vector<uint8_t>& unknown,
                   const std::function<Rgba(uint32_t vertex)>& fallback);
// colors must hold the known vertices' colours (as given to plan_fill).
Expected<FillResult> solve_fill(const MeshData& mesh, std::vector<Rgba>& colors, FillPlan plan,
                                const FillSolverOptions& solver = {});

// colors: one per vertex of mesh (read for known vertices, written for unknown
// ones). unknown: one flag per vertex (1 = to fill). The graph is
// mesh.triangles. Errors: kInternal if the solver fails (should not happen:
// every solved component is anchored, so the matrix is positive definite).
Expected<FillResult> fill_harmonic(const MeshData& mesh, std::vector<Rgba>& colors,
                                   const std::vector<uint8_t>& unknown,
                                   const std::function<Rgba(uint32_t vertex)>& fallback,
                                   const FillSolverOptions& solver = {});

}  // namespace texbake
