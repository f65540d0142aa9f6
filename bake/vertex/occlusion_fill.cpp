#include "bake/vertex/occlusion_fill.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <numeric>
#include <span>
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

// The whole symmetric matrix of one component for the multigrid solver, in
// compressed rows: `diagonal` on the diagonal and -1 per coupling (row, col)
// at both (row, col) and (col, row), repeated couplings summed. Rows and
// columns are local (row - first).
using Coupling = std::pair<uint32_t, uint32_t>;
LaplaceMatrix component_matrix(const Coupling* couplings_begin, const Coupling* couplings_end,
                               const double* diagonal, uint32_t first, Eigen::Index size) {
  const std::span<const Coupling> couplings(couplings_begin, couplings_end);
  std::vector<int> start(static_cast<std::size_t>(size) + 1, 1);  // the diagonal
  start[0] = 0;
  for (const auto& [r, c] : couplings) ++start[r - first + 1], ++start[c - first + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<int> column(static_cast<std::size_t>(start.back()));
  std::vector<double> value(column.size());
  std::vector<int> next(start.begin(), start.end() - 1);
  for (Eigen::Index i = 0; i < size; ++i) {
    column[next[i]] = static_cast<int>(i), value[next[i]++] = diagonal[i];
  }
  for (const auto& [r, c] : couplings) {
    const int lr = static_cast<int>(r - first), lc = static_cast<int>(c - first);
    column[next[lr]] = lc, value[next[lr]++] = -1.0;
    column[next[lc]] = lr, value[next[lc]++] = -1.0;
  }
  // Sort each row by column and sum repeats (an edge shared by two triangles).
  std::vector<int> kept(static_cast<std::size_t>(size));
  parallel_for_chunks(static_cast<std::size_t>(size), 4096,
                      [&](std::size_t begin, std::size_t end) {
                        std::vector<std::pair<int, double>> row;
                        for (std::size_t i = begin; i < end; ++i) {
                          row.clear();
                          for (int k = start[i]; k < start[i + 1]; ++k)
                            row.emplace_back(column[k], value[k]);
                          std::sort(row.begin(), row.end(),
                                    [](const auto& x, const auto& y) { return x.first < y.first; });
                          int out = start[i];
                          for (std::size_t k = 0; k < row.size(); ++k) {
                            if (out > start[i] && column[out - 1] == row[k].first) {
                              value[out - 1] += row[k].second;
                            } else {
                              column[out] = row[k].first, value[out++] = row[k].second;
                            }
                          }
                          kept[i] = out - start[i];
                        }
                      });
  // The kept entries, written straight into the compressed arrays.
  LaplaceMatrix m(size, size);
  int* outer = m.outerIndexPtr();
  outer[0] = 0;
  for (Eigen::Index i = 0; i < size; ++i) outer[i + 1] = outer[i] + kept[i];
  m.resizeNonZeros(outer[size]);
  parallel_for_chunks(
      static_cast<std::size_t>(size), 4096, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          std::copy_n(column.begin() + start[i], kept[i], m.innerIndexPtr() + outer[i]);
          std::copy_n(value.begin() + start[i], kept[i], m.valuePtr() + outer[i]);
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
  couplings.reserve(mesh.triangles.size());
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
  // Group the couplings by component (a stable counting sort on their row).
  std::vector<uint32_t> component_of_row(rows);
  for (std::size_t c = 0; c < components; ++c) {
    std::fill(component_of_row.begin() + component_start[c],
              component_of_row.begin() + component_start[c + 1], static_cast<uint32_t>(c));
  }
  std::vector<uint32_t> coupling_start(components + 1, 0);
  for (const auto& [r, col] : couplings) ++coupling_start[component_of_row[r] + 1];
  for (std::size_t c = 0; c < components; ++c) coupling_start[c + 1] += coupling_start[c];
  std::vector<std::pair<uint32_t, uint32_t>> grouped(couplings.size());
  {
    std::vector<uint32_t> next(coupling_start.begin(), coupling_start.end() - 1);
    for (const auto& e : couplings) grouped[next[component_of_row[e.first]]++] = e;
  }
  couplings = {};

  // One sparse symmetric positive definite solve per component: a component's
  // factor is freed before the next is built, so the peak memory is that of
  // the largest component, not of all. Only the lower triangle is stored
  // (SimplicialLDLT reads no more); AMD ordering (Eigen's default) keeps the
  // factor's fill-in small.
  //
  // A component of more than solver.direct_rows rows is solved iteratively
  // instead (bake/vertex/laplace_multigrid.h): a direct factor's time and
  // memory grow as n^1.5 or worse on a surface, the multigrid's linearly.
  std::vector<Eigen::Triplet<double>> triplets;
  for (std::size_t c = 0; c < components; ++c) {
    const uint32_t first = component_start[c];
    const auto size = static_cast<Eigen::Index>(component_start[c + 1] - first);
    if (static_cast<std::size_t>(size) > solver.direct_rows) {
      const LaplaceMatrix laplacian = component_matrix(grouped.data() + coupling_start[c],
                                                       grouped.data() + coupling_start[c + 1],
                                                       diagonal.data() + first, first, size);
      const ColorColumns b = rhs.middleRows(first, size);
      ColorColumns x;
      Expected<MultigridStats> solved =
          solve_laplace_multigrid(laplacian, b, x, solver.relative_tolerance);
      if (!solved) return solved.error();
      result.iterations = std::max(result.iterations, solved->iterations);
      rhs.middleRows(first, size) = x;
      continue;
    }
    triplets.clear();
    for (uint32_t k = coupling_start[c]; k < coupling_start[c + 1]; ++k) {
      triplets.emplace_back(grouped[k].first - first, grouped[k].second - first, -1.0);
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
