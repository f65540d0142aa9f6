#include "bake/vertex/laplace_multigrid.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "bake/util/parallel.h"

namespace texbake {

namespace {

using Index = Eigen::Index;
using CoarseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Columns4 = std::array<double, 4>;

constexpr Index kCoarsestRows = 1500;  // solved by a direct factorisation at or below
constexpr int kMaxLevels = 30;
constexpr double kStrength = 0.08;  // strong: |a_ij| >= kStrength * sqrt(a_ii a_jj)
constexpr Index kBlockRows = 4096;  // rows per parallel block (fixed: sums stay deterministic)

struct Level {
  LaplaceMatrix a;  // released on the finest level once copied into `compact`
  // The finest level's a with float values, when every value is exactly a
  // float (the graph Laplacian's small integers): 8 bytes a non-zero
  // instead of 12 for the product that every CG iteration and V-cycle
  // repeat most. Empty otherwise.
  struct {
    std::vector<int> outer, inner;
    std::vector<float> value;
  } compact;
  Eigen::VectorXd jacobi;  // omega / a_ii: the damped Jacobi weights
  LaplaceMatrix p;         // prolongation from the next coarser level (rows: this level)
  LaplaceMatrix r;         // restriction to it, p^T
  ColorColumns x, b, t;    // the V-cycle's vectors on this level
};

Index block_count(Index rows) {
  return (rows + kBlockRows - 1) / kBlockRows;
}

// Calls fn(begin, end) on the fixed row blocks of [0, rows), in parallel.
template <class Fn>
void for_row_blocks(Index rows, Fn&& fn) {
  parallel_for_blocks(static_cast<std::size_t>(rows), static_cast<std::size_t>(kBlockRows),
                      [&](std::size_t, std::size_t begin, std::size_t end) {
                        fn(static_cast<Index>(begin), static_cast<Index>(end));
                      });
}

// A matrix in compressed rows as the products read it: the values of the
// finest level are stored as float when that is exact (the graph Laplacian's
// small integers), the rest as double. The products widen every value to
// double, so they compute the same sums either way with less memory traffic.
template <class V>
struct Rows {
  const int* outer;
  const int* inner;
  const V* value;
  Index rows;
};

Rows<double> rows_of(const LaplaceMatrix& m) {
  return {m.outerIndexPtr(), m.innerIndexPtr(), m.valuePtr(), m.rows()};
}

// The four sums of m's row i times the columns of x.
template <class V>
inline Columns4 row_times(const Rows<V>& m, Index i, const double* xs) {
  Columns4 s{0, 0, 0, 0};
  for (int k = m.outer[i]; k < m.outer[i + 1]; ++k) {
    const double v = m.value[k];
    const double* row = xs + 4 * static_cast<Index>(m.inner[k]);
    s[0] += v * row[0], s[1] += v * row[1], s[2] += v * row[2], s[3] += v * row[3];
  }
  return s;
}

// Per-block partial sums of the four columns, added in block order at the
// end: the same sums, in the same order, whatever the thread count.
class BlockSums {
 public:
  explicit BlockSums(Index rows)
      : partial_(static_cast<std::size_t>(block_count(rows)), Columns4{0, 0, 0, 0}) {}
  void set(Index block_begin, const Columns4& s) {
    partial_[static_cast<std::size_t>(block_begin / kBlockRows)] = s;
  }
  Columns4 total() const {
    Columns4 t{0, 0, 0, 0};
    for (const Columns4& s : partial_) {
      for (int c = 0; c < 4; ++c) t[c] += s[c];
    }
    return t;
  }

 private:
  std::vector<Columns4> partial_;
};

// y = m x.
template <class V>
void multiply(const Rows<V>& m, const ColorColumns& x, ColorColumns& y) {
  y.resize(m.rows, 4);
  const double* xs = x.data();
  double* ys = y.data();
  for_row_blocks(m.rows, [&](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) {
      const Columns4 s = row_times(m, i, xs);
      for (int c = 0; c < 4; ++c) ys[4 * i + c] = s[c];
    }
  });
}

// y = m x, returning per column the sum over rows of x(i, c) * y(i, c) (m
// square): the product and column_dots(x, y) in one pass.
template <class V>
Columns4 multiply_dot(const Rows<V>& m, const ColorColumns& x, ColorColumns& y) {
  y.resize(m.rows, 4);
  const double* xs = x.data();
  double* ys = y.data();
  BlockSums sums(m.rows);
  for_row_blocks(m.rows, [&](Index begin, Index end) {
    Columns4 d{0, 0, 0, 0};
    for (Index i = begin; i < end; ++i) {
      const Columns4 s = row_times(m, i, xs);
      for (int c = 0; c < 4; ++c) ys[4 * i + c] = s[c];
      for (int c = 0; c < 4; ++c) d[c] += xs[4 * i + c] * ys[4 * i + c];
    }
    sums.set(begin, d);
  });
  return sums.total();
}

// y += m x.
template <class V>
void multiply_add(const Rows<V>& m, const ColorColumns& x, ColorColumns& y) {
  const double* xs = x.data();
  double* ys = y.data();
  for_row_blocks(m.rows, [&](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) {
      const Columns4 s = row_times(m, i, xs);
      for (int c = 0; c < 4; ++c) ys[4 * i + c] += s[c];
    }
  });
}

// out = b - a x.
template <class V>
void residual(const Rows<V>& a, const ColorColumns& x, const ColorColumns& b, ColorColumns& out) {
  out.resize(a.rows, 4);
  const double* xs = x.data();
  const double* bs = b.data();
  double* os = out.data();
  for_row_blocks(a.rows, [&](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) {
      const Columns4 s = row_times(a, i, xs);
      for (int c = 0; c < 4; ++c) os[4 * i + c] = bs[4 * i + c] - s[c];
    }
  });
}

// One damped Jacobi sweep out of place: out = x + jacobi (b - a x) (the
// residual and the update in one pass). With dot_with, also returns per
// column the sum over rows of dot_with(i, c) * out(i, c).
template <class V>
Columns4 jacobi_sweep(const Rows<V>& a, const Eigen::VectorXd& jacobi, const ColorColumns& x,
                      const ColorColumns& b, ColorColumns& out,
                      const ColorColumns* dot_with = nullptr) {
  out.resize(a.rows, 4);
  const double* xs = x.data();
  const double* bs = b.data();
  const double* ws = jacobi.data();
  double* os = out.data();
  const double* ds = dot_with ? dot_with->data() : nullptr;
  BlockSums sums(a.rows);
  for_row_blocks(a.rows, [&](Index begin, Index end) {
    Columns4 d{0, 0, 0, 0};
    for (Index i = begin; i < end; ++i) {
      const Columns4 s = row_times(a, i, xs);
      for (int c = 0; c < 4; ++c) {
        const double t = bs[4 * i + c] - s[c];
        os[4 * i + c] = xs[4 * i + c] + ws[i] * t;
      }
      if (ds) {
        for (int c = 0; c < 4; ++c) d[c] += ds[4 * i + c] * os[4 * i + c];
      }
    }
    sums.set(begin, d);
  });
  return sums.total();
}

// Per column, the sum over rows of u(i, c) * v(i, c): block partial sums in
// parallel, then added in block order.
Columns4 column_dots(const ColorColumns& u, const ColorColumns& v) {
  const double* us = u.data();
  const double* vs = v.data();
  BlockSums sums(u.rows());
  for_row_blocks(u.rows(), [&](Index begin, Index end) {
    Columns4 s{0, 0, 0, 0};
    for (Index i = begin; i < end; ++i) {
      for (int c = 0; c < 4; ++c) s[c] += us[4 * i + c] * vs[4 * i + c];
    }
    sums.set(begin, s);
  });
  return sums.total();
}

// Damped Jacobi weights omega / a_ii, with omega = 4 / (3 rho) and rho the
// Gershgorin bound max_i sum_j |a_ij| / a_ii on the spectral radius of
// D^-1 a (at most 2 for a diagonally dominant M-matrix): the usual choice
// for smoothed aggregation, safe without an eigenvalue estimate.
Eigen::VectorXd jacobi_weights(const LaplaceMatrix& a) {
  const Index n = a.rows();
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
  double rho = 0;
  for (Index i = 0; i < n; ++i) {
    double row_sum = 0;
    for (LaplaceMatrix::InnerIterator it(a, i); it; ++it) {
      if (it.col() == i) diagonal[i] = it.value();
      row_sum += std::abs(it.value());
    }
    rho = std::max(rho, row_sum / diagonal[i]);
  }
  const double omega = 4.0 / (3.0 * rho);
  return omega * diagonal.cwiseInverse();
}

// Greedy aggregation over the strong connections (the three phases of Vanek,
// Mandel and Brezina): a node whose strong neighbours are all free seeds an
// aggregate of itself and them; the rest join the aggregate of their
// strongest aggregated neighbour, and what is left forms aggregates of its
// own. Sequential, in row order: deterministic. Returns the count.
int aggregate(const LaplaceMatrix& a, std::vector<int>& aggregate_of) {
  const Index n = a.rows();
  Eigen::VectorXd diagonal(n);
  for (Index i = 0; i < n; ++i) diagonal[i] = a.coeff(i, i);
  auto strong = [&](Index i, const LaplaceMatrix::InnerIterator& it) {
    return it.col() != i &&
           std::abs(it.value()) >= kStrength * std::sqrt(diagonal[i] * diagonal[it.col()]);
  };
  aggregate_of.assign(static_cast<std::size_t>(n), -1);
  int count = 0;
  for (Index i = 0; i < n; ++i) {
    if (aggregate_of[i] != -1) continue;
    bool free = true, any = false;
    for (LaplaceMatrix::InnerIterator it(a, i); it && free; ++it) {
      if (!strong(i, it)) continue;
      any = true;
      free = aggregate_of[it.col()] == -1;
    }
    if (!free || !any) continue;
    aggregate_of[i] = count;
    for (LaplaceMatrix::InnerIterator it(a, i); it; ++it) {
      if (strong(i, it)) aggregate_of[it.col()] = count;
    }
    ++count;
  }
  const std::vector<int> seeded = aggregate_of;
  for (Index i = 0; i < n; ++i) {
    if (aggregate_of[i] != -1) continue;
    double best = 0;
    for (LaplaceMatrix::InnerIterator it(a, i); it; ++it) {
      if (strong(i, it) && seeded[it.col()] != -1 && std::abs(it.value()) > best) {
        best = std::abs(it.value());
        aggregate_of[i] = seeded[it.col()];
      }
    }
  }
  for (Index i = 0; i < n; ++i) {
    if (aggregate_of[i] != -1) continue;
    aggregate_of[i] = count;
    for (LaplaceMatrix::InnerIterator it(a, i); it; ++it) {
      if (strong(i, it) && aggregate_of[it.col()] == -1) aggregate_of[it.col()] = count;
    }
    ++count;
  }
  return count;
}

// One row of a sparse product being summed (build_rows below): a dense
// accumulator over all columns and the list of columns touched. Terms are
// added in the order given; flush emits the non-zero sums in ascending
// column order. Its arrays are per thread and kept between calls (flush
// leaves them zero): sized per block instead, they would cost blocks x
// columns to clear, quadratic in the mesh.
class DenseRow {
 public:
  explicit DenseRow(Index cols) : s_(scratch()) {
    // A row left by an exception: every marked column is in `touched`
    // (add() lists a column before marking it).
    for (int c : s_.touched) s_.sum[c] = 0.0, s_.seen[c] = 0;
    s_.touched.clear();
    const auto n = static_cast<std::size_t>(cols);
    if (s_.sum.size() < n) s_.sum.resize(n, 0.0);
    if (s_.seen.size() < n) s_.seen.resize(n, 0);
  }
  void add(int col, double v) {
    if (!s_.seen[col]) {
      s_.touched.push_back(col);
      s_.seen[col] = 1;
    }
    s_.sum[col] += v;
  }
  // Appends the row's non-zero entries to columns/values and clears it.
  void flush(std::vector<int>& columns, std::vector<double>& values) {
    std::sort(s_.touched.begin(), s_.touched.end());
    for (int c : s_.touched) {
      if (s_.sum[c] != 0.0) columns.push_back(c), values.push_back(s_.sum[c]);
      s_.sum[c] = 0.0, s_.seen[c] = 0;
    }
    s_.touched.clear();
  }

 private:
  struct Scratch {
    std::vector<double> sum;
    std::vector<uint8_t> seen;
    std::vector<int> touched;
  };
  static Scratch& scratch() {
    thread_local Scratch s;
    return s;
  }
  Scratch& s_;
};

// A rows x cols matrix in compressed rows whose row i is summed by
// fn(i, row) into a DenseRow, exact zeros dropped. Fixed blocks of rows are
// summed in parallel into their own lists, then copied into place. Each
// row's terms are added in the order fn gives them, so the matrix does not
// depend on the thread count.
//
// Hand-written rather than Eigen's sparse product: that runs on one thread
// and was most of the hierarchy's set-up time.
template <class RowFn>
LaplaceMatrix build_rows(Index rows, Index cols, RowFn&& fn) {
  const std::size_t blocks = static_cast<std::size_t>(block_count(rows));
  std::vector<std::vector<int>> block_columns(blocks);
  std::vector<std::vector<double>> block_values(blocks);
  std::vector<int> row_start(static_cast<std::size_t>(rows) + 1, 0);
  parallel_for_blocks(static_cast<std::size_t>(rows), static_cast<std::size_t>(kBlockRows),
                      [&](std::size_t block, std::size_t begin, std::size_t end) {
                        DenseRow row(cols);
                        auto& columns = block_columns[block];
                        auto& values = block_values[block];
                        for (std::size_t i = begin; i < end; ++i) {
                          const std::size_t before = columns.size();
                          fn(static_cast<Index>(i), row);
                          row.flush(columns, values);
                          row_start[i + 1] = static_cast<int>(columns.size() - before);
                        }
                      });
  for (Index i = 0; i < rows; ++i) row_start[i + 1] += row_start[i];
  LaplaceMatrix m(rows, cols);
  m.resizeNonZeros(row_start.back());
  std::copy(row_start.begin(), row_start.end(), m.outerIndexPtr());
  parallel_for_chunks(blocks, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      const int at = row_start[k * static_cast<std::size_t>(kBlockRows)];
      std::copy(block_columns[k].begin(), block_columns[k].end(), m.innerIndexPtr() + at);
      std::copy(block_values[k].begin(), block_values[k].end(), m.valuePtr() + at);
    }
  });
  return m;
}

// x * y (Gustavson's row-by-row product), in parallel.
LaplaceMatrix multiply_sparse(const LaplaceMatrix& x, const LaplaceMatrix& y) {
  return build_rows(x.rows(), y.cols(), [&](Index i, DenseRow& row) {
    for (LaplaceMatrix::InnerIterator xi(x, i); xi; ++xi) {
      for (LaplaceMatrix::InnerIterator yk(y, xi.col()); yk; ++yk) {
        row.add(static_cast<int>(yk.col()), xi.value() * yk.value());
      }
    }
  });
}

// The smoothed prolongation (I - D^-1 omega a) P_tent of the aggregation.
// P_tent has a single 1 per row, at the row's aggregate, so row i of the
// product is 1 at agg(i) minus jacobi_i times, per aggregate J, the sum of
// a_ij over the j of J.
LaplaceMatrix smoothed_prolongation(const LaplaceMatrix& a, const Eigen::VectorXd& jacobi,
                                    const std::vector<int>& aggregate_of, int coarse) {
  return build_rows(a.rows(), coarse, [&](Index i, DenseRow& row) {
    row.add(aggregate_of[i], 1.0);
    for (LaplaceMatrix::InnerIterator it(a, i); it; ++it) {
      row.add(aggregate_of[it.col()], -jacobi[i] * it.value());
    }
  });
}

class Hierarchy {
 public:
  // Takes the finest matrix over. Eigen 3.4's SparseMatrix has no move
  // constructor or assignment: a std::move copies it. Matrices are handed
  // over with swap, and the levels are reserved so that no vector growth
  // copies them either.
  Status build(LaplaceMatrix&& a) {
    levels_.clear();
    levels_.reserve(kMaxLevels);
    levels_.emplace_back();
    levels_.back().a.swap(a);
    while (static_cast<int>(levels_.size()) < kMaxLevels &&
           levels_.back().a.rows() > kCoarsestRows) {
      Level& fine = levels_.back();
      fine.jacobi = jacobi_weights(fine.a);
      std::vector<int> aggregate_of;
      const int coarse = aggregate(fine.a, aggregate_of);
      if (coarse >= fine.a.rows() * 9 / 10) break;  // coarsening stalled: solve here
      LaplaceMatrix p = smoothed_prolongation(fine.a, fine.jacobi, aggregate_of, coarse);
      fine.p.swap(p);
      fine.r = fine.p.transpose();
      const LaplaceMatrix ap = multiply_sparse(fine.a, fine.p);
      LaplaceMatrix coarse_a = multiply_sparse(fine.r, ap);
      levels_.emplace_back();
      levels_.back().a.swap(coarse_a);
    }
    levels_.back().p = {};
    levels_.back().r = {};
    coarsest_.compute(CoarseMatrix(levels_.back().a));
    if (coarsest_.info() != Eigen::Success) {
      return make_error(ErrorCode::kInternal,
                        "occlusion fill: factorising the coarsest multigrid level failed");
    }
    compact_finest();
    return ok_status();
  }

  int levels() const { return static_cast<int>(levels_.size()); }

  // out = b - a x and q = a p with the sums p(i, c) q(i, c), on the finest
  // level (the caller's CG).
  void residual_finest(const ColorColumns& x, const ColorColumns& b, ColorColumns& out) const {
    with_a(levels_[0], [&](const auto& a) { residual(a, x, b, out); });
  }
  Columns4 multiply_dot_finest(const ColorColumns& p, ColorColumns& q) const {
    Columns4 d{};
    with_a(levels_[0], [&](const auto& a) { d = multiply_dot(a, p, q); });
    return d;
  }

  // z = M r: one symmetric V-cycle (one damped Jacobi sweep before and one
  // after the coarse correction, so M is symmetric positive definite, as CG
  // needs). Returns per column the sum over rows of r(i, c) z(i, c).
  Columns4 apply(const ColorColumns& r, ColorColumns& z) { return cycle(0, r, z, true); }

 private:
  // fn(the level's a as Rows<float> or Rows<double>).
  template <class Fn>
  static void with_a(const Level& l, Fn&& fn) {
    if (!l.compact.value.empty()) {
      fn(Rows<float>{l.compact.outer.data(), l.compact.inner.data(), l.compact.value.data(),
                     static_cast<Index>(l.compact.outer.size()) - 1});
    } else {
      fn(rows_of(l.a));
    }
  }

  // The finest a into `compact` when every value converts to float and back
  // unchanged; the double copy is then released.
  void compact_finest() {
    Level& l = levels_[0];
    const Index nnz = l.a.nonZeros();
    const double* value = l.a.valuePtr();
    bool exact = l.a.isCompressed();
    for (Index k = 0; k < nnz && exact; ++k) {
      exact = static_cast<double>(static_cast<float>(value[k])) == value[k];
    }
    if (!exact || nnz == 0) return;
    l.compact.outer.assign(l.a.outerIndexPtr(), l.a.outerIndexPtr() + l.a.rows() + 1);
    l.compact.inner.assign(l.a.innerIndexPtr(), l.a.innerIndexPtr() + nnz);
    l.compact.value.resize(static_cast<std::size_t>(nnz));
    for (Index k = 0; k < nnz; ++k) l.compact.value[k] = static_cast<float>(value[k]);
    l.a = LaplaceMatrix();
  }

  // out = M_k b on level k: the V-cycle from x = 0. A level's `t` holds its
  // residual until it is restricted; the next coarser level's result is
  // written into that level's own `t` (free by then). With dot_b, returns
  // the sums b(i, c) out(i, c).
  Columns4 cycle(std::size_t k, const ColorColumns& b, ColorColumns& out, bool dot_b) {
    Level& l = levels_[k];
    if (k + 1 == levels_.size()) {
      out = coarsest_.solve(b);
      return dot_b ? column_dots(b, out) : Columns4{};
    }
    // The first sweep, from x = 0: x = jacobi b.
    l.x.resize(b.rows(), 4);
    for_row_blocks(b.rows(), [&](Index begin, Index end) {
      for (Index i = begin; i < end; ++i) {
        for (int c = 0; c < 4; ++c) l.x(i, c) = l.jacobi[i] * b(i, c);
      }
    });
    with_a(l, [&](const auto& a) { residual(a, l.x, b, l.t); });
    Level& next = levels_[k + 1];
    multiply(rows_of(l.r), l.t, next.b);
    cycle(k + 1, next.b, next.t, false);
    multiply_add(rows_of(l.p), next.t, l.x);
    Columns4 d{};
    with_a(l, [&](const auto& a) {
      d = jacobi_sweep(a, l.jacobi, l.x, b, out, dot_b ? &b : nullptr);
    });
    return d;
  }

  std::vector<Level> levels_;
  Eigen::SimplicialLDLT<CoarseMatrix, Eigen::Lower> coarsest_;
};

// a with rows and columns renumbered: new row r is old row order[r]. Each
// new row is old row order[r]'s entries renumbered and sorted by column,
// written in parallel straight into the compressed arrays (the sizes are
// known up front).
LaplaceMatrix reordered(const LaplaceMatrix& a, const std::vector<int>& order) {
  const Index n = a.rows();
  std::vector<int> new_of(static_cast<std::size_t>(n));
  for (Index r = 0; r < n; ++r) new_of[order[r]] = static_cast<int>(r);
  const int* a_outer = a.outerIndexPtr();
  LaplaceMatrix out(n, n);
  int* outer = out.outerIndexPtr();
  outer[0] = 0;
  for (Index r = 0; r < n; ++r) outer[r + 1] = outer[r] + a_outer[order[r] + 1] - a_outer[order[r]];
  out.resizeNonZeros(outer[n]);
  for_row_blocks(n, [&](Index begin, Index end) {
    std::vector<std::pair<int, double>> row;
    for (Index r = begin; r < end; ++r) {
      row.clear();
      for (int k = a_outer[order[r]]; k < a_outer[order[r] + 1]; ++k) {
        row.emplace_back(new_of[a.innerIndexPtr()[k]], a.valuePtr()[k]);
      }
      std::sort(row.begin(), row.end(),
                [](const auto& p, const auto& q) { return p.first < q.first; });
      for (std::size_t k = 0; k < row.size(); ++k) {
        out.innerIndexPtr()[outer[r] + k] = row[k].first;
        out.valuePtr()[outer[r] + k] = row[k].second;
      }
    }
  });
  return out;
}

Expected<MultigridStats> solve_ordered(LaplaceMatrix&& ordered, const ColorColumns& b,
                                       ColorColumns& x, double relative_tolerance,
                                       int max_iterations) {
  const Index n = ordered.rows();
  MultigridStats stats;
  Hierarchy hierarchy;
  if (Status built = hierarchy.build(std::move(ordered)); !built) return built.error();
  stats.levels = hierarchy.levels();

  Columns4 limit{}, b_norm2 = column_dots(b, b);
  std::array<bool, 4> done{};
  for (int c = 0; c < 4; ++c) {
    limit[c] = relative_tolerance * relative_tolerance * b_norm2[c];
    if (b_norm2[c] == 0) {  // the solution is zero: no iteration could reach |r| <= 0 otherwise
      x.col(c).setZero();
      done[c] = true;
    }
  }
  ColorColumns r, z, p, q;
  hierarchy.residual_finest(x, b, r);
  Columns4 rz = hierarchy.apply(r, z);
  p = z;
  auto converged = [&](const Columns4& r_norm2) {
    bool all = true;
    for (int c = 0; c < 4; ++c) {
      if (!done[c] && r_norm2[c] <= limit[c]) done[c] = true;
      all = all && done[c];
    }
    return all;
  };
  auto report = [&](const Columns4& r_norm2) {
    stats.worst_relative_residual = 0;
    for (int c = 0; c < 4; ++c) {
      if (b_norm2[c] > 0) {
        stats.worst_relative_residual =
            std::max(stats.worst_relative_residual, std::sqrt(r_norm2[c] / b_norm2[c]));
      }
    }
  };
  Columns4 r_norm2 = column_dots(r, r);
  while (!converged(r_norm2)) {
    if (stats.iterations == max_iterations) {
      report(r_norm2);
      return make_error(ErrorCode::kInternal,
                        "occlusion fill: the multigrid solver did not converge in " +
                            std::to_string(max_iterations) + " iterations");
    }
    ++stats.iterations;
    const Columns4 pq = hierarchy.multiply_dot_finest(p, q);
    Columns4 alpha{};
    for (int c = 0; c < 4; ++c) alpha[c] = done[c] || pq[c] <= 0 ? 0.0 : rz[c] / pq[c];
    // x += alpha p, r -= alpha q, and the sums r(i, c)^2, in one pass.
    {
      BlockSums sums(n);
      double* xs = x.data();
      double* rs = r.data();
      const double* ps = p.data();
      const double* qs = q.data();
      for_row_blocks(n, [&](Index begin, Index end) {
        Columns4 d{0, 0, 0, 0};
        for (Index i = begin; i < end; ++i) {
          for (int c = 0; c < 4; ++c) {
            xs[4 * i + c] += alpha[c] * ps[4 * i + c];
            rs[4 * i + c] -= alpha[c] * qs[4 * i + c];
          }
          for (int c = 0; c < 4; ++c) d[c] += rs[4 * i + c] * rs[4 * i + c];
        }
        sums.set(begin, d);
      });
      r_norm2 = sums.total();
    }
    if (converged(r_norm2)) break;
    const Columns4 rz_next = hierarchy.apply(r, z);
    Columns4 beta{};
    for (int c = 0; c < 4; ++c) beta[c] = done[c] || rz[c] == 0 ? 0.0 : rz_next[c] / rz[c];
    rz = rz_next;
    for_row_blocks(n, [&](Index begin, Index end) {
      for (Index i = begin; i < end; ++i) {
        for (int c = 0; c < 4; ++c) p(i, c) = z(i, c) + beta[c] * p(i, c);
      }
    });
  }
  report(r_norm2);
  return stats;
}

}  // namespace

std::vector<int> breadth_first_order(Index n, const int* start, const int* column, int offset) {
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(n));
  std::vector<uint8_t> seen(static_cast<std::size_t>(n), 0);
  for (Index seed = 0; seed < n; ++seed) {
    if (seen[seed]) continue;
    seen[seed] = 1;
    order.push_back(static_cast<int>(seed));
    for (std::size_t head = order.size() - 1; head < order.size(); ++head) {
      const int i = order[head];
      for (int k = start[i]; k < start[i + 1]; ++k) {
        const int j = column[k] - offset;
        if (!seen[j]) seen[j] = 1, order.push_back(j);
      }
    }
  }
  return order;
}

Expected<MultigridStats> solve_laplace_multigrid_ordered(LaplaceMatrix&& a, const ColorColumns& b,
                                                         ColorColumns& x, double relative_tolerance,
                                                         int max_iterations) {
  const Index n = a.rows();
  if (x.rows() != n) x = ColorColumns::Zero(n, 4);
  if (n == 0) return MultigridStats{};
  return solve_ordered(std::move(a), b, x, relative_tolerance, max_iterations);
}

Expected<MultigridStats> solve_laplace_multigrid(const LaplaceMatrix& a, const ColorColumns& b,
                                                 ColorColumns& x, double relative_tolerance,
                                                 int max_iterations) {
  const Index n = a.rows();
  if (x.rows() != n) x = ColorColumns::Zero(n, 4);
  if (n == 0) return MultigridStats{};
  LaplaceMatrix compressed;
  const LaplaceMatrix* m = &a;
  if (!a.isCompressed()) {
    compressed = a;
    compressed.makeCompressed();
    m = &compressed;
  }
  const std::vector<int> order = breadth_first_order(n, m->outerIndexPtr(), m->innerIndexPtr(), 0);
  ColorColumns ob(n, 4), ox(n, 4);
  for (Index r = 0; r < n; ++r) ob.row(r) = b.row(order[r]), ox.row(r) = x.row(order[r]);
  LaplaceMatrix ordered = reordered(*m, order);
  Expected<MultigridStats> stats =
      solve_ordered(std::move(ordered), ob, ox, relative_tolerance, max_iterations);
  if (stats) {
    for (Index r = 0; r < n; ++r) x.row(order[r]) = ox.row(r);
  }
  return stats;
}

}  // namespace texbake
