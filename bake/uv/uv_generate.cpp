// `--uv generate`: chart growing, chart cutting, packing (see uv_generate.h).
// Plain C++ and bake/parallel.h; the LSCM solve (Eigen) lives in
// uv_generate_flatten.cpp.
//
// Hand-written rather than a library: Debian ships no UV atlas library
// (xatlas, UVAtlas are not packaged). CGAL's LSCM parameterizer was used for
// the flattening until it proved the bottleneck; the same energy is now
// solved directly with Eigen's sparse Cholesky (see uv_generate_flatten.cpp).
#include "bake/uv/uv_generate.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <string>

#include "bake/util/parallel.h"
#include "bake/uv/uv_generate_internal.h"
#include "mapping/vec.h"

namespace texbake {
namespace {

using uv_detail::ChartMesh;
using uv_detail::FlattenStatus;

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
constexpr int kMaxAtlasSize = 16384;
// Pieces above this are halved before any solve. On the 832k-triangle
// armadillo every piece of more than ~47k triangles failed the stretch check
// after its solve (the solves thrown away were 1.5x the triangles kept), so a
// lower cap skips those wasted solves without changing the atlas there.
constexpr std::size_t kMaxSolveTriangles = 49152;
// Split pieces at least this large have their halves processed in parallel.
constexpr std::size_t kParallelSplitTriangles = 8192;

struct Vec2 {
  double x = 0, y = 0;
};

double cross2(Vec2 a, Vec2 b, Vec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// ---------------------------------------------------------------------------
// Mesh geometry and adjacency.

struct Geometry {
  const std::vector<std::array<uint32_t, 3>>* tris = nullptr;
  std::vector<Vec3> pos;
  std::vector<Vec3> normal;  // unit face normal (zero for a triangle degenerate in double)
  std::vector<double> area;
  std::vector<Vec3> centroid;
  // adj[3t+k]: corner-edge 3t'+k' across edge k of t (vertices v[k] -> v[k+1]),
  // or kNone when that edge is a border, non-manifold (not exactly two
  // triangles) or shared by two triangles of opposite winding.
  std::vector<uint32_t> adj;
};

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

// ---------------------------------------------------------------------------
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

// ---------------------------------------------------------------------------
// Cutting and flattening.

struct FlatChart {
  std::vector<uint32_t> tris;                   // global triangle ids
  std::vector<std::array<uint32_t, 3>> corner;  // local vertex per corner
  std::vector<Vec2> uv;                         // per local vertex, in 3D length units
  double area3d = 0;
};

// Scratch shared by all chart tasks: each task touches only the entries of
// its own piece's triangles (pieces are disjoint), so no two threads write
// the same element. Halves of a split piece are processed in parallel, so a
// task may read the stamp of a neighbouring triangle that another task is
// writing: stamps are accessed atomically (relaxed) and every marking takes
// a fresh value from `next_stamp`, so a stamp never matches another task's.
struct Scratch {
  std::vector<uint32_t> stamp;  // per triangle: membership of the current piece
  std::atomic<uint32_t> next_stamp{0};
  std::vector<uint32_t> parent;  // per corner: union-find welding corners into vertices
  std::vector<uint32_t> local;   // per corner root: local vertex index
};

class ChartCutter {
 public:
  ChartCutter(const Geometry& g, const std::vector<uint32_t>& chart, Scratch& s, double max_stretch)
      : g_(g), chart_(chart), s_(s), max_stretch_(max_stretch) {}

  // Flattens all triangles of chart c (given as `tris`) into one or more
  // flat charts appended to out.
  void run(uint32_t c, std::vector<uint32_t> tris, std::vector<FlatChart>& out) {
    chart_id_ = c;
    process(std::move(tris), out);
  }

 private:
  uint32_t stamp_of(uint32_t t) const {
    return std::atomic_ref<uint32_t>(s_.stamp[t]).load(std::memory_order_relaxed);
  }
  void set_stamp(uint32_t t, uint32_t v) {
    std::atomic_ref<uint32_t>(s_.stamp[t]).store(v, std::memory_order_relaxed);
  }
  uint32_t fresh_stamp() { return stamp_ = s_.next_stamp.fetch_add(1) + 1; }

  bool in_piece(uint32_t t) const { return chart_[t] == chart_id_ && stamp_of(t) == stamp_; }

  void mark(const std::vector<uint32_t>& tris) {
    fresh_stamp();
    for (uint32_t t : tris) set_stamp(t, stamp_);
  }

  // Connected components of tris over in-piece adjacency.
  std::vector<std::vector<uint32_t>> components(const std::vector<uint32_t>& tris) {
    mark(tris);
    const uint32_t piece = stamp_;
    const uint32_t seen = fresh_stamp();
    std::vector<std::vector<uint32_t>> comps;
    std::vector<uint32_t> stack;
    for (uint32_t seed : tris) {
      if (stamp_of(seed) != piece) continue;
      comps.emplace_back();
      set_stamp(seed, seen);
      stack.push_back(seed);
      while (!stack.empty()) {
        const uint32_t t = stack.back();
        stack.pop_back();
        comps.back().push_back(t);
        for (int k = 0; k < 3; ++k) {
          const uint32_t a = g_.adj[3 * t + k];
          if (a == kNone || chart_[a / 3] != chart_id_ || stamp_of(a / 3) != piece) continue;
          set_stamp(a / 3, seen);
          stack.push_back(a / 3);
        }
      }
      std::sort(comps.back().begin(), comps.back().end());
    }
    return comps;
  }

  void process(std::vector<uint32_t> tris, std::vector<FlatChart>& out) {
    for (auto& comp : components(tris)) flatten_or_split(std::move(comp), out);
  }

  uint32_t find(uint32_t c) {
    while (s_.parent[c] != c) c = s_.parent[c] = s_.parent[s_.parent[c]];
    return c;
  }

  // Welds the corners of a connected piece into local vertices.
  // Edges listed in `cuts` (sorted corner-edge ids 3t+k, both sides) are not
  // welded: they become border.
  bool interior(uint32_t ce, const std::vector<uint32_t>& cuts) const {
    const uint32_t a = g_.adj[ce];
    return a != kNone && in_piece(a / 3) && !std::binary_search(cuts.begin(), cuts.end(), ce);
  }

  FlatChart weld(const std::vector<uint32_t>& tris,
                 std::vector<std::pair<uint32_t, uint32_t>>& border,
                 const std::vector<uint32_t>& cuts) {
    mark(tris);
    for (uint32_t t : tris) {
      for (int k = 0; k < 3; ++k) s_.parent[3 * t + k] = 3 * t + k;
    }
    for (uint32_t t : tris) {
      for (int k = 0; k < 3; ++k) {
        if (!interior(3 * t + k, cuts)) continue;
        const uint32_t a = g_.adj[3 * t + k];
        const uint32_t t2 = a / 3, k2 = a % 3;
        auto unite = [&](uint32_t x, uint32_t y) {
          x = find(x);
          y = find(y);
          if (x != y) s_.parent[std::max(x, y)] = std::min(x, y);
        };
        unite(3 * t + k, 3 * t2 + (k2 + 1) % 3);
        unite(3 * t + (k + 1) % 3, 3 * t2 + k2);
      }
    }
    FlatChart fc;
    fc.tris = tris;
    fc.corner.resize(tris.size());
    for (uint32_t t : tris) {
      for (int k = 0; k < 3; ++k) s_.local[3 * t + k] = kNone;
    }
    uint32_t nloc = 0;
    for (std::size_t i = 0; i < tris.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const uint32_t r = find(3 * tris[i] + k);
        if (s_.local[r] == kNone) s_.local[r] = nloc++;
        fc.corner[i][k] = s_.local[r];
      }
      fc.area3d += g_.area[tris[i]];
    }
    fc.uv.resize(nloc);
    border.clear();
    for (std::size_t i = 0; i < tris.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        if (!interior(3 * tris[i] + k, cuts)) {
          border.push_back({fc.corner[i][k], fc.corner[i][(k + 1) % 3]});
        }
      }
    }
    return fc;
  }

  void flatten_or_split(std::vector<uint32_t> tris, std::vector<FlatChart>& out) {
    // The sparse solve grows faster than linearly with the chart and a failed
    // check would waste it: very large charts are halved before anything else
    // (welding and cutting them first would be thrown away too).
    if (tris.size() > kMaxSolveTriangles) {
      auto [a, b] = split(tris);
      process_halves(std::move(a), std::move(b), out);
      return;
    }
    std::vector<std::pair<uint32_t, uint32_t>> border;
    std::vector<uint32_t> cuts;
    FlatChart fc = weld(tris, border, cuts);
    // A chart with holes (genus 0, several border loops) becomes a disk by
    // cutting along shortest paths between its loops; other non-disks are split.
    // The welded piece is vertex-manifold by construction (corners are welded
    // only across interior edges), so it is a disk iff it has Euler
    // characteristic 1 and one border loop.
    bool disk = false;
    for (int i = 0; i < 16; ++i) {
      std::vector<uint32_t> loop;
      const int loops = border_loops(fc, border, loop);
      const long edges =
          (3 * static_cast<long>(tris.size()) + static_cast<long>(border.size())) / 2;
      const long euler = static_cast<long>(fc.uv.size()) - edges + static_cast<long>(tris.size());
      if (loops == 1 && euler == 1) {
        disk = true;
        break;
      }
      if (loops <= 1 || euler != 2 - loops || !cut_between_loops(fc, tris, border, loop, cuts))
        break;
      fc = weld(tris, border, cuts);
    }
    if (tris.size() == 1) {
      flatten_single(fc);
      out.push_back(std::move(fc));
      return;
    }
    if (disk && flatten(fc, border) && valid(fc, border)) {
      out.push_back(std::move(fc));
      return;
    }
    auto [a, b] = split(tris);
    process_halves(std::move(a), std::move(b), out);
  }

  // The two halves of a split piece are disjoint: large ones are processed
  // in parallel (a chart of 200k triangles would otherwise be one serial task
  // that ends the chart loop alone), each into its own list, appended in
  // order, so the result does not depend on the thread count.
  void process_halves(std::vector<uint32_t> a, std::vector<uint32_t> b,
                      std::vector<FlatChart>& out) {
    if (a.size() + b.size() < kParallelSplitTriangles) {
      process(std::move(a), out);
      process(std::move(b), out);
      return;
    }
    std::vector<FlatChart> half[2];
    std::vector<uint32_t>* tris[2] = {&a, &b};
    parallel_for_chunks(2, 1, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) {
        ChartCutter sub(g_, chart_, s_, max_stretch_);
        sub.chart_id_ = chart_id_;
        sub.process(std::move(*tris[i]), half[i]);
      }
    });
    for (auto& h : half) {
      for (FlatChart& fc : h) out.push_back(std::move(fc));
    }
  }

  // Labels border vertices with their loop (kNone inside); returns the loop
  // count, or -1 when a vertex starts two border edges (not a manifold disk).
  static int border_loops(const FlatChart& fc,
                          const std::vector<std::pair<uint32_t, uint32_t>>& border,
                          std::vector<uint32_t>& loop) {
    std::vector<uint32_t> next(fc.uv.size(), kNone);
    for (const auto& [a, b] : border) {
      if (next[a] != kNone) return -1;
      next[a] = b;
    }
    loop.assign(fc.uv.size(), kNone);
    int loops = 0;
    for (const auto& e : border) {
      if (loop[e.first] != kNone) continue;
      for (uint32_t v = e.first; v != kNone && loop[v] == kNone; v = next[v]) loop[v] = loops;
      ++loops;
    }
    return loops;
  }

  // Adds to `cuts` the interior edges of shortest paths (3D length) that join
  // every border loop to the longest one, in one Dijkstra run grown like
  // Prim's tree: when the search reaches a new loop, the path to it and that
  // loop become sources at distance 0 and the search goes on (a
  // label-correcting search, so distances lowered later are re-propagated).
  // One run and one re-weld replace a run and a re-weld per hole. Returns
  // false if no loop could be reached.
  bool cut_between_loops(const FlatChart& fc, const std::vector<uint32_t>& tris,
                         const std::vector<std::pair<uint32_t, uint32_t>>& border,
                         const std::vector<uint32_t>& loop, std::vector<uint32_t>& cuts) {
    const std::size_t nv = fc.uv.size();
    std::vector<uint32_t> loop_size;
    for (uint32_t l : loop) {
      if (l == kNone) continue;
      if (l >= loop_size.size()) loop_size.resize(l + 1, 0);
      ++loop_size[l];
    }
    const uint32_t outer = static_cast<uint32_t>(
        std::max_element(loop_size.begin(), loop_size.end()) - loop_size.begin());
    // Interior edges as a CSR graph over local vertices: (neighbour, corner-edge).
    std::vector<uint32_t> offset(nv + 1, 0);
    for (std::size_t i = 0; i < tris.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        if (interior(3 * tris[i] + k, cuts)) ++offset[fc.corner[i][k] + 1];
      }
    }
    for (std::size_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
    std::vector<std::pair<uint32_t, uint32_t>> links(offset[nv]);
    {
      std::vector<uint32_t> fill(offset.begin(), offset.end() - 1);
      for (std::size_t i = 0; i < tris.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
          if (!interior(3 * tris[i] + k, cuts)) continue;
          links[fill[fc.corner[i][k]]++] = {fc.corner[i][(k + 1) % 3], 3 * tris[i] + k};
        }
      }
    }
    std::vector<double> dist(nv, std::numeric_limits<double>::infinity());
    std::vector<uint32_t> via(nv, kNone);  // corner-edge reaching the vertex
    std::vector<uint8_t> joined(loop_size.size(), 0);
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    auto make_source = [&](uint32_t v) {
      dist[v] = 0;
      via[v] = kNone;
      queue.push({0.0, v});
    };
    auto join_loop = [&](uint32_t l) {
      joined[l] = 1;
      for (uint32_t v = 0; v < nv; ++v) {
        if (loop[v] == l) make_source(v);
      }
    };
    join_loop(outer);
    bool any = false;
    const auto& tv = *g_.tris;
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > dist[v]) continue;
      if (loop[v] != kNone && !joined[loop[v]]) {
        std::vector<uint32_t> path;
        for (uint32_t u = v; via[u] != kNone;) {
          const uint32_t ce = via[u];
          cuts.push_back(ce);
          cuts.push_back(g_.adj[ce]);
          // Step back to the edge's start vertex.
          const uint32_t i = static_cast<uint32_t>(
              std::lower_bound(tris.begin(), tris.end(), ce / 3) - tris.begin());
          u = fc.corner[i][ce % 3];
          path.push_back(u);
        }
        any = true;
        join_loop(loop[v]);
        for (uint32_t u : path) make_source(u);
        continue;
      }
      for (uint32_t j = offset[v]; j < offset[v + 1]; ++j) {
        const auto [w, ce] = links[j];
        const auto& t = tv[ce / 3];
        const double nd = d + length(g_.pos[t[ce % 3]] - g_.pos[t[(ce % 3 + 1) % 3]]);
        if (nd < dist[w]) {
          dist[w] = nd;
          via[w] = ce;
          queue.push({nd, w});
        }
      }
    }
    if (any) std::sort(cuts.begin(), cuts.end());
    return any;
  }

  void flatten_single(FlatChart& fc) {
    const auto& t = (*g_.tris)[fc.tris[0]];
    const Vec3 p0 = g_.pos[t[0]], p1 = g_.pos[t[1]], p2 = g_.pos[t[2]];
    const double l01 = length(p1 - p0);
    const Vec3 e1 = (p1 - p0) / l01;
    const double x2 = dot(p2 - p0, e1);
    const double y2 = length(cross(e1, p2 - p0));
    fc.uv[fc.corner[0][0]] = {0, 0};
    fc.uv[fc.corner[0][1]] = {l01, 0};
    fc.uv[fc.corner[0][2]] = {x2, y2};
  }

  // LSCM (uv_generate_flatten.cpp) with the two vertices farthest apart along
  // the longer axis of the projection onto the piece's mean plane pinned.
  bool flatten(FlatChart& fc, const std::vector<std::pair<uint32_t, uint32_t>>& border) {
    const auto& tris = *g_.tris;
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
        const Vec3 p = g_.pos[tris[t][k]];
        const uint32_t l = fc.corner[i][k];
        cm.positions[3 * l] = p.x;
        cm.positions[3 * l + 1] = p.y;
        cm.positions[3 * l + 2] = p.z;
      }
      nsum += g_.normal[t] * g_.area[t];
      if (g_.area[t] > best_area) {
        best_area = g_.area[t];
        best_normal = g_.normal[t];
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
    if (uv_detail::flatten_lscm(cm, uv) != FlattenStatus::kOk) return false;
    for (uint32_t l = 0; l < nloc; ++l) fc.uv[l] = {uv[2 * l], uv[2 * l + 1]};
    return true;
  }

  // No flipped or degenerate triangle, a border that does not cross itself,
  // and stretch within the limit. Rescales fc.uv so that UV area = 3D area.
  bool valid(FlatChart& fc, const std::vector<std::pair<uint32_t, uint32_t>>& border) {
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
    const auto& tris = *g_.tris;
    double stretch_sum = 0;
    for (std::size_t i = 0; i < fc.tris.size(); ++i) {
      const auto& c = fc.corner[i];
      const double a = 0.5 * cross2(fc.uv[c[0]], fc.uv[c[1]], fc.uv[c[2]]);
      if (a < 1e-6 * g_.area[fc.tris[i]]) return false;
      stretch_sum += triangle_l2_squared(tris[fc.tris[i]], fc.uv[c[0]], fc.uv[c[1]], fc.uv[c[2]]) *
                     g_.area[fc.tris[i]];
    }
    if (std::sqrt(stretch_sum / fc.area3d) > max_stretch_) return false;
    if (border_crosses_itself(fc, border)) return false;
    return true;
  }

 public:
  // Sander et al. 2001: squared L2 stretch of one triangle (3D points q, UVs p).
  double triangle_l2_squared(const std::array<uint32_t, 3>& t, Vec2 p1, Vec2 p2, Vec2 p3) const {
    const Vec3 q1 = g_.pos[t[0]], q2 = g_.pos[t[1]], q3 = g_.pos[t[2]];
    const double a2 = cross2(p1, p2, p3);  // 2A
    const Vec3 ss = (q1 * (p2.y - p3.y) + q2 * (p3.y - p1.y) + q3 * (p1.y - p2.y)) / a2;
    const Vec3 st = (q1 * (p3.x - p2.x) + q2 * (p1.x - p3.x) + q3 * (p2.x - p1.x)) / a2;
    return 0.5 * (dot(ss, ss) + dot(st, st));
  }

 private:
  static bool segments_cross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
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
  bool border_crosses_itself(const FlatChart& fc,
                             const std::vector<std::pair<uint32_t, uint32_t>>& border) const {
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
      const int cx0 = cell_of(std::min(a.x, b.x), x0, cw),
                cx1 = cell_of(std::max(a.x, b.x), x0, cw);
      const int cy0 = cell_of(std::min(a.y, b.y), y0, ch),
                cy1 = cell_of(std::max(a.y, b.y), y0, ch);
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

  // Splits a piece in two halves of equal area across the longest axis of its
  // centroids' bounding box.
  std::pair<std::vector<uint32_t>, std::vector<uint32_t>> split(std::vector<uint32_t> tris) const {
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    double total = 0;
    for (uint32_t t : tris) {
      const Vec3 c = g_.centroid[t];
      lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
      hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
      total += g_.area[t];
    }
    const Vec3 ext = hi - lo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    std::sort(tris.begin(), tris.end(), [&](uint32_t a, uint32_t b) {
      const double ca = g_.centroid[a][axis], cb = g_.centroid[b][axis];
      return ca < cb || (ca == cb && a < b);
    });
    std::size_t cut = 1;
    double acc = g_.area[tris[0]];
    while (cut + 1 < tris.size() && acc + g_.area[tris[cut]] <= 0.5 * total)
      acc += g_.area[tris[cut++]];
    std::vector<uint32_t> a(tris.begin(), tris.begin() + cut), b(tris.begin() + cut, tris.end());
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    return {std::move(a), std::move(b)};
  }

  const Geometry& g_;
  const std::vector<uint32_t>& chart_;
  Scratch& s_;
  double max_stretch_;
  uint32_t chart_id_ = 0;
  uint32_t stamp_ = 0;
};

// Rotates a chart so that its minimum-area bounding rectangle (one side along
// a convex-hull edge, Freeman & Shapira 1975) is axis aligned, with its
// lower-left corner at the origin.
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

// ---------------------------------------------------------------------------
// Packing.

// Conservative coverage: does triangle (a, b, c) meet the square
// [x0, x1] x [y0, y1]? Separating axes: the square's axes (by the caller's
// bounding-box loop) and the triangle's three edge normals.
bool triangle_meets_box(Vec2 a, Vec2 b, Vec2 c, double x0, double y0, double x1, double y1) {
  const double orient = cross2(a, b, c);
  const Vec2 v[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    const Vec2 p = v[k], q = v[(k + 1) % 3];
    // Inside is where orient * cross(p, q, x) >= 0; the box is outside if even
    // its best corner is strictly outside.
    const double nx = -(q.y - p.y) * orient, ny = (q.x - p.x) * orient;
    const double bx = nx > 0 ? x1 : x0, by = ny > 0 ? y1 : y0;
    if (nx * (bx - p.x) + ny * (by - p.y) < 0) return false;
  }
  return true;
}

// Covered texels of a chart at one scale. The chart's UVs (in length units,
// lower-left at the origin) map to texel space as uv * scale + 0.5, so that
// the bitmap is [0, w) x [0, h).
struct ChartRaster {
  int w = 0, h = 0;
  std::vector<uint8_t> bits;  // row-major, row 0 at the bottom
  std::size_t covered = 0;
};

// Texel squares are grown by kCoverEps texel in the packer so that the
// float32 rounding of the final UVs never makes a texel covered that the
// packer did not see (float32 spacing near 1 is 6e-8, i.e. 1e-3 texel at 16384).
constexpr double kCoverEps = 1e-2;

ChartRaster rasterize_chart(const FlatChart& fc, double scale) {
  ChartRaster r;
  double x1 = 0, y1 = 0;
  for (const Vec2& p : fc.uv) {
    x1 = std::max(x1, p.x * scale + 0.5);
    y1 = std::max(y1, p.y * scale + 0.5);
  }
  r.w = static_cast<int>(std::floor(x1 + kCoverEps)) + 1;
  r.h = static_cast<int>(std::floor(y1 + kCoverEps)) + 1;
  r.bits.assign(static_cast<std::size_t>(r.w) * r.h, 0);
  for (const auto& c : fc.corner) {
    const Vec2 a{fc.uv[c[0]].x * scale + 0.5, fc.uv[c[0]].y * scale + 0.5};
    const Vec2 b{fc.uv[c[1]].x * scale + 0.5, fc.uv[c[1]].y * scale + 0.5};
    const Vec2 d{fc.uv[c[2]].x * scale + 0.5, fc.uv[c[2]].y * scale + 0.5};
    const int i0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, d.x}) - kCoverEps)));
    const int i1 =
        std::min(r.w - 1, static_cast<int>(std::floor(std::max({a.x, b.x, d.x}) + kCoverEps)));
    const int j0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, d.y}) - kCoverEps)));
    const int j1 =
        std::min(r.h - 1, static_cast<int>(std::floor(std::max({a.y, b.y, d.y}) + kCoverEps)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        uint8_t& bit = r.bits[static_cast<std::size_t>(j) * r.w + i];
        if (bit) continue;
        if (triangle_meets_box(a, b, d, i - kCoverEps, j - kCoverEps, i + 1 + kCoverEps,
                               j + 1 + kCoverEps)) {
          bit = 1;
          ++r.covered;
        }
      }
    }
  }
  return r;
}

// Column profiles of a raster in one of four rotations (counter-clockwise
// quarter turns): width, height, lowest and highest covered row per column.
struct Profile {
  int w = 0, h = 0;
  std::vector<int> bottom, top;
};

Profile profile(const ChartRaster& r, int rot) {
  std::vector<int> col_lo(r.w, r.h), col_hi(r.w, -1), row_lo(r.h, r.w), row_hi(r.h, -1);
  for (int j = 0; j < r.h; ++j) {
    for (int i = 0; i < r.w; ++i) {
      if (!r.bits[static_cast<std::size_t>(j) * r.w + i]) continue;
      col_lo[i] = std::min(col_lo[i], j);
      col_hi[i] = std::max(col_hi[i], j);
      row_lo[j] = std::min(row_lo[j], i);
      row_hi[j] = std::max(row_hi[j], i);
    }
  }
  Profile p;
  if (rot == 0) {  // (i, j) -> (i, j)
    p = {r.w, r.h, col_lo, col_hi};
  } else if (rot == 2) {  // (i, j) -> (w-1-i, h-1-j)
    p.w = r.w, p.h = r.h;
    p.bottom.resize(r.w), p.top.resize(r.w);
    for (int c = 0; c < r.w; ++c) {
      p.bottom[c] = r.h - 1 - col_hi[r.w - 1 - c];
      p.top[c] = r.h - 1 - col_lo[r.w - 1 - c];
    }
  } else if (rot == 1) {  // (i, j) -> (h-1-j, i)
    p.w = r.h, p.h = r.w;
    p.bottom.resize(r.h), p.top.resize(r.h);
    for (int c = 0; c < r.h; ++c) {
      p.bottom[c] = row_lo[r.h - 1 - c];
      p.top[c] = row_hi[r.h - 1 - c];
    }
  } else {  // (i, j) -> (j, w-1-i)
    p.w = r.h, p.h = r.w;
    p.bottom.resize(r.h), p.top.resize(r.h);
    for (int c = 0; c < r.h; ++c) {
      p.bottom[c] = r.w - 1 - row_hi[c];
      p.top[c] = r.w - 1 - row_lo[c];
    }
  }
  // A connected chart covers every column of its box; should one not, treat
  // that column as fully covered (safe: it only reserves more space).
  for (int c = 0; c < p.w; ++c) {
    if (p.top[c] < p.bottom[c]) p.bottom[c] = 0, p.top[c] = p.h - 1;
  }
  return p;
}

struct Placement {
  int x = 0, y = 0, rot = 0;
};

// Occupied texels of the atlas, per column, as sorted disjoint closed row
// intervals [first, last]. Placed charts enter dilated by the padding.
class ColumnIntervals {
 public:
  explicit ColumnIntervals(int size) : cols_(size) {}

  // Smallest row r >= y such that [r, r + (last - first)] meets no interval
  // of column x, given the span starts at `first` ... relative form: returns
  // the lowest start row >= y of a free span of `len` rows in column x.
  int lowest_free(int x, int y, int len) const {
    const auto& col = cols_[x];
    // First interval ending at or above y (ends are sorted: intervals are disjoint).
    auto it =
        std::lower_bound(col.begin(), col.end(), y,
                         [](const std::pair<int, int>& s, int row) { return s.second < row; });
    for (; it != col.end(); ++it) {
      if (it->first > y + len - 1) return y;
      y = it->second + 1;
    }
    return y;
  }

  void insert(int x, int a, int b) {
    auto& col = cols_[x];
    auto it = std::lower_bound(col.begin(), col.end(), std::pair<int, int>{a, b});
    it = col.insert(it, {a, b});
    // Merge with neighbours that overlap or touch.
    if (it != col.begin() && std::prev(it)->second >= a - 1) {
      --it;
      it->second = std::max(it->second, b);
      col.erase(std::next(it));
    }
    while (std::next(it) != col.end() && std::next(it)->first <= it->second + 1) {
      it->second = std::max(it->second, std::next(it)->second);
      col.erase(std::next(it));
    }
  }

 private:
  std::vector<std::vector<std::pair<int, int>>> cols_;
};

// Bottom-left-fill packing of rasterised charts, largest first, into a strip
// `size` texels wide and at most `max_height` high: each chart takes, over
// four quarter turns and every column, the lowest position where each of its
// columns' covered span [bottom, top] fits between the occupied spans of the
// atlas column below it (a chart's column is treated as covered from its
// lowest to its highest texel). Holes left under earlier charts are thus
// filled by later ones, unlike a skyline packer. Occupied spans are the
// placed charts dilated by `padding` (in the Chebyshev metric), so covered
// texels of two charts are more than `padding` texels apart; the strip's
// edges need no gutter. Ties: lower top edge, then further left, then fewer
// turns. Returns the height used (the highest top edge), or -1 when a chart
// does not fit below max_height.
int pack(const std::vector<ChartRaster>& rasters, const std::vector<uint32_t>& order, int size,
         int padding, int max_height, std::vector<Placement>& placed) {
  ColumnIntervals occupied(size);
  placed.assign(rasters.size(), {});
  constexpr std::size_t kGrain = 128;
  struct Best {
    long score = std::numeric_limits<long>::max();
    int x = 0, y = 0, rot = 0;
  };
  int used = 0;
  Profile profiles[4];
  // Lowest position of profile p at column x (y only grows while raising, so
  // this ends after at most one raise per occupied span), or -1 when it
  // cannot beat `bound` (score (top edge) * size + x) or exceeds max_height.
  auto lowest = [&](const Profile& p, int x, long bound) {
    int y = 0;
    for (int c = 0, clean = 0; clean < p.w; c = c + 1 == p.w ? 0 : c + 1) {
      const int len = p.top[c] - p.bottom[c] + 1;
      const int free = occupied.lowest_free(x + c, y + p.bottom[c], len);
      if (free == y + p.bottom[c]) {
        ++clean;
        continue;
      }
      y = free - p.bottom[c];
      clean = 1;
      if (y + p.h > max_height || (static_cast<long>(y) + p.h) * size + x >= bound) return -1;
    }
    return y;
  };
  for (uint32_t ci : order) {
    Best best;
    for (int rot = 0; rot < 4; ++rot) profiles[rot] = profile(rasters[ci], rot);
    // Wide charts are first placed on every kStride-th column, then the best
    // of those is refined column by column within +-kStride: the cost of a
    // column is the chart's width, and a texel or two of horizontal slack
    // rarely decides whether a wide chart fits.
    const int stride = std::clamp(profiles[0].w / 32, 1, 4);
    for (int rot = 0; rot < 4; ++rot) {
      const Profile& p = profiles[rot];
      if (p.w > size || p.h > max_height) continue;
      // The best possible score of this turn (y = 0, x = 0) cannot win.
      if (static_cast<long>(p.h) * size >= best.score) continue;
      const std::size_t positions = static_cast<std::size_t>(size - p.w) / stride + 1;
      // Fixed chunks of kGrain columns, one result slot each (parallel_for_chunks
      // may split a range at any point, so chunks are indexed explicitly).
      std::vector<Best> chunk_best((positions + kGrain - 1) / kGrain);
      parallel_for_chunks(chunk_best.size(), 1, [&](std::size_t kb, std::size_t ke) {
        for (std::size_t k = kb; k < ke; ++k) {
          const std::size_t b = k * kGrain, e = std::min(positions, b + kGrain);
          Best local = best;  // prune with what earlier rotations found (same for every chunk)
          for (std::size_t i = b; i < e; ++i) {
            const int x = static_cast<int>(i) * stride;
            // Scores grow with x at equal height: nothing further right in
            // this chunk can beat a position already found at y = 0.
            if (static_cast<long>(p.h) * size + x >= local.score) break;
            const int y = lowest(p, x, local.score);
            if (y < 0) continue;
            const long score = (static_cast<long>(y) + p.h) * size + x;
            if (score < local.score) local = {score, x, y, rot};
          }
          chunk_best[k] = local;
        }
      });
      for (const Best& cb : chunk_best) {
        if (cb.score < best.score) best = cb;
      }
    }
    if (stride > 1 && best.score != std::numeric_limits<long>::max()) {
      const Profile& p = profiles[best.rot];
      const int x0 = std::max(0, best.x - stride + 1),
                x1 = std::min(size - p.w, best.x + stride - 1);
      for (int x = x0; x <= x1; ++x) {
        if (x == best.x) continue;
        const int y = lowest(p, x, best.score);
        if (y < 0) continue;
        const long score = (static_cast<long>(y) + p.h) * size + x;
        if (score < best.score) best = {score, x, y, best.rot};
      }
    }
    if (best.score == std::numeric_limits<long>::max()) return -1;
    placed[ci] = {best.x, best.y, best.rot};
    const Profile& p = profiles[best.rot];
    used = std::max(used, best.y + p.h);
    for (int c = -padding; c < p.w + padding; ++c) {
      const int x = best.x + c;
      if (x < 0 || x >= size) continue;
      int lo = std::numeric_limits<int>::max(), hi = -1;
      for (int d = std::max(0, c - padding); d <= std::min(p.w - 1, c + padding); ++d) {
        if (p.top[d] < p.bottom[d]) continue;
        lo = std::min(lo, p.bottom[d]);
        hi = std::max(hi, p.top[d]);
      }
      if (hi >= 0) occupied.insert(x, best.y + lo - padding, best.y + hi + padding);
    }
  }
  return used;
}

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
  const Geometry g = build_geometry(mesh);
  const std::size_t n = mesh.triangles.size();
  double total_area = 0;
  for (double a : g.area) total_area += a;
  if (!(total_area > 0)) {
    return make_error(ErrorCode::kInvalidArgument, "the mesh's triangles have zero total area");
  }

  // 1. Charts.
  uint32_t chart_count = 0;
  std::vector<uint32_t> chart =
      grow_charts(g, std::cos(options.max_chart_angle_deg * M_PI / 180.0), chart_count);
  smooth_chart_borders(g, chart, chart_count,
                       std::cos(std::min(89.0, options.max_chart_angle_deg + 15.0) * M_PI / 180.0),
                       4);
  // Charts below ~1/2000 of the surface cost more gutter than they save stretch.
  merge_small_charts(g, chart, chart_count, total_area * 5e-4);

  // 2. Cut and flatten, one task per chart (charts' triangles are disjoint).
  std::vector<std::vector<uint32_t>> members(chart_count);
  for (uint32_t t = 0; t < n; ++t) members[chart[t]].push_back(t);
  Scratch scratch;
  scratch.stamp.assign(n, 0);
  scratch.parent.resize(3 * n);
  scratch.local.resize(3 * n);
  std::vector<std::vector<FlatChart>> pieces(chart_count);
  // Largest charts first so that the slowest solves do not end the loop alone.
  std::vector<uint32_t> by_size(chart_count);
  std::iota(by_size.begin(), by_size.end(), 0u);
  std::stable_sort(by_size.begin(), by_size.end(),
                   [&](uint32_t a, uint32_t b) { return members[a].size() > members[b].size(); });
  parallel_for_chunks(chart_count, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const uint32_t c = by_size[i];
      ChartCutter cutter(g, chart, scratch, options.max_chart_stretch);
      cutter.run(c, std::move(members[c]), pieces[c]);
      for (FlatChart& fc : pieces[c]) orient_chart(fc);
    }
  });
  std::vector<FlatChart> charts;
  for (auto& p : pieces) {
    for (auto& fc : p) charts.push_back(std::move(fc));
  }
  pieces.clear();

  // 3. Pack: bisection on the global scale (texels per unit length).
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
  std::vector<ChartRaster> best_rasters;
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
      for (std::size_t i = b; i < e; ++i) rasters[i] = rasterize_chart(charts[i], scale);
    });
    const int used = pack(rasters, order, size, padding, max_height, placement);
    if (used >= 0 && used <= size) {
      lo = scale;
      best_scale = scale;
      best_placement = placement;
      best_rasters = rasters;
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
      const double x = p.x * best_scale + 0.5, y = p.y * best_scale + 0.5;
      double u = x, v = y;
      switch (pl.rot) {  // continuous versions of the rotations in profile()
        case 1:
          u = r.h - y, v = x;
          break;
        case 2:
          u = r.w - x, v = r.h - y;
          break;
        case 3:
          u = y, v = r.w - x;
          break;
        default:
          break;
      }
      atlas.uvs.push_back({static_cast<float>(std::clamp((u + pl.x) * inv, 0.0, 1.0)),
                           static_cast<float>(std::clamp((v + pl.y) * inv, 0.0, 1.0))});
    }
    for (std::size_t i = 0; i < fc.tris.size(); ++i) {
      const uint32_t t = fc.tris[i];
      atlas.triangle_chart[t] = static_cast<uint32_t>(ci);
      atlas.triangle_uvs[t] = {base + fc.corner[i][0], base + fc.corner[i][1],
                               base + fc.corner[i][2]};
    }
  }
  // Stretch on the final (float) UVs, as a consumer sees them.
  ChartCutter metric(g, chart, scratch, 0);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& c = atlas.triangle_uvs[t];
    const Vec2 p1{atlas.uvs[c[0]].u, atlas.uvs[c[0]].v}, p2{atlas.uvs[c[1]].u, atlas.uvs[c[1]].v},
        p3{atlas.uvs[c[2]].u, atlas.uvs[c[2]].v};
    const double a = 0.5 * cross2(p1, p2, p3);
    if (!(a > 0)) continue;  // cannot happen for valid charts; keeps the sum finite
    uv_area += a;
    stretch_sum += metric.triangle_l2_squared(mesh.triangles[t], p1, p2, p3) * g.area[t];
  }
  atlas.stretch_l2 = std::sqrt(stretch_sum / total_area) * std::sqrt(uv_area / total_area);
  atlas.utilisation = static_cast<double>(covered) / (static_cast<double>(size) * size);
  return atlas;
}

}  // namespace texbake
