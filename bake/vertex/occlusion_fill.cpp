#include "bake/vertex/occlusion_fill.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <numeric>
#include <unordered_map>
#include <utility>

#include "bake/util/parallel.h"
#include "bake/vertex/laplace_multigrid.h"
#include "mesh_io/weld.h"

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

// The Laplacian of rows [first, first + size) (one component) for the
// multigrid solver, its rows and columns renumbered by `order` (new row r is
// local row order[r]): `diagonal` on the diagonal and, per coupling, minus
// the number of times it is listed. adjacency: the couplings of every row,
// global row numbers, each row's sorted (repeats adjacent); start: where
// each row's list begins (start[first + size] ends the last). Each new row
// is written in parallel straight into the compressed arrays, sorted by
// column, repeats summed: the matrix a component matrix built entry by
// entry and then renumbered would be, in one pass.
LaplaceMatrix ordered_component_matrix(const std::vector<int>& start,
                                       const std::vector<int>& adjacency,
                                       const std::vector<double>& diagonal, uint32_t first,
                                       Eigen::Index size, const std::vector<int>& order) {
  std::vector<int> new_of(static_cast<std::size_t>(size));
  for (Eigen::Index r = 0; r < size; ++r) new_of[order[r]] = static_cast<int>(r);
  // Distinct neighbours of each row (its sorted list's runs), plus the diagonal.
  std::vector<int> kept(static_cast<std::size_t>(size));
  parallel_for_chunks(static_cast<std::size_t>(size), 4096, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      int distinct = 1;
      const int rb = start[first + i], re = start[first + i + 1];
      for (int k = rb; k < re; ++k) distinct += k == rb || adjacency[k] != adjacency[k - 1];
      kept[i] = distinct;
    }
  });
  LaplaceMatrix m(size, size);
  int* outer = m.outerIndexPtr();
  outer[0] = 0;
  for (Eigen::Index r = 0; r < size; ++r) outer[r + 1] = outer[r] + kept[order[r]];
  kept = {};
  m.resizeNonZeros(outer[size]);
  int* inner = m.innerIndexPtr();
  double* value = m.valuePtr();
  parallel_for_chunks(static_cast<std::size_t>(size), 4096, [&](std::size_t b, std::size_t e) {
    std::vector<std::pair<int, double>> row;
    for (std::size_t r = b; r < e; ++r) {
      const auto old = static_cast<uint32_t>(order[r]);
      row.clear();
      row.emplace_back(static_cast<int>(r), diagonal[first + old]);
      const int rb = start[first + old], re = start[first + old + 1];
      for (int k = rb; k < re;) {
        int run = k + 1;
        while (run < re && adjacency[run] == adjacency[k]) ++run;
        row.emplace_back(new_of[adjacency[k] - static_cast<int>(first)],
                         -static_cast<double>(run - k));
        k = run;
      }
      std::sort(row.begin(), row.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
      for (std::size_t k = 0; k < row.size(); ++k) {
        inner[outer[r] + k] = row[k].first;
        value[outer[r] + k] = row[k].second;
      }
    }
  });
  return m;
}

}  // namespace

FillPlan plan_fill(const MeshData& mesh, std::vector<Rgba>& colors,
                   const std::vector<uint8_t>& unknown,
                   const std::function<Rgba(uint32_t vertex)>& fallback) {
  const std::size_t n = mesh.positions.size();
  FillPlan plan;
  FillResult& result = plan.result;

  // Vertices at one position (split at a UV or normal seam: mesh_io/weld.h)
  // are one point of the graph, so a seam does not cut the fill apart. A
  // point with a known copy is known: its unknown copies take the mean of
  // the known copies' colours. Without shared positions every vertex is its
  // own point (the code below then numbers and solves exactly as if there
  // were no welding).
  const std::vector<uint32_t> weld = weld_by_position(mesh);
  std::vector<uint8_t> point_known;  // per first copy: 1 if a copy is known
  if (!weld.empty()) {
    point_known.assign(n, 0);
    for (std::size_t v = 0; v < n; ++v) {
      if (!unknown[v]) point_known[weld[v]] = 1;
    }
    std::unordered_map<uint32_t, std::pair<std::array<double, 4>, uint32_t>> known_mean;
    for (std::size_t v = 0; v < n; ++v) {
      if (unknown[v] && point_known[weld[v]]) known_mean.try_emplace(weld[v]);
    }
    for (std::size_t v = 0; v < n && !known_mean.empty(); ++v) {
      if (unknown[v]) continue;
      auto it = known_mean.find(weld[v]);
      if (it == known_mean.end()) continue;
      for (int c = 0; c < 4; ++c) it->second.first[c] += colors[v][c];
      ++it->second.second;
    }
    for (std::size_t v = 0; v < n; ++v) {
      if (!unknown[v] || !point_known[weld[v]]) continue;
      const auto& [sum, count] = known_mean.at(weld[v]);
      for (int c = 0; c < 4; ++c) colors[v][c] = static_cast<float>(sum[c] / count);
      ++result.filled;
    }
  }

  // Number the unknown points 0..m-1 (in order of their first copy); every
  // copy of a point has its slot.
  std::vector<uint32_t> slot(n, kNotUnknown);
  std::vector<uint32_t> vertex_of;
  for (std::size_t v = 0; v < n; ++v) {
    if (!unknown[v]) continue;
    if (weld.empty() || weld[v] == v) {
      if (!weld.empty() && point_known[v]) continue;
      slot[v] = static_cast<uint32_t>(vertex_of.size());
      vertex_of.push_back(static_cast<uint32_t>(v));
    } else {
      slot[v] = slot[weld[v]];  // kNotUnknown for a point with a known copy
    }
  }
  const std::size_t m = vertex_of.size();
  if (m == 0) return plan;

  // Components of unknown vertices, and which of them touch a known vertex.
  DisjointSets sets(m);
  std::vector<uint8_t> touches_known(m, 0);
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[k], b = tri[(k + 1) % 3];
      const uint32_t sa = slot[a], sb = slot[b];
      if (sa != kNotUnknown && sb != kNotUnknown) {
        sets.unite(sa, sb);  // (sa == sb: an edge between copies of one point, no coupling)
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

  // Rows of the system: the anchored unknowns, numbered so that each
  // component's rows are contiguous (components in order of their smallest
  // unknown, vertices in input order within one). The others fall back.
  std::vector<uint32_t> component_of_root(m, kNotUnknown);
  std::vector<uint32_t> component_start;  // first row of each component, + total
  for (std::size_t i = 0; i < m; ++i) {
    const uint32_t root = sets.find(static_cast<uint32_t>(i));
    if (!anchored[root]) continue;
    if (component_of_root[root] == kNotUnknown) {
      component_of_root[root] = static_cast<uint32_t>(component_start.size());
      component_start.push_back(0);
    }
    ++component_start[component_of_root[root]];
  }
  {
    uint32_t total = 0;
    for (uint32_t& c : component_start) total += std::exchange(c, total);
    component_start.push_back(total);
  }
  std::vector<uint32_t> row(m, kNotUnknown);
  {
    std::vector<uint32_t> next(component_start.begin(), component_start.end() - 1);
    for (std::size_t i = 0; i < m; ++i) {
      const uint32_t root = sets.find(static_cast<uint32_t>(i));
      if (anchored[root]) row[i] = next[component_of_root[root]]++;
    }
  }
  // Counted per vertex: every copy of a point is filled, or takes its own
  // fallback.
  for (std::size_t v = 0; v < n; ++v) {
    if (slot[v] == kNotUnknown) continue;
    if (row[slot[v]] != kNotUnknown) {
      ++result.filled;
    } else {
      colors[v] = fallback(static_cast<uint32_t>(v));
      ++result.unfilled;
    }
  }
  plan.slot = std::move(slot);
  plan.row = std::move(row);
  plan.vertex_of = std::move(vertex_of);
  plan.component_start = std::move(component_start);
  return plan;
}

Expected<FillResult> solve_fill(const MeshData& mesh, std::vector<Rgba>& colors, FillPlan plan,
                                const FillSolverOptions& solver) {
  const std::vector<uint32_t>& slot = plan.slot;
  const std::vector<uint32_t>& row = plan.row;
  const std::vector<uint32_t>& component_start = plan.component_start;
  FillResult result = plan.result;
  const std::size_t rows = component_start.empty() ? 0 : component_start.back();
  if (rows == 0) return result;
  const std::size_t components = component_start.size() - 1;

  // L_uu c_u = W_ub c_b: each triangle edge adds weight 1 (so an interior edge
  // of a manifold mesh weighs 2, uniformly: the solution is unchanged).
  std::vector<double> diagonal(rows, 0.0);
  std::vector<std::pair<uint32_t, uint32_t>> couplings;  // (row, column), row > column
  couplings.reserve(mesh.triangles.size());              // reserved, not touched: no page is spent
  std::vector<int> start(rows + 1, 0);  // couplings per row, then where each row's begin
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows), 4);
  auto row_of = [&](uint32_t v) { return slot[v] == kNotUnknown ? kNotUnknown : row[slot[v]]; };
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[k], b = tri[(k + 1) % 3];
      const uint32_t ra = row_of(a), rb = row_of(b);
      if (ra != kNotUnknown && rb != kNotUnknown) {
        if (ra == rb) continue;  // copies of one point (a zero-length edge)
        diagonal[ra] += 1, diagonal[rb] += 1;
        couplings.emplace_back(std::max(ra, rb), std::min(ra, rb));
        ++start[ra + 1], ++start[rb + 1];
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
  // Every row's couplings, both ways, in compressed rows over all the rows
  // (a component's rows are contiguous, so its couplings are a contiguous
  // slice), each row's list sorted: repeated couplings (an edge of two
  // triangles) end up side by side.
  for (std::size_t r = 0; r < rows; ++r) start[r + 1] += start[r];
  std::vector<int> adjacency(static_cast<std::size_t>(start[rows]));  // written whole below
  {
    std::vector<int> next(start.begin(), start.end() - 1);
    for (const auto& [r, col] : couplings) {
      adjacency[next[r]++] = static_cast<int>(col);
      adjacency[next[col]++] = static_cast<int>(r);
    }
  }
  couplings = {};
  parallel_for_chunks(rows, 4096, [&](std::size_t b, std::size_t e) {
    for (std::size_t r = b; r < e; ++r) {
      std::sort(adjacency.begin() + start[r], adjacency.begin() + start[r + 1]);
    }
  });

  // One sparse symmetric positive definite solve per component: a component's
  // factor is freed before the next is built, so the peak memory is that of
  // the largest component, not of all. Only the lower triangle is stored
  // (SimplicialLDLT reads no more); AMD ordering (Eigen's default) keeps the
  // factor's fill-in small.
  //
  // A component of more than solver.direct_rows rows is solved iteratively
  // instead (bake/vertex/laplace_multigrid.h): a direct factor's time and
  // memory grow as n^1.5 or worse on a surface, the multigrid's linearly.
  // Its rows are numbered breadth-first first (the solver's products gather
  // neighbours' values), and its matrix, right-hand side and solution are
  // made in that order straight from the couplings (no matrix in the
  // component's own order, no copies of the vectors).
  std::vector<Eigen::Triplet<double>> triplets;
  for (std::size_t c = 0; c < components; ++c) {
    const uint32_t first = component_start[c];
    const auto size = static_cast<Eigen::Index>(component_start[c + 1] - first);
    if (static_cast<std::size_t>(size) > solver.direct_rows) {
      const std::vector<int> order = breadth_first_order(size, start.data() + first,
                                                         adjacency.data(), static_cast<int>(first));
      LaplaceMatrix laplacian =
          ordered_component_matrix(start, adjacency, diagonal, first, size, order);
      ColorColumns b(size, 4);
      for (Eigen::Index r = 0; r < size; ++r) b.row(r) = rhs.row(first + order[r]);
      ColorColumns x = ColorColumns::Zero(size, 4);
      Expected<MultigridStats> solved =
          solve_laplace_multigrid_ordered(std::move(laplacian), b, x, solver.relative_tolerance);
      if (!solved) return solved.error();
      result.iterations = std::max(result.iterations, solved->iterations);
      for (Eigen::Index r = 0; r < size; ++r) rhs.row(first + order[r]) = x.row(r);
      continue;
    }
    // The lower triangle: each coupling once, as (row, column) with row > column.
    triplets.clear();
    for (Eigen::Index r = 0; r < size; ++r) {
      const int global = static_cast<int>(first + r);
      for (int k = start[global]; k < start[global + 1]; ++k) {
        if (adjacency[k] < global)
          triplets.emplace_back(r, adjacency[k] - static_cast<int>(first), -1.0);
      }
    }
    for (Eigen::Index r = 0; r < size; ++r) triplets.emplace_back(r, r, diagonal[first + r]);
    Eigen::SparseMatrix<double> laplacian(size, size);
    laplacian.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> direct(laplacian);
    if (direct.info() != Eigen::Success) {
      return make_error(ErrorCode::kInternal, "occlusion fill: factorising the Laplacian failed");
    }
    rhs.middleRows(first, size) = direct.solve(rhs.middleRows(first, size)).eval();
    if (direct.info() != Eigen::Success) {
      return make_error(ErrorCode::kInternal, "occlusion fill: solving the Laplace system failed");
    }
  }
  for (std::size_t v = 0; v < slot.size(); ++v) {
    if (slot[v] == kNotUnknown || row[slot[v]] == kNotUnknown) continue;
    const auto r = static_cast<Eigen::Index>(row[slot[v]]);
    for (int c = 0; c < 4; ++c) colors[v][c] = static_cast<float>(rhs(r, c));
  }
  return result;
}

Expected<FillResult> fill_harmonic(const MeshData& mesh, std::vector<Rgba>& colors,
                                   const std::vector<uint8_t>& unknown,
                                   const std::function<Rgba(uint32_t vertex)>& fallback,
                                   const FillSolverOptions& solver) {
  return solve_fill(mesh, colors, plan_fill(mesh, colors, unknown, fallback), solver);
}

}  // namespace texbake
