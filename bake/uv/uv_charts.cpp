// Stage 1 of `--uv generate` (see uv_generate_internal.h): mesh geometry and
// adjacency, then charts by normal-cone region growing, smoothed borders and
// small charts merged into a neighbour.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

#include "bake/util/parallel.h"
#include "bake/uv/uv_generate_internal.h"

namespace texbake::uv_detail {
namespace {

// Chart growing: normal-cone region growing, seeds in triangle order,
// frontier ordered by normal deviation from the chart's mean normal.

std::vector<uint32_t> grow_charts(const Geometry& g, double cos_max, uint32_t& chart_count) {
  const std::size_t n = g.area.size();
  std::vector<uint32_t> chart(n, kNone);
  using Item = std::pair<double, uint32_t>;  // (deviation, triangle): min-heap
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> frontier;
  uint32_t count = 0;
  for (uint32_t seed = 0; seed < n; ++seed) {
    if (chart[seed] != kNone) continue;
    const uint32_t c = count++;
    chart[seed] = c;
    Vec3 sum = g.normal[seed] * g.area[seed];
    Vec3 mean = g.normal[seed];
    auto push_neighbours = [&](uint32_t t) {
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = g.adj[3 * t + k];
        if (a == kNone || chart[a / 3] != kNone) continue;
        frontier.push({1.0 - dot(g.normal[a / 3], mean), a / 3});
      }
    };
    push_neighbours(seed);
    while (!frontier.empty()) {
      const uint32_t t = frontier.top().second;
      frontier.pop();
      if (chart[t] != kNone) continue;
      if (dot(g.normal[t], mean) < cos_max) continue;
      chart[t] = c;
      sum += g.normal[t] * g.area[t];
      const double len = length(sum);
      if (len > 0) mean = sum / len;
      push_neighbours(t);
    }
  }
  chart_count = count;
  return chart;
}

// Region growing on a scanned surface leaves saw-toothed chart borders (a
// triangle whose normal is off by noise joins the neighbour chart), and every
// tooth costs gutter texels. A triangle with two or three neighbours in one
// other chart moves there when its normal stays within `cos_max` of that
// chart's mean normal. Sequential passes in triangle order (deterministic).
void smooth_chart_borders(const Geometry& g, std::vector<uint32_t>& chart, uint32_t chart_count,
                          double cos_max, int passes) {
  const std::size_t n = chart.size();
  std::vector<Vec3> mean(chart_count);
  for (std::size_t t = 0; t < n; ++t) mean[chart[t]] += g.normal[t] * g.area[t];
  for (Vec3& m : mean) m = length(m) > 0 ? normalize(m) : m;
  for (int pass = 0; pass < passes; ++pass) {
    std::size_t moved = 0;
    for (std::size_t t = 0; t < n; ++t) {
      uint32_t nb[3];
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = g.adj[3 * t + k];
        nb[k] = a == kNone ? kNone : chart[a / 3];
      }
      uint32_t target = kNone;
      if (nb[0] != kNone && nb[0] == nb[1])
        target = nb[0];
      else if (nb[0] != kNone && nb[0] == nb[2])
        target = nb[0];
      else if (nb[1] != kNone && nb[1] == nb[2])
        target = nb[1];
      if (target == kNone || target == chart[t]) continue;
      if (dot(g.normal[t], mean[target]) < cos_max) continue;
      chart[t] = target;
      ++moved;
    }
    if (moved == 0) break;
  }
}

// Merges charts smaller than min_area into the neighbouring chart with which
// they share the longest border (lengths summed in 3D), smallest charts first.
void merge_small_charts(const Geometry& g, std::vector<uint32_t>& chart, uint32_t& chart_count,
                        double min_area) {
  const std::size_t n = chart.size();
  std::vector<double> chart_area(chart_count, 0.0);
  for (std::size_t t = 0; t < n; ++t) chart_area[chart[t]] += g.area[t];
  std::vector<std::vector<uint32_t>> members(chart_count);
  for (uint32_t t = 0; t < n; ++t) members[chart[t]].push_back(t);
  std::vector<uint32_t> order(chart_count);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return chart_area[a] < chart_area[b]; });
  std::vector<uint32_t> target(chart_count);  // union-find over merged charts
  std::iota(target.begin(), target.end(), 0u);
  auto find = [&](uint32_t c) {
    while (target[c] != c) c = target[c] = target[target[c]];
    return c;
  };
  const auto& tris = *g.tris;
  for (uint32_t c : order) {
    if (find(c) != c || chart_area[c] >= min_area) continue;
    // Shared border length per neighbouring chart (few neighbours: linear list).
    std::vector<std::pair<uint32_t, double>> shared;
    for (uint32_t t : members[c]) {
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = g.adj[3 * t + k];
        if (a == kNone) continue;
        const uint32_t d = find(chart[a / 3]);
        if (d == c) continue;
        const double len = length(g.pos[tris[t][k]] - g.pos[tris[t][(k + 1) % 3]]);
        auto it = std::find_if(shared.begin(), shared.end(), [&](auto& s) { return s.first == d; });
        if (it == shared.end())
          shared.push_back({d, len});
        else
          it->second += len;
      }
    }
    if (shared.empty()) continue;
    auto best = shared.begin();
    for (auto it = shared.begin(); it != shared.end(); ++it) {
      if (it->second > best->second || (it->second == best->second && it->first < best->first)) {
        best = it;
      }
    }
    const uint32_t d = best->first;
    target[c] = d;
    chart_area[d] += chart_area[c];
    members[d].insert(members[d].end(), members[c].begin(), members[c].end());
    members[c].clear();
    members[c].shrink_to_fit();
  }
  // Renumber surviving charts in order of their smallest triangle.
  std::vector<uint32_t> renum(chart_count, kNone);
  uint32_t count = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const uint32_t r = find(chart[t]);
    if (renum[r] == kNone) renum[r] = count++;
    chart[t] = renum[r];
  }
  chart_count = count;
}

}  // namespace

Geometry build_geometry(const MeshData& mesh) {
  Geometry g;
  g.tris = &mesh.triangles;
  const auto& tris = mesh.triangles;
  const std::size_t n = tris.size();
  g.pos.resize(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    g.pos[i] = {mesh.positions[i].x, mesh.positions[i].y, mesh.positions[i].z};
  }
  g.normal.resize(n);
  g.area.resize(n);
  g.centroid.resize(n);
  parallel_for_chunks(n, 4096, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t) {
      const Vec3 p0 = g.pos[tris[t][0]], p1 = g.pos[tris[t][1]], p2 = g.pos[tris[t][2]];
      const Vec3 c = cross(p1 - p0, p2 - p0);
      const double len = length(c);
      g.area[t] = 0.5 * len;
      g.normal[t] = len > 0 ? c / len : Vec3{};
      g.centroid[t] = (p0 + p1 + p2) / 3.0;
    }
  });

  // Edges bucketed by their smaller vertex (counting sort, O(n)).
  const std::size_t nv = mesh.positions.size();
  std::vector<uint32_t> offsets(nv + 1, 0);
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) ++offsets[std::min(t[k], t[(k + 1) % 3]) + 1];
  }
  for (std::size_t i = 0; i < nv; ++i) offsets[i + 1] += offsets[i];
  std::vector<uint32_t> entries(3 * n);
  {
    std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t t = 0; t < n; ++t) {
      for (int k = 0; k < 3; ++k) {
        const uint32_t lo = std::min(tris[t][k], tris[t][(k + 1) % 3]);
        entries[fill[lo]++] = static_cast<uint32_t>(3 * t + k);
      }
    }
  }
  g.adj.assign(3 * n, kNone);
  auto other = [&](uint32_t ce) {
    const auto& t = tris[ce / 3];
    const uint32_t a = t[ce % 3], b = t[(ce % 3 + 1) % 3];
    return std::max(a, b);
  };
  auto forward = [&](uint32_t ce) {
    const auto& t = tris[ce / 3];
    return t[ce % 3] < t[(ce % 3 + 1) % 3];
  };
  parallel_for_chunks(nv, 8192, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      for (uint32_t i = offsets[v]; i < offsets[v + 1]; ++i) {
        const uint32_t hi = other(entries[i]);
        uint32_t count = 0, mate = kNone;
        for (uint32_t j = offsets[v]; j < offsets[v + 1]; ++j) {
          if (j == i || other(entries[j]) != hi) continue;
          ++count;
          mate = entries[j];
        }
        if (count == 1 && forward(mate) != forward(entries[i])) g.adj[entries[i]] = mate;
      }
    }
  });
  return g;
}

std::vector<uint32_t> make_charts(const Geometry& g, double max_angle_deg, double min_area,
                                  uint32_t& chart_count) {
  std::vector<uint32_t> chart = grow_charts(g, std::cos(max_angle_deg * M_PI / 180.0), chart_count);
  smooth_chart_borders(g, chart, chart_count,
                       std::cos(std::min(89.0, max_angle_deg + 15.0) * M_PI / 180.0), 4);
  merge_small_charts(g, chart, chart_count, min_area);
  return chart;
}

}  // namespace texbake::uv_detail
