// Chart flattening by least-squares conformal maps (see
// bake/uv_generate_internal.h), solved directly with Eigen.
//
// Why not CGAL's LSCM_parameterizer_3 (used before): it builds the normal
// equations row by row through OpenNL and rebuilds a Surface_mesh per chart;
// on an 830k-triangle mesh that overhead alone was as large as the sparse
// factorisation. The energy here is the same one (Levy, Petitjean, Ray,
// Maillot 2002), written in its equivalent form "Dirichlet energy minus
// signed area" (Desbrun, Meyer, Alliez 2002, section 3.2; Mullen et al. 2008):
//   E_C(u, v) = 1/2 (u^T L u + v^T L v) - A(u, v),
// L the cotangent Laplacian, A the signed area of the border polygon. Its
// Hessian is assembled with setFromTriplets and factorised once by Eigen's
// SimplicialLDLT. The disk check that CGAL's Surface_mesh did is done by the
// caller (Euler characteristic and border loops of the welded chart), so this
// translation unit needs no CGAL any more.
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>

#include "bake/uv/uv_generate_internal.h"

namespace texbake::uv_detail {

FlattenStatus flatten_lscm(const ChartMesh& chart, std::vector<double>& uv) {
  const std::size_t n = chart.positions.size() / 3;
  if (n < 3 || chart.fixed0 == chart.fixed1 || chart.fixed0 >= n || chart.fixed1 >= n) {
    return FlattenStatus::kSolveFailed;
  }
  // Unknowns interleaved (u_i, v_i); the two pinned vertices are eliminated
  // and their fixed values moved to the right-hand side.
  //
  // Fill-reducing order: AMD on the vertex graph (n - 2 nodes), each vertex's
  // (u, v) pair then kept adjacent. The Hessian's pattern is exactly the
  // vertex graph with 2x2 blocks, so this is the same kind of order as AMD on
  // the full 2(n - 2) system (which Eigen's default would compute) at about a
  // quarter of the ordering work; the factorisation then uses it as given.
  std::vector<int> vid(n, -1);
  int nu = 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (v != chart.fixed0 && v != chart.fixed1) vid[v] = nu++;
  }
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm;
  {
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(chart.faces.size() * 3 + nu);
    for (int v = 0; v < nu; ++v) pattern.emplace_back(v, v, 1.0);
    for (const auto& f : chart.faces) {
      for (int k = 0; k < 3; ++k) {
        const int a = vid[f[k]], b = vid[f[(k + 1) % 3]];
        if (a >= 0 && b >= 0) pattern.emplace_back(std::max(a, b), std::min(a, b), 1.0);
      }
    }
    Eigen::SparseMatrix<double> s(nu, nu);
    s.setFromTriplets(pattern.begin(), pattern.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pinv;
    Eigen::AMDOrdering<int> amd;
    amd(s.selfadjointView<Eigen::Lower>(), pinv);
    perm = pinv.inverse();
  }
  std::vector<int> index(2 * n);
  const int m = 2 * nu;
  for (std::size_t v = 0; v < n; ++v) {
    const int r = vid[v] < 0 ? -1 : perm.indices()[vid[v]];
    index[2 * v] = r < 0 ? -1 : 2 * r;
    index[2 * v + 1] = r < 0 ? -1 : 2 * r + 1;
  }
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(chart.faces.size() * 3 * 6 + chart.border.size() * 2);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  // Adds w to H(r, c) of the full Hessian. Only the lower triangle is kept
  // (every off-diagonal entry is added from both sides).
  auto add = [&](std::size_t r_full, std::size_t c_full, double w) {
    const int r = index[r_full];
    if (r < 0) return;
    const int c = index[c_full];
    if (c < 0) {
      rhs[r] -= w * chart.initial_uv[c_full];
    } else if (c <= r) {
      triplets.emplace_back(r, c, w);
    }
  };
  const double* p = chart.positions.data();
  for (const auto& f : chart.faces) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t o = f[k], i = f[(k + 1) % 3], j = f[(k + 2) % 3];
      double e1[3], e2[3];
      for (int d = 0; d < 3; ++d) {
        e1[d] = p[3 * i + d] - p[3 * o + d];
        e2[d] = p[3 * j + d] - p[3 * o + d];
      }
      const double dot = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
      const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                   cz = e1[0] * e2[1] - e1[1] * e2[0];
      const double l1 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
      const double l2 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
      // A triangle degenerate in 3D would give an infinite cotangent; the
      // floor keeps the system finite (the caller rejects a map that squeezes
      // a triangle to nothing and splits the chart).
      const double cross =
          std::max(std::sqrt(cx * cx + cy * cy + cz * cz), 1e-10 * std::sqrt(l1 * l2));
      if (!(cross > 0)) return FlattenStatus::kSolveFailed;
      const double w = 0.5 * dot / cross;  // half the cotangent at corner o, for edge (i, j)
      for (std::size_t d = 0; d < 2; ++d) {
        add(2 * i + d, 2 * i + d, w);
        add(2 * j + d, 2 * j + d, w);
        add(2 * i + d, 2 * j + d, -w);
        add(2 * j + d, 2 * i + d, -w);
      }
    }
  }
  // Signed area of the border polygon, A = 1/2 sum over border edges i->j of
  // (u_i v_j - u_j v_i) (border edges run counter-clockwise for a chart of
  // counter-clockwise faces): its Hessian is subtracted.
  for (const auto& [i, j] : chart.border) {
    add(2 * i, 2 * j + 1, -0.5);
    add(2 * j + 1, 2 * i, -0.5);
    add(2 * j, 2 * i + 1, 0.5);
    add(2 * i + 1, 2 * j, 0.5);
  }
  Eigen::SparseMatrix<double> h(m, m);
  h.setFromTriplets(triplets.begin(), triplets.end());
  triplets = {};
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>>
      ldlt(h);
  if (ldlt.info() != Eigen::Success) return FlattenStatus::kSolveFailed;
  const Eigen::VectorXd x = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success) return FlattenStatus::kSolveFailed;
  uv.resize(2 * n);
  for (std::size_t k = 0; k < 2 * n; ++k) {
    uv[k] = index[k] < 0 ? chart.initial_uv[k] : x[index[k]];
    if (!std::isfinite(uv[k])) return FlattenStatus::kSolveFailed;
  }
  return FlattenStatus::kOk;
}

}  // namespace texbake::uv_detail
