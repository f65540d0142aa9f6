// `--uv generate` (see uv_generate.h): input checks, the four stages of
// uv_generate_internal.h in order, the search for the largest scale whose
// pack fits the atlas, and the atlas' UVs and metrics.
//
// Hand-written rather than a library: Debian ships no UV atlas library
// (xatlas, UVAtlas are not packaged). The flattening is solved with Eigen
// (uv_flatten.cpp); CGAL is used only by bake/fit/.
#include "bake/uv/uv_generate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "bake/util/parallel.h"
#include "bake/uv/uv_generate_internal.h"
#include "mesh_io/image_io.h"

namespace texbake {
namespace {

using uv_detail::ChartRaster;
using uv_detail::cross2;
using uv_detail::FlatChart;
using uv_detail::Geometry;
using uv_detail::Placement;
using uv_detail::Vec2;

// The kInvalidArgument errors of generate_uv_atlas (uv_generate.h) that need
// no geometry: options out of range, no triangles, bad indices or positions.
Status validate(const MeshData& mesh, const UvGenerateOptions& o) {
  auto bad = [](std::string m) {
    return Status(make_error(ErrorCode::kInvalidArgument, std::move(m)));
  };
  if (o.atlas_size < 1 || o.atlas_size > kMaxAtlasSize) {
    return bad("atlas size " + std::to_string(o.atlas_size) + " is outside 1..16384");
  }
  if (o.padding < 0) return bad("padding " + std::to_string(o.padding) + " is negative");
  if (!(o.max_chart_angle_deg > 0 && o.max_chart_angle_deg < 90)) {
    return bad("chart normal-cone angle must be in (0, 90) degrees");
  }
  if (!(o.max_chart_stretch >= 1)) return bad("maximum chart stretch must be at least 1");
  if (mesh.triangles.empty()) return bad("the mesh has no triangles to lay out");
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Float3 p = mesh.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return bad("vertex " + std::to_string(i) + " has a non-finite coordinate");
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (uint32_t v : mesh.triangles[t]) {
      if (v >= mesh.positions.size()) {
        return bad("triangle " + std::to_string(t) + " refers to vertex " + std::to_string(v) +
                   " of " + std::to_string(mesh.positions.size()));
      }
    }
  }
  return ok_status();
}

}  // namespace

Expected<UvAtlas> generate_uv_atlas(const MeshData& mesh, const UvGenerateOptions& options) {
  if (Status st = validate(mesh, options); !st) return st.error();
  const Geometry g = uv_detail::build_geometry(mesh);
  const std::size_t n = mesh.triangles.size();
  double total_area = 0;
  for (double a : g.area) total_area += a;
  if (!(total_area > 0)) {
    return make_error(ErrorCode::kInvalidArgument, "the mesh's triangles have zero total area");
  }

  // 1. Charts. Charts below ~1/2000 of the surface cost more gutter than they
  // save stretch.
  uint32_t chart_count = 0;
  const std::vector<uint32_t> chart =
      uv_detail::make_charts(g, options.max_chart_angle_deg, total_area * 5e-4, chart_count);

  // 2. Cut into disks and flatten.
  const std::vector<FlatChart> charts =
      uv_detail::cut_charts(g, chart, chart_count, options.max_chart_stretch);

  // 3. Pack at the largest global scale (texels per unit length) that fits.
  const int size = options.atlas_size;
  const int padding = options.padding;
  double max_extent = 0;
  for (const FlatChart& fc : charts) {
    for (const Vec2& p : fc.uv) max_extent = std::max({max_extent, p.x, p.y});
  }
  std::vector<uint32_t> order(charts.size());
  std::iota(order.begin(), order.end(), 0u);
  std::vector<double> box_area(charts.size());
  for (std::size_t i = 0; i < charts.size(); ++i) {
    double x = 0, y = 0;
    for (const Vec2& p : charts[i].uv) x = std::max(x, p.x), y = std::max(y, p.y);
    box_area[i] = x * y;
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return box_area[a] > box_area[b]; });

  std::vector<ChartRaster> rasters(charts.size());
  std::vector<Placement> placement, best_placement;
  // The best pack so far is kept by swapping (every round overwrites all of
  // `rasters` and `placement`), not by copying the bitmaps.
  std::vector<ChartRaster> best_rasters(charts.size());
  double best_scale = 0;
  // Scale search. A pack into a strip of the atlas' width reports the height
  // it needs; at a fixed width that height grows about as scale^2, so the
  // next scale is scale * sqrt(size / height), kept strictly inside the
  // bracket [largest scale that fitted, smallest that did not]. This needs
  // 3-5 packs where bisection from a blind start needed 8-10. A pack that
  // overflows the strip by more than kOverflow stops early.
  constexpr double kOverflow = 1.3;
  const int max_height = static_cast<int>(std::min<double>(kOverflow * size, 4.0 * kMaxAtlasSize));
  double lo = 0, hi = std::numeric_limits<double>::infinity();
  // Start: charts covering about 70 % of the atlas (UV area = 3D area).
  double scale = std::sqrt(0.7 * size * static_cast<double>(size) / total_area);
  if (max_extent > 0) scale = std::min(scale, (size - 1) / max_extent);
  int probes = 0;
  for (int round = 0; round < 40; ++round) {
    parallel_for_chunks(charts.size(), 8, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) rasters[i] = uv_detail::rasterize_chart(charts[i], scale);
    });
    const int used = uv_detail::pack(rasters, order, size, padding, max_height, placement);
    if (used >= 0 && used <= size) {
      lo = scale;
      best_scale = scale;
      best_placement.swap(placement);
      best_rasters.swap(rasters);
    } else {
      hi = scale;
    }
    if (lo > 0 && round >= 5) break;
    // The packed height is not monotonic in the scale (a slightly larger
    // chart can land in a better hole), so once the bracket is tight a few
    // probes just above the best fitting scale are still worth a pack.
    if (hi / lo < 1.005) {
      if (probes == 2) break;
      scale = lo * (1.0 + 0.004 * ++probes);
      continue;
    }
    double next =
        used > 0 ? scale * std::sqrt(static_cast<double>(size) / used) : scale / kOverflow;
    if (used > 0 && used <= size) next *= 1.002;  // a pack that fits exactly: still try a bit more
    if (lo > 0 && hi < std::numeric_limits<double>::infinity()) {
      // Inside the bracket, at least a quarter of the way from either end.
      const double a = lo + 0.25 * (hi - lo), c = hi - 0.25 * (hi - lo);
      next = std::clamp(next, a, c);
    } else if (next <= lo) {
      next = lo * 1.01;
    } else if (next >= hi) {
      next = hi / 1.01;
    }
    if (max_extent > 0 && next * max_extent > size - 1) {
      if (lo >= (size - 1) / max_extent) break;
      next = (size - 1) / max_extent;
    }
    scale = next;
  }
  if (lo == 0) {
    return make_error(ErrorCode::kUnsupported, "cannot pack " + std::to_string(charts.size()) +
                                                   " charts into a " + std::to_string(size) +
                                                   " texel atlas with a " +
                                                   std::to_string(padding) + " texel gutter");
  }

  // 4. Output.
  UvAtlas atlas;
  atlas.atlas_size = size;
  atlas.padding = padding;
  atlas.chart_count = static_cast<uint32_t>(charts.size());
  atlas.texels_per_unit = best_scale;
  atlas.triangle_uvs.resize(n);
  atlas.triangle_chart.resize(n);
  std::size_t covered = 0;
  double stretch_sum = 0, uv_area = 0;
  const double inv = 1.0 / size;
  for (std::size_t ci = 0; ci < charts.size(); ++ci) {
    const FlatChart& fc = charts[ci];
    const ChartRaster& r = best_rasters[ci];
    const Placement& pl = best_placement[ci];
    covered += r.covered;
    const uint32_t base = static_cast<uint32_t>(atlas.uvs.size());
    for (const Vec2& p : fc.uv) {
      const Vec2 t = uv_detail::placed_texel(r, pl, best_scale, p);
      atlas.uvs.push_back({static_cast<float>(std::clamp(t.x * inv, 0.0, 1.0)),
                           static_cast<float>(std::clamp(t.y * inv, 0.0, 1.0))});
    }
    for (std::size_t i = 0; i < fc.tris.size(); ++i) {
      const uint32_t t = fc.tris[i];
      atlas.triangle_chart[t] = static_cast<uint32_t>(ci);
      atlas.triangle_uvs[t] = {base + fc.corner[i][0], base + fc.corner[i][1],
                               base + fc.corner[i][2]};
    }
  }
  // Stretch on the final (float) UVs, as a consumer sees them.
  for (std::size_t t = 0; t < n; ++t) {
    const auto& c = atlas.triangle_uvs[t];
    const Vec2 p1{atlas.uvs[c[0]].u, atlas.uvs[c[0]].v}, p2{atlas.uvs[c[1]].u, atlas.uvs[c[1]].v},
        p3{atlas.uvs[c[2]].u, atlas.uvs[c[2]].v};
    const double a = 0.5 * cross2(p1, p2, p3);
    if (!(a > 0)) continue;  // cannot happen for valid charts; keeps the sum finite
    uv_area += a;
    stretch_sum += uv_detail::triangle_l2_squared(g, mesh.triangles[t], p1, p2, p3) * g.area[t];
  }
  atlas.stretch_l2 = std::sqrt(stretch_sum / total_area) * std::sqrt(uv_area / total_area);
  atlas.utilisation = static_cast<double>(covered) / (static_cast<double>(size) * size);
  return atlas;
}

}  // namespace texbake
