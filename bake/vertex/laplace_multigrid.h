// Iterative solver for the occlusion fill's large Laplace systems
// (bake/vertex/occlusion_fill.h): conjugate gradients preconditioned by one
// V-cycle of smoothed-aggregation algebraic multigrid (Vanek, Mandel and Brezina
// 1996), several right-hand sides at once. Its cost grows about linearly with
// the unknowns (a direct sparse Cholesky factor of a surface mesh's Laplacian
// grows as n^1.5 or worse: 7-8x time per 4x mesh), so it is what the fill
// uses for large components.
//
// Hand-written because no algebraic multigrid library is packaged by Debian
// without MPI (hypre needs it; AMGCL and others are not packaged), and Eigen
// offers only incomplete-Cholesky and diagonal preconditioners, whose CG
// iteration counts grow with the mesh (about sqrt(n) on a surface).
//
// Everything is deterministic: the hierarchy is built sequentially, the
// products are row-parallel (each row computed by one thread, in one order),
// and dot products are summed in fixed blocks in a fixed order, so the result
// is independent of the thread count.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "mapping/error.h"

namespace texbake {

using LaplaceMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using ColorColumns = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;

struct MultigridStats {
  int levels = 0;                      // levels of the hierarchy (1 = the coarsest solve alone)
  int iterations = 0;                  // CG iterations until every column met the tolerance
  double worst_relative_residual = 0;  // max over columns of |b - Ax| / |b|
};

// Solves a x = b for the four columns of b. a: symmetric positive definite,
// compressed, with a positive diagonal and non-positive off-diagonal entries
// (an M-matrix such as the graph Laplacian with Dirichlet rows). x: the initial
// guess (any size: a wrong-sized x starts from zero), overwritten by the
// solution. Stops when every column's residual is at most
// relative_tolerance times its right-hand side (a zero column gives zero), or
// after max_iterations. Errors: kInternal if the coarsest factorisation fails
// or the tolerance is not met within max_iterations.
Expected<MultigridStats> solve_laplace_multigrid(const LaplaceMatrix& a, const ColorColumns& b,
                                                 ColorColumns& x, double relative_tolerance,
                                                 int max_iterations = 500);

// The same solve for a matrix its caller has already numbered so that
// neighbours sit close together in memory (solve_laplace_multigrid numbers
// them by breadth_first_order first, which the products' gathers need once
// the vectors outgrow the caches). Takes a over (its memory is the finest
// level's).
Expected<MultigridStats> solve_laplace_multigrid_ordered(LaplaceMatrix&& a, const ColorColumns& b,
                                                         ColorColumns& x, double relative_tolerance,
                                                         int max_iterations = 500);

// A breadth-first order of a graph of n nodes (seeds in index order, each
// node's neighbours in the order stored): order[new] = old. The neighbours of
// node i are column[k] - offset for k in [start[i], start[i + 1]) (the
// compressed rows of a matrix, or a slice of rows [offset, offset + n) of a
// larger one with start pointing at its row offset); repeats are allowed.
std::vector<int> breadth_first_order(Eigen::Index n, const int* start, const int* column,
                                     int offset);

}  // namespace texbake
