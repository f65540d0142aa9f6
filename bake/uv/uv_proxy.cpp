#include "bake/uv/uv_proxy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "bake/util/parallel.h"
#include "mapping/image_view.h"

namespace texbake {
namespace {

// A corner closer to the proxy's axis than this fraction of its triangle's
// longest edge is treated as sitting on the singular point (pole, apex,
// disk centre): its azimuth is numerically meaningless there.
constexpr double kSingularRelative = 1e-3;
// Cut points closer than this (in u) to a corner snap onto it, so cutting
// never makes needle triangles.
constexpr double kSnapU = 1e-7;

struct Axis {
  bool periodic = false;
  Vec3 origin, dir;
};

Axis axis_of(const Proxy& proxy) {
  return std::visit(
      [](const auto& p) -> Axis {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, Sphere>) return {true, p.center, p.frame.axis};
        if constexpr (std::is_same_v<T, Cylinder>) return {true, p.base, p.frame.axis};
        if constexpr (std::is_same_v<T, Cone>) return {true, p.apex, p.frame.axis};
        if constexpr (std::is_same_v<T, Disk>) return {true, p.center, p.frame.axis};
        return {false, {}, {}};
      },
      proxy);
}

Vec3 to_vec(Float3 p) {
  return {p.x, p.y, p.z};
}

// One corner of a piece being assembled.
struct PieceCorner {
  uint32_t vertex;
  double u, v;
  Float3 normal;
  bool has_normal;
};

uint64_t uv_key(float u, float v) {
  uint32_t a, b;
  std::memcpy(&a, &u, 4);
  std::memcpy(&b, &v, 4);
  return (uint64_t{a} << 32) | b;
}

}  // namespace

Expected<ProxyUvLayout> proxy_uv_layout(const MeshData& mesh, const Proxy& proxy) {
  const std::size_t nv = mesh.vertex_count();
  const Axis axis = axis_of(proxy);

  // Per-vertex inverse mapping and distance from the axis (parallel, pure).
  std::vector<MapResult> mapped(nv);
  std::vector<double> axis_dist(nv, std::numeric_limits<double>::infinity());
  parallel_for_chunks(nv, 4096, [&](std::size_t begin, std::size_t end) {
    std::visit(
        [&](const auto& p) {
          for (std::size_t i = begin; i < end; ++i) {
            const Vec3 pos = to_vec(mesh.positions[i]);
            mapped[i] = p.inverse_map(pos);
            if (axis.periodic) {
              const Vec3 w = pos - axis.origin;
              axis_dist[i] = length(w - dot(w, axis.dir) * axis.dir);
            }
          }
        },
        proxy);
  });

  ProxyUvLayout out;
  ProxyUvStats& st = out.stats;
  MeshData& m = out.mesh;
  m.positions = mesh.positions;
  const bool with_normals = !mesh.corner_normal.empty();
  if (with_normals) m.normals = mesh.normals;

  std::unordered_map<uint64_t, uint32_t> uv_index;
  // Cut vertices keyed by (lower vertex, higher vertex, parameter from the lower).
  std::map<std::tuple<uint32_t, uint32_t, double>, uint32_t> cut_vertex;
  m.face_offsets.push_back(0);

  auto emit_triangle = [&](const PieceCorner& a, const PieceCorner& b, const PieceCorner& c) {
    const PieceCorner* cs[3] = {&a, &b, &c};
    const uint32_t base = static_cast<uint32_t>(m.face_vertices.size());
    for (const PieceCorner* pc : cs) {
      m.face_vertices.push_back(pc->vertex);
      const float fu = static_cast<float>(pc->u), fv = static_cast<float>(pc->v);
      auto [it, added] = uv_index.try_emplace(uv_key(fu, fv), static_cast<uint32_t>(m.uvs.size()));
      if (added) m.uvs.push_back({fu, fv});
      m.corner_uv.push_back(it->second);
      if (with_normals) {
        m.corner_normal.push_back(static_cast<uint32_t>(m.normals.size()));
        m.normals.push_back(pc->normal);
      }
    }
    const uint32_t face = static_cast<uint32_t>(m.face_offsets.size() - 1);
    m.face_offsets.push_back(base + 3);
    m.triangles.push_back({a.vertex, b.vertex, c.vertex});
    m.triangle_corners.push_back({base, base + 1, base + 2});
    m.triangle_face.push_back(face);
  };

  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    PieceCorner pc[3];
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = to_vec(mesh.positions[tri[k]]), b = to_vec(mesh.positions[tri[(k + 1) % 3]]);
      longest = std::max(longest, length(b - a));
    }
    bool singular[3], undefined[3];
    for (int k = 0; k < 3; ++k) {
      const MapResult& r = mapped[tri[k]];
      pc[k].vertex = tri[k];
      pc[k].u = r.uv.u;
      pc[k].v = r.uv.v;
      undefined[k] =
          r.status == MapStatus::kUndefined || !std::isfinite(r.uv.u) || !std::isfinite(r.uv.v);
      singular[k] = undefined[k] || axis_dist[tri[k]] <= kSingularRelative * longest;
      pc[k].has_normal = with_normals;
      if (with_normals) {
        const uint32_t ni = mesh.corner_normal[mesh.triangle_corners[t][k]];
        pc[k].normal = ni < mesh.normals.size() ? mesh.normals[ni] : Float3{};
      }
    }

    if (axis.periodic) {
      // Unwrap the regular corners' u onto the shortest interval.
      int reg[3], nreg = 0;
      for (int k = 0; k < 3; ++k)
        if (!singular[k]) reg[nreg++] = k;
      if (nreg >= 2) {
        std::sort(reg, reg + nreg, [&](int a, int b) { return pc[a].u < pc[b].u; });
        // Largest circular gap: after reg[g] (the gap wrapping past 1 for g = nreg-1).
        int g = nreg - 1;
        double best = pc[reg[0]].u + 1 - pc[reg[nreg - 1]].u;
        for (int i = 0; i + 1 < nreg; ++i) {
          const double gap = pc[reg[i + 1]].u - pc[reg[i]].u;
          if (gap > best) best = gap, g = i;
        }
        // Values up to and including reg[g] come after the gap: shift by +1.
        if (g != nreg - 1)
          for (int i = 0; i <= g; ++i) pc[reg[i]].u += 1;
      }
      double mean_u = 0, mean_v = 0;
      for (int i = 0; i < nreg; ++i) mean_u += pc[reg[i]].u, mean_v += pc[reg[i]].v;
      if (nreg > 0) mean_u /= nreg, mean_v /= nreg;
      for (int k = 0; k < 3; ++k) {
        if (!singular[k]) continue;
        ++st.singular_corners;
        pc[k].u = nreg > 0 ? mean_u : 0.0;
        if (undefined[k]) pc[k].v = nreg > 0 ? mean_v : 0.5;
      }
      const double lo = std::min({pc[0].u, pc[1].u, pc[2].u});
      const double hi = std::max({pc[0].u, pc[1].u, pc[2].u});
      if (hi - lo > 0.5) ++st.wide_triangles;
      if (lo >= 1) {
        for (auto& c : pc) c.u -= 1;
      }
    } else {
      for (int k = 0; k < 3; ++k) {
        if (!undefined[k]) continue;
        ++st.singular_corners;
        pc[k].u = 0.5;
        pc[k].v = 0.5;
      }
    }

    const double hi = std::max({pc[0].u, pc[1].u, pc[2].u});
    if (!axis.periodic || hi <= 1 + kSnapU) {
      if (axis.periodic)
        for (auto& c : pc) c.u = std::min(c.u, 1.0);
      emit_triangle(pc[0], pc[1], pc[2]);
      continue;
    }

    // Cut along u = 1 (Sutherland-Hodgman against both half-planes, which
    // keeps the winding). Corners within kSnapU of the line sit on it.
    ++st.cut_triangles;
    for (auto& c : pc)
      if (std::abs(c.u - 1) <= kSnapU) c.u = 1;
    std::vector<PieceCorner> left, right;
    for (int k = 0; k < 3; ++k) {
      const PieceCorner& p = pc[k];
      const PieceCorner& q = pc[(k + 1) % 3];
      if (p.u <= 1) left.push_back(p);
      if (p.u >= 1) right.push_back(p);
      if ((p.u < 1 && q.u > 1) || (p.u > 1 && q.u < 1)) {
        // The parameter is computed from the lower vertex index, so both
        // triangles of an edge compute the same bits and share the cut vertex.
        const bool p_low = p.vertex < q.vertex;
        const PieceCorner& lo_c = p_low ? p : q;
        const PieceCorner& hi_c = p_low ? q : p;
        const uint32_t lo_v = lo_c.vertex, hi_v = hi_c.vertex;
        const double s_low = (1 - lo_c.u) / (hi_c.u - lo_c.u);
        const double s = p_low ? s_low : 1 - s_low;
        auto [it, added] = cut_vertex.try_emplace({lo_v, hi_v, s_low}, 0u);
        if (added) {
          const Vec3 a = to_vec(mesh.positions[lo_v]), b = to_vec(mesh.positions[hi_v]);
          const Vec3 x = a + s_low * (b - a);
          it->second = static_cast<uint32_t>(m.positions.size());
          m.positions.push_back(
              {static_cast<float>(x.x), static_cast<float>(x.y), static_cast<float>(x.z)});
          ++st.added_vertices;
        }
        PieceCorner x;
        x.vertex = it->second;
        x.u = 1;
        x.v = p.v + s * (q.v - p.v);
        x.has_normal = with_normals;
        if (with_normals) {
          const Vec3 n = to_vec(p.normal) + s * (to_vec(q.normal) - to_vec(p.normal));
          const double len = length(n);
          const Vec3 nn = len > 0 ? n / len : n;
          x.normal = {static_cast<float>(nn.x), static_cast<float>(nn.y), static_cast<float>(nn.z)};
        }
        left.push_back(x);
        right.push_back(x);
      }
    }
    for (auto& c : right) c.u -= 1;
    for (const auto* piece : {&left, &right}) {
      for (std::size_t i = 1; i + 1 < piece->size(); ++i) {
        emit_triangle((*piece)[0], (*piece)[i], (*piece)[i + 1]);
      }
    }
  }

  // Rescale into [0, 1] if the mesh leaves the proxy's domain.
  float lo_u = 0, hi_u = 1, lo_v = 0, hi_v = 1;
  for (const Float2& q : m.uvs) {
    lo_u = std::min(lo_u, q.u), hi_u = std::max(hi_u, q.u);
    lo_v = std::min(lo_v, q.v), hi_v = std::max(hi_v, q.v);
  }
  if (lo_u < 0 || hi_u > 1 || lo_v < 0 || hi_v > 1) {
    st.rescaled = true;
    for (Float2& q : m.uvs) {
      if (!axis.periodic) q.u = std::clamp((q.u - lo_u) / (hi_u - lo_u), 0.f, 1.f);
      q.v = std::clamp((q.v - lo_v) / (hi_v - lo_v), 0.f, 1.f);
    }
  }
  return out;
}

MeshUvCheck check_mesh_uvs(const MeshData& mesh, int size) {
  MeshUvCheck check;
  for (uint32_t c = 0; c < mesh.corner_uv.size(); ++c) {
    const uint32_t i = mesh.corner_uv[c];
    if (i >= mesh.uvs.size()) continue;
    const Float2 q = mesh.uvs[i];
    if (!(q.u >= 0 && q.u <= 1 && q.v >= 0 && q.v <= 1)) ++check.corners_outside;
  }
  // Count, per texel, the triangles whose interior holds the texel centre
  // (strictly: a centre on an edge shared by two neighbours is no overlap).
  std::vector<uint8_t> count(static_cast<std::size_t>(size) * size, 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    double px[3], py[3];
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const uint32_t corner = mesh.triangle_corners[t][k];
      if (corner >= mesh.corner_uv.size() || mesh.corner_uv[corner] >= mesh.uvs.size()) {
        ok = false;
        break;
      }
      const Float2 q = mesh.uvs[mesh.corner_uv[corner]];
      const PixelPos pp = pixel_from_uv(UV{q.u, q.v}, size, size);
      px[k] = pp.x;
      py[k] = pp.y;
    }
    if (!ok) continue;
    const double area2 = (px[1] - px[0]) * (py[2] - py[0]) - (py[1] - py[0]) * (px[2] - px[0]);
    if (!(std::abs(area2) > 0)) continue;
    const double sgn = area2 > 0 ? 1 : -1;
    const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({px[0], px[1], px[2]}))));
    const int x1 =
        std::min(size - 1, static_cast<int>(std::floor(std::max({px[0], px[1], px[2]}))));
    const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({py[0], py[1], py[2]}))));
    const int y1 =
        std::min(size - 1, static_cast<int>(std::floor(std::max({py[0], py[1], py[2]}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k) {
          const int j = (k + 1) % 3;
          const double e = (px[j] - px[k]) * (y - py[k]) - (py[j] - py[k]) * (x - px[k]);
          inside = sgn * e > 0;
        }
        if (!inside) continue;
        uint8_t& c = count[static_cast<std::size_t>(y) * size + x];
        if (c < 255) ++c;
      }
    }
  }
  for (uint8_t c : count) {
    check.covered_texels += c >= 1;
    check.overlap_texels += c >= 2;
  }
  return check;
}

}  // namespace texbake
