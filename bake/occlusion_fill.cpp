#include "bake/occlusion_fill.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <numeric>

namespace texbake {

namespace {

// Union-find with path halving, over the unknown vertices.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), 0u);
  }
  uint32_t find(uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);  // deterministic root
  }

 private:
  std::vector<uint32_t> parent_;
};

constexpr uint32_t kNotUnknown = 0xFFFFFFFFu;

}  // namespace

Expected<FillResult> fill_harmonic(const MeshData& mesh, std::vector<Rgba>& colors,
                                   const std::vector<uint8_t>& unknown,
                                   const std::function<Rgba(uint32_t vertex)>& fallback) {
  const std::size_t n = mesh.positions.size();
  FillResult result;

  // Number the unknown vertices 0..m-1.
  std::vector<uint32_t> slot(n, kNotUnknown);
  std::vector<uint32_t> vertex_of;
  for (std::size_t v = 0; v < n; ++v) {
    if (unknown[v]) {
      slot[v] = static_cast<uint32_t>(vertex_of.size());
      vertex_of.push_back(static_cast<uint32_t>(v));
    }
  }
  const std::size_t m = vertex_of.size();
  if (m == 0) return result;

  // Components of unknown vertices, and which of them touch a known vertex.
  DisjointSets sets(m);
  std::vector<uint8_t> touches_known(m, 0);
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[k], b = tri[(k + 1) % 3];
      const uint32_t sa = slot[a], sb = slot[b];
      if (sa != kNotUnknown && sb != kNotUnknown) {
        sets.unite(sa, sb);
      } else if (sa != kNotUnknown) {
        touches_known[sa] = 1;
      } else if (sb != kNotUnknown) {
        touches_known[sb] = 1;
      }
    }
  }
  std::vector<uint8_t> anchored(m, 0);
  for (std::size_t i = 0; i < m; ++i) {
    if (touches_known[i]) anchored[sets.find(static_cast<uint32_t>(i))] = 1;
  }

  // Renumber the anchored unknowns (the system's rows); the others fall back.
  std::vector<uint32_t> row(m, kNotUnknown);
  std::size_t rows = 0;
  for (std::size_t i = 0; i < m; ++i) {
    if (anchored[sets.find(static_cast<uint32_t>(i))]) {
      row[i] = static_cast<uint32_t>(rows++);
    } else {
      colors[vertex_of[i]] = fallback(vertex_of[i]);
      ++result.unfilled;
    }
  }
  result.filled = rows;
  if (rows == 0) return result;

  // L_uu c_u = W_ub c_b: each triangle edge adds weight 1 (so an interior edge
  // of a manifold mesh weighs 2, uniformly: the solution is unchanged). Only
  // the lower triangle is stored: SimplicialLDLT reads no more.
  std::vector<double> diagonal(rows, 0.0);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(mesh.triangles.size() * 2 + rows);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows), 4);
  auto row_of = [&](uint32_t v) { return slot[v] == kNotUnknown ? kNotUnknown : row[slot[v]]; };
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[k], b = tri[(k + 1) % 3];
      const uint32_t ra = row_of(a), rb = row_of(b);
      if (ra != kNotUnknown && rb != kNotUnknown) {
        diagonal[ra] += 1, diagonal[rb] += 1;
        triplets.emplace_back(std::max(ra, rb), std::min(ra, rb), -1.0);
      } else if (ra != kNotUnknown) {
        // b is known (an unanchored unknown never shares an edge with an anchored one).
        diagonal[ra] += 1;
        for (int c = 0; c < 4; ++c) rhs(ra, c) += colors[b][c];
      } else if (rb != kNotUnknown) {
        diagonal[rb] += 1;
        for (int c = 0; c < 4; ++c) rhs(rb, c) += colors[a][c];
      }
    }
  }
  for (std::size_t r = 0; r < rows; ++r) triplets.emplace_back(r, r, diagonal[r]);
  Eigen::SparseMatrix<double> laplacian(static_cast<Eigen::Index>(rows),
                                        static_cast<Eigen::Index>(rows));
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  triplets = {};

  // AMD ordering (Eigen's default) keeps the fill-in of the factor small.
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver(laplacian);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kInternal, "occlusion fill: factorising the Laplacian failed");
  }
  const Eigen::MatrixXd solution = solver.solve(rhs);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kInternal, "occlusion fill: solving the Laplace system failed");
  }
  for (std::size_t i = 0; i < m; ++i) {
    if (row[i] == kNotUnknown) continue;
    const auto r = static_cast<Eigen::Index>(row[i]);
    for (int c = 0; c < 4; ++c) colors[vertex_of[i]][c] = static_cast<float>(solution(r, c));
  }
  return result;
}

}  // namespace texbake
