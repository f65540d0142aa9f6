// Stage 2 of `--uv generate` (see uv_generate_internal.h): every chart is cut
// into pieces that are topological disks and flatten well (uv_flatten.cpp),
// halving a piece and retrying until it does.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>

#include "bake/util/parallel.h"
#include "bake/uv/uv_generate_internal.h"

namespace texbake::uv_detail {
namespace {

// Pieces above this are halved before any solve. On the 832k-triangle
// armadillo every piece of more than ~47k triangles failed the stretch check
// after its solve (the solves thrown away were 1.5x the triangles kept), so a
// lower cap skips those wasted solves without changing the atlas there.
constexpr std::size_t kMaxSolveTriangles = 49152;
// Split pieces at least this large have their halves processed in parallel.
constexpr std::size_t kParallelSplitTriangles = 8192;

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

// Cuts one chart into flattened disks (see cut_charts); one per chart task,
// all sharing one Scratch.
class ChartCutter {
 public:
  ChartCutter(const Geometry& g, const std::vector<uint32_t>& chart, Scratch& s, double max_stretch)
      : g_(g), chart_(chart), s_(s), max_stretch_(max_stretch) {}

  // Cuts chart c (its triangles `tris`, ascending) into one or more flat
  // charts appended to out.
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

  // Connected components of tris (ascending) over in-piece adjacency, each
  // ascending, in order of their smallest triangle.
  std::vector<std::vector<uint32_t>> components(std::vector<uint32_t> tris) {
    mark(tris);
    const uint32_t piece = stamp_;
    // Every component takes a fresh stamp as its label.
    std::vector<uint32_t> labels;
    std::vector<std::size_t> sizes;
    std::vector<uint32_t> stack;
    for (uint32_t seed : tris) {
      if (stamp_of(seed) != piece) continue;
      const uint32_t label = fresh_stamp();
      labels.push_back(label);
      sizes.push_back(0);
      set_stamp(seed, label);
      stack.push_back(seed);
      while (!stack.empty()) {
        const uint32_t t = stack.back();
        stack.pop_back();
        ++sizes.back();
        for (int k = 0; k < 3; ++k) {
          const uint32_t a = g_.adj[3 * t + k];
          if (a == kNone || chart_[a / 3] != chart_id_ || stamp_of(a / 3) != piece) continue;
          set_stamp(a / 3, label);
          stack.push_back(a / 3);
        }
      }
    }
    std::vector<std::vector<uint32_t>> comps;
    if (labels.size() == 1) {  // the usual case: the piece is connected
      comps.push_back(std::move(tris));
      return comps;
    }
    // Labels ascend (other tasks may take stamps in between): distribute tris
    // in order, so each component stays ascending.
    comps.resize(labels.size());
    for (std::size_t c = 0; c < labels.size(); ++c) comps[c].reserve(sizes[c]);
    for (uint32_t t : tris) {
      const auto c = std::lower_bound(labels.begin(), labels.end(), stamp_of(t)) - labels.begin();
      comps[static_cast<std::size_t>(c)].push_back(t);
    }
    return comps;
  }

  void process(std::vector<uint32_t> tris, std::vector<FlatChart>& out) {
    for (auto& comp : components(std::move(tris))) flatten_or_split(std::move(comp), out);
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

  FlatChart weld(const std::vector<uint32_t>& tris, Border& border,
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
    Border border;
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
      flatten_triangle(g_, fc);
      out.push_back(std::move(fc));
      return;
    }
    if (disk && flatten_chart(g_, fc, border, max_stretch_)) {
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
  static int border_loops(const FlatChart& fc, const Border& border, std::vector<uint32_t>& loop) {
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
                         const Border& border, const std::vector<uint32_t>& loop,
                         std::vector<uint32_t>& cuts) {
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

  // Splits a piece (ascending) in two halves of equal area across the longest
  // axis of its centroids' bounding box: triangles in order of their
  // centroid along it (ties by index), the first half up to half the area.
  // Both halves come out ascending (a stable partition of the input, not a
  // sort).
  std::pair<std::vector<uint32_t>, std::vector<uint32_t>> split(
      const std::vector<uint32_t>& tris) const {
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
    // (centroid, position in tris): positions order like indices (tris is
    // ascending), and the keys sit beside them rather than behind an index.
    std::vector<std::pair<double, uint32_t>> order(tris.size());
    for (std::size_t i = 0; i < tris.size(); ++i) {
      order[i] = {g_.centroid[tris[i]][axis], static_cast<uint32_t>(i)};
    }
    // The first half in that order, by weighted quickselect (expected linear
    // time; a full sort dominated the splitting of million-triangle charts).
    // Invariant: order[0, low) holds the `low` first triangles of the sorted
    // order, of area `below` <= half the total, and every triangle in
    // order[high, n) comes after all of order[0, high). It ends with low =
    // high: the longest prefix of at most half the area (at least the first
    // triangle, at most all but the last: order[0] is then the first and
    // order[n - 1] the last).
    const double half = 0.5 * total;
    std::size_t low = 0, high = order.size();
    double below = 0;
    while (low < high) {
      const std::size_t mid = low + (high - low) / 2;
      std::nth_element(order.begin() + low, order.begin() + mid, order.begin() + high);
      double left = 0;
      for (std::size_t i = low; i <= mid; ++i) left += g_.area[tris[order[i].second]];
      if (below + left <= half) {
        below += left;
        low = mid + 1;
      } else {
        high = mid;
      }
    }
    std::size_t cut = std::clamp<std::size_t>(low, 1, tris.size() - 1);
    // The halves must be those of the one-by-one sum in sorted order (the
    // atlas depends on them). The blocks' sums above differ from it only by
    // rounding, which decides the cut only when the total lands within
    // rounding of half (equal areas, as on a subdivided mesh, do that):
    // then the whole order is sorted and summed that way.
    auto area_at = [&](std::size_t i) { return g_.area[tris[order[i].second]]; };
    const double slack =
        4.0 * static_cast<double>(tris.size()) * std::numeric_limits<double>::epsilon() * total;
    // The triangle after the prefix in sorted order: the least of the rest.
    const auto next = std::min_element(order.begin() + low, order.end());
    if (std::abs(below - half) <= slack ||
        (next != order.end() && std::abs(below + g_.area[tris[next->second]] - half) <= slack)) {
      std::sort(order.begin(), order.end());
      cut = 1;
      double acc = area_at(0);
      while (cut + 1 < tris.size() && acc + area_at(cut) <= half) acc += area_at(cut++);
    }
    std::vector<uint8_t> first(tris.size(), 0);
    for (std::size_t i = 0; i < cut; ++i) first[order[i].second] = 1;
    std::vector<uint32_t> a, b;
    a.reserve(cut);
    b.reserve(tris.size() - cut);
    for (std::size_t i = 0; i < tris.size(); ++i) (first[i] ? a : b).push_back(tris[i]);
    return {std::move(a), std::move(b)};
  }

  const Geometry& g_;
  const std::vector<uint32_t>& chart_;
  Scratch& s_;
  double max_stretch_;
  uint32_t chart_id_ = 0;
  uint32_t stamp_ = 0;
};

}  // namespace

std::vector<FlatChart> cut_charts(const Geometry& g, const std::vector<uint32_t>& chart,
                                  uint32_t chart_count, double max_stretch) {
  const std::size_t n = chart.size();
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
  // One task per chart (charts' triangles are disjoint).
  parallel_for_chunks(chart_count, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const uint32_t c = by_size[i];
      ChartCutter cutter(g, chart, scratch, max_stretch);
      cutter.run(c, std::move(members[c]), pieces[c]);
      for (FlatChart& fc : pieces[c]) orient_chart(fc);
    }
  });
  std::vector<FlatChart> charts;
  for (auto& p : pieces) {
    for (auto& fc : p) charts.push_back(std::move(fc));
  }
  return charts;
}

}  // namespace texbake::uv_detail
