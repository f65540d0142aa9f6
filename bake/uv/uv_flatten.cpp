// Stage 3 of `--uv generate` (see uv_generate_internal.h): one chart known
// to be a disk flattened by least-squares conformal maps, solved directly with
// Eigen, then checked; charts rotated to their minimum-area bounding box.
//
// Why not CGAL's LSCM_parameterizer_3 (used before): it builds the normal
// equations row by row through OpenNL and rebuilds a Surface_mesh per chart;
// on an 830k-triangle mesh that overhead alone was as large as the sparse
// factorisation. The energy here is the same one (Levy, Petitjean, Ray,
// Maillot 2002), written in its equivalent form "Dirichlet energy minus
// signed area" (Desbrun, Meyer, Alliez 2002, section 3.2; Mullen et al. 2008):
//   E_C(u, v) = 1/2 (u^T L u + v^T L v) - A(u, v),
// L the cotangent Laplacian, A the signed area of the border polygon. Its
// Hessian, as the equivalent complex Hermitian matrix over z = u + iv, is
// assembled with setFromTriplets and factorised once by Eigen's
// SimplicialLDLT. The disk check that CGAL's Surface_mesh did is done by
// uv_cut.cpp (Euler characteristic and border loops of the welded chart).
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "bake/uv/uv_generate_internal.h"

namespace texbake::uv_detail {
namespace {

// One chart as a stand-alone triangle mesh: local vertices (corners of the
// chart's triangles welded across the chart's manifold, consistently oriented
// edges) and faces in the mesh's winding order.
struct ChartMesh {
  std::vector<double> positions;               // x, y, z per local vertex
  std::vector<std::array<uint32_t, 3>> faces;  // local vertex indices
  Border border;                               // border edges in face winding order
  std::vector<double> initial_uv;              // u, v per local vertex (only fixed0/1 are used)
  uint32_t fixed0 = 0, fixed1 = 0;             // locked at their initial_uv (LSCM needs two)
};

// Least-squares conformal map (Levy et al. 2002) of a chart that the caller
// has checked to be a topological disk (connected, Euler characteristic 1,
// one border loop), with chart.fixed0/fixed1 locked at their initial_uv. On
// success (true), uv holds u, v per local vertex; false when the
// factorisation failed or produced non-finite values. Flips and overlaps are
// not checked here (acceptable() does).
bool flatten_lscm(const ChartMesh& chart, std::vector<double>& uv) {
  const std::size_t n = chart.positions.size() / 3;
  if (n < 3 || chart.fixed0 == chart.fixed1 || chart.fixed0 >= n || chart.fixed1 >= n) {
    return false;
  }
  // One complex unknown z_i = u_i + i v_i per vertex (see below); the two
  // pinned vertices are eliminated and their fixed values moved to the
  // right-hand side.
  //
  // Fill-reducing order: AMD on the vertex graph (n - 2 nodes), computed
  // here and given to the factorisation as is.
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
  // The real Hessian over (u, v) is [[L, B], [B^T, L]] with B antisymmetric
  // (the area term couples u_i with v_j only), which is the real form of the
  // Hermitian matrix C = L - iB over z = u + iv (Levy et al.'s complex form of
  // the same energy): C z = b_u + i b_v solves the same system with half the
  // unknowns, a quarter of the factor's entries and about half its flops.
  std::vector<int> index(n);
  for (std::size_t v = 0; v < n; ++v) index[v] = vid[v] < 0 ? -1 : perm.indices()[vid[v]];
  using Complex = std::complex<double>;
  std::vector<Eigen::Triplet<Complex>> triplets;
  triplets.reserve(chart.faces.size() * 3 * 3 + chart.border.size() * 2);
  Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(nu);
  auto pinned = [&](std::size_t v) {
    return Complex(chart.initial_uv[2 * v], chart.initial_uv[2 * v + 1]);
  };
  // Adds w to C(r, c). Only the lower triangle is kept (every off-diagonal
  // entry is added from both sides, conjugated).
  auto add = [&](std::size_t r_full, std::size_t c_full, Complex w) {
    const int r = index[r_full];
    if (r < 0) return;
    const int c = index[c_full];
    if (c < 0) {
      rhs[r] -= w * pinned(c_full);
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
      if (!(cross > 0)) return false;
      const double w = 0.5 * dot / cross;  // half the cotangent at corner o, for edge (i, j)
      add(i, i, w);
      add(j, j, w);
      add(i, j, -w);
      add(j, i, -w);
    }
  }
  // Signed area of the border polygon, A = 1/2 sum over border edges i->j of
  // (u_i v_j - u_j v_i) (border edges run counter-clockwise for a chart of
  // counter-clockwise faces): its Hessian is subtracted, B(i, j) -= 1/2 and
  // B(j, i) += 1/2, so C(i, j) gains i/2 and C(j, i) -i/2.
  for (const auto& [i, j] : chart.border) {
    add(i, j, Complex(0, 0.5));
    add(j, i, Complex(0, -0.5));
  }
  Eigen::SparseMatrix<Complex> h(nu, nu);
  h.setFromTriplets(triplets.begin(), triplets.end());
  triplets = {};
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Complex>, Eigen::Lower, Eigen::NaturalOrdering<int>>
      ldlt(h);
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::VectorXcd z = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success) return false;
  uv.resize(2 * n);
  for (std::size_t v = 0; v < n; ++v) {
    const Complex c = index[v] < 0 ? pinned(v) : z[index[v]];
    uv[2 * v] = c.real();
    uv[2 * v + 1] = c.imag();
    if (!std::isfinite(uv[2 * v]) || !std::isfinite(uv[2 * v + 1])) return false;
  }
  return true;
}

// flatten_lscm with the two vertices farthest apart along the longer axis of
// the projection onto the piece's mean plane pinned (fc.uv in the solve's
// scale). False when the pins coincide or the solve fails.
bool pin_and_flatten(const Geometry& g, FlatChart& fc, const Border& border) {
  const auto& tris = *g.tris;
  ChartMesh cm;
  cm.border = border;
  const std::size_t nloc = fc.uv.size();
  cm.positions.resize(3 * nloc);
  Vec3 nsum{};
  double best_area = -1;
  Vec3 best_normal{0, 0, 1};
  for (std::size_t i = 0; i < fc.tris.size(); ++i) {
    const uint32_t t = fc.tris[i];
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = g.pos[tris[t][k]];
      const uint32_t l = fc.corner[i][k];
      cm.positions[3 * l] = p.x;
      cm.positions[3 * l + 1] = p.y;
      cm.positions[3 * l + 2] = p.z;
    }
    nsum += g.normal[t] * g.area[t];
    if (g.area[t] > best_area) {
      best_area = g.area[t];
      best_normal = g.normal[t];
    }
    cm.faces.push_back(fc.corner[i]);
  }
  const Vec3 n = length(nsum) > 1e-9 * fc.area3d ? normalize(nsum) : best_normal;
  const Vec3 helper = std::abs(n.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalize(cross(n, helper));
  const Vec3 e2 = cross(n, e1);
  cm.initial_uv.resize(2 * nloc);
  uint32_t umin = 0, umax = 0, vmin = 0, vmax = 0;
  for (uint32_t l = 0; l < nloc; ++l) {
    const Vec3 p{cm.positions[3 * l], cm.positions[3 * l + 1], cm.positions[3 * l + 2]};
    cm.initial_uv[2 * l] = dot(p, e1);
    cm.initial_uv[2 * l + 1] = dot(p, e2);
    if (cm.initial_uv[2 * l] < cm.initial_uv[2 * umin]) umin = l;
    if (cm.initial_uv[2 * l] > cm.initial_uv[2 * umax]) umax = l;
    if (cm.initial_uv[2 * l + 1] < cm.initial_uv[2 * vmin + 1]) vmin = l;
    if (cm.initial_uv[2 * l + 1] > cm.initial_uv[2 * vmax + 1]) vmax = l;
  }
  const bool use_u = cm.initial_uv[2 * umax] - cm.initial_uv[2 * umin] >=
                     cm.initial_uv[2 * vmax + 1] - cm.initial_uv[2 * vmin + 1];
  cm.fixed0 = use_u ? umin : vmin;
  cm.fixed1 = use_u ? umax : vmax;
  if (cm.fixed0 == cm.fixed1) return false;
  std::vector<double> uv;
  if (!flatten_lscm(cm, uv)) return false;
  for (uint32_t l = 0; l < nloc; ++l) fc.uv[l] = {uv[2 * l], uv[2 * l + 1]};
  return true;
}

// Do the closed segments ab and cd meet (a proper crossing, or an endpoint of
// one on the other)?
bool segments_cross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double d1 = cross2(a, b, c), d2 = cross2(a, b, d);
  const double d3 = cross2(c, d, a), d4 = cross2(c, d, b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    return true;
  }
  auto on = [](Vec2 p, Vec2 q, Vec2 r, double o) {  // r on segment pq given collinear
    return o == 0 && std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) &&
           std::min(p.y, q.y) <= r.y && r.y <= std::max(p.y, q.y);
  };
  return on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4);
}

// Uniform grid over the border segments; segments sharing a vertex are
// neighbours along the border and are not tested against each other.
bool border_crosses_itself(const FlatChart& fc, const Border& border) {
  const std::size_t m = border.size();
  if (m < 4) return false;
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& e : border) {
    for (uint32_t v : {e.first, e.second}) {
      x0 = std::min(x0, fc.uv[v].x);
      x1 = std::max(x1, fc.uv[v].x);
      y0 = std::min(y0, fc.uv[v].y);
      y1 = std::max(y1, fc.uv[v].y);
    }
  }
  const int cells = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(m))));
  const double cw = std::max((x1 - x0) / cells, 1e-300), ch = std::max((y1 - y0) / cells, 1e-300);
  auto cell_of = [&](double v, double o, double s) {
    return std::clamp(static_cast<int>((v - o) / s), 0, cells - 1);
  };
  std::vector<std::vector<uint32_t>> grid(static_cast<std::size_t>(cells) * cells);
  for (uint32_t i = 0; i < m; ++i) {
    const Vec2 a = fc.uv[border[i].first], b = fc.uv[border[i].second];
    const int cx0 = cell_of(std::min(a.x, b.x), x0, cw), cx1 = cell_of(std::max(a.x, b.x), x0, cw);
    const int cy0 = cell_of(std::min(a.y, b.y), y0, ch), cy1 = cell_of(std::max(a.y, b.y), y0, ch);
    for (int y = cy0; y <= cy1; ++y) {
      for (int x = cx0; x <= cx1; ++x) grid[static_cast<std::size_t>(y) * cells + x].push_back(i);
    }
  }
  for (const auto& cell : grid) {
    for (std::size_t i = 0; i < cell.size(); ++i) {
      for (std::size_t j = i + 1; j < cell.size(); ++j) {
        const auto& e = border[cell[i]];
        const auto& f = border[cell[j]];
        if (e.first == f.first || e.first == f.second || e.second == f.first ||
            e.second == f.second) {
          continue;
        }
        if (segments_cross(fc.uv[e.first], fc.uv[e.second], fc.uv[f.first], fc.uv[f.second])) {
          return true;
        }
      }
    }
  }
  return false;
}

// No flipped or degenerate triangle, a border that does not cross itself,
// and stretch within the limit. Rescales fc.uv so that UV area = 3D area.
bool acceptable(const Geometry& g, FlatChart& fc, const Border& border, double max_stretch) {
  double uv_area = 0;
  for (const auto& c : fc.corner) {
    const double a = 0.5 * cross2(fc.uv[c[0]], fc.uv[c[1]], fc.uv[c[2]]);
    if (!(a > 0)) return false;
    uv_area += a;
  }
  const double scale = std::sqrt(fc.area3d / uv_area);
  if (!std::isfinite(scale) || scale <= 0) return false;
  for (auto& p : fc.uv) p = {p.x * scale, p.y * scale};
  // Relative area threshold: a triangle squeezed to nothing in UV is as bad
  // as a flipped one for baking.
  const auto& tris = *g.tris;
  double stretch_sum = 0;
  for (std::size_t i = 0; i < fc.tris.size(); ++i) {
    const auto& c = fc.corner[i];
    const double a = 0.5 * cross2(fc.uv[c[0]], fc.uv[c[1]], fc.uv[c[2]]);
    if (a < 1e-6 * g.area[fc.tris[i]]) return false;
    stretch_sum += triangle_l2_squared(g, tris[fc.tris[i]], fc.uv[c[0]], fc.uv[c[1]], fc.uv[c[2]]) *
                   g.area[fc.tris[i]];
  }
  if (std::sqrt(stretch_sum / fc.area3d) > max_stretch) return false;
  if (border_crosses_itself(fc, border)) return false;
  return true;
}

}  // namespace

void flatten_triangle(const Geometry& g, FlatChart& fc) {
  const auto& t = (*g.tris)[fc.tris[0]];
  const Vec3 p0 = g.pos[t[0]], p1 = g.pos[t[1]], p2 = g.pos[t[2]];
  const double l01 = length(p1 - p0);
  const Vec3 e1 = (p1 - p0) / l01;
  const double x2 = dot(p2 - p0, e1);
  const double y2 = length(cross(e1, p2 - p0));
  fc.uv[fc.corner[0][0]] = {0, 0};
  fc.uv[fc.corner[0][1]] = {l01, 0};
  fc.uv[fc.corner[0][2]] = {x2, y2};
}

bool flatten_chart(const Geometry& g, FlatChart& fc, const Border& border, double max_stretch) {
  return pin_and_flatten(g, fc, border) && acceptable(g, fc, border, max_stretch);
}

double triangle_l2_squared(const Geometry& g, const std::array<uint32_t, 3>& t, Vec2 p1, Vec2 p2,
                           Vec2 p3) {
  const Vec3 q1 = g.pos[t[0]], q2 = g.pos[t[1]], q3 = g.pos[t[2]];
  const double a2 = cross2(p1, p2, p3);  // 2A
  const Vec3 ss = (q1 * (p2.y - p3.y) + q2 * (p3.y - p1.y) + q3 * (p1.y - p2.y)) / a2;
  const Vec3 st = (q1 * (p3.x - p2.x) + q2 * (p1.x - p3.x) + q3 * (p2.x - p1.x)) / a2;
  return 0.5 * (dot(ss, ss) + dot(st, st));
}

void orient_chart(FlatChart& fc) {
  std::vector<Vec2> pts = fc.uv;
  std::sort(pts.begin(), pts.end(),
            [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  std::vector<Vec2> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {  // Andrew's monotone chain
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross2(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  double best = std::numeric_limits<double>::infinity();
  Vec2 best_dir{1, 0};
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2 a = hull[i], b = hull[(i + 1) % hull.size()];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (!(len > 0)) continue;
    const Vec2 d{(b.x - a.x) / len, (b.y - a.y) / len};
    double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
    for (const Vec2& p : hull) {
      const double u = p.x * d.x + p.y * d.y, v = -p.x * d.y + p.y * d.x;
      u0 = std::min(u0, u);
      u1 = std::max(u1, u);
      v0 = std::min(v0, v);
      v1 = std::max(v1, v);
    }
    const double area = (u1 - u0) * (v1 - v0);
    if (area < best) {
      best = area;
      best_dir = d;
    }
  }
  double u0 = 1e300, v0 = 1e300;
  for (Vec2& p : fc.uv) {
    p = {p.x * best_dir.x + p.y * best_dir.y, -p.x * best_dir.y + p.y * best_dir.x};
    u0 = std::min(u0, p.x);
    v0 = std::min(v0, p.y);
  }
  for (Vec2& p : fc.uv) p = {p.x - u0, p.y - v0};
}

}  // namespace texbake::uv_detail
