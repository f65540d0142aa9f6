// Stage 4 of `--uv generate` (see uv_generate_internal.h): charts rasterised
// at one scale (conservative coverage) and packed by bottom-left fill over
// column spans.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "bake/util/parallel.h"
#include "bake/uv/uv_generate_internal.h"

namespace texbake::uv_detail {
namespace {

// Conservative coverage of one triangle (a, b, c): does it meet the square
// [x0, x1] x [y0, y1]? Separating axes: the square's axes (by the caller's
// bounding-box loop) and the triangle's three edge normals, which are worked
// out once per triangle rather than once per texel tested.
class TriangleBoxTest {
 public:
  TriangleBoxTest(Vec2 a, Vec2 b, Vec2 c) {
    const double orient = cross2(a, b, c);
    const Vec2 v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Vec2 p = v[k], q = v[(k + 1) % 3];
      // Inside is where orient * cross(p, q, x) >= 0.
      p_[k] = p;
      nx_[k] = -(q.y - p.y) * orient;
      ny_[k] = (q.x - p.x) * orient;
    }
  }

  bool meets(double x0, double y0, double x1, double y1) const {
    for (int k = 0; k < 3; ++k) {
      // The box is outside if even its best corner is strictly outside.
      const double bx = nx_[k] > 0 ? x1 : x0, by = ny_[k] > 0 ? y1 : y0;
      if (nx_[k] * (bx - p_[k].x) + ny_[k] * (by - p_[k].y) < 0) return false;
    }
    return true;
  }

 private:
  Vec2 p_[3];
  double nx_[3], ny_[3];
};

// Texel squares are grown by kCoverEps texel in the packer so that the
// float32 rounding of the final UVs never makes a texel covered that the
// packer did not see (float32 spacing near 1 is 6e-8, i.e. 1e-3 texel at 16384).
constexpr double kCoverEps = 1e-2;

// Column profiles of a raster in one of four rotations (counter-clockwise
// quarter turns): width, height, lowest and highest covered row per column.
struct Profile {
  int w = 0, h = 0;
  std::vector<int> bottom, top;
};

// The four turns' profiles of r from one scan of its bits.
void profiles(const ChartRaster& r, Profile (&out)[4]) {
  std::vector<int> col_lo(r.w, r.h), col_hi(r.w, -1), row_lo(r.h, r.w), row_hi(r.h, -1);
  for (int j = 0; j < r.h; ++j) {
    const uint8_t* row = r.bits.data() + static_cast<std::size_t>(j) * r.w;
    for (int i = 0; i < r.w; ++i) {
      if (!row[i]) continue;
      col_lo[i] = std::min(col_lo[i], j);
      col_hi[i] = std::max(col_hi[i], j);
      row_lo[j] = std::min(row_lo[j], i);
      row_hi[j] = std::max(row_hi[j], i);
    }
  }
  for (int rot = 0; rot < 4; ++rot) {
    Profile& p = out[rot];
    if (rot == 0) {  // (i, j) -> (i, j)
      p.w = r.w, p.h = r.h;
      p.bottom = col_lo, p.top = col_hi;
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
  }
}

// Occupied texels of the atlas, per column, as sorted disjoint closed row
// intervals [first, last]. Placed charts enter dilated by the padding.
class ColumnIntervals {
 public:
  explicit ColumnIntervals(int size) : cols_(size) {}

  // Lowest row r >= y such that rows [r, r + len - 1] of column x meet no
  // interval.
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

  // Adds rows [a, b] to column x, merging intervals that overlap or touch.
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

}  // namespace

ChartRaster rasterize_chart(const FlatChart& fc, double scale) {
  ChartRaster r;
  // Texel positions of the local vertices, once each (a vertex is in about
  // six triangles), and the raster's extent from them.
  std::vector<Vec2> texel(fc.uv.size());
  double x1 = 0, y1 = 0;
  for (std::size_t v = 0; v < fc.uv.size(); ++v) {
    texel[v] = {fc.uv[v].x * scale + 0.5, fc.uv[v].y * scale + 0.5};
    x1 = std::max(x1, texel[v].x);
    y1 = std::max(y1, texel[v].y);
  }
  r.w = static_cast<int>(std::floor(x1 + kCoverEps)) + 1;
  r.h = static_cast<int>(std::floor(y1 + kCoverEps)) + 1;
  r.bits.assign(static_cast<std::size_t>(r.w) * r.h, 0);
  for (const auto& c : fc.corner) {
    const Vec2 a = texel[c[0]], b = texel[c[1]], d = texel[c[2]];
    const int i0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, d.x}) - kCoverEps)));
    const int i1 =
        std::min(r.w - 1, static_cast<int>(std::floor(std::max({a.x, b.x, d.x}) + kCoverEps)));
    const int j0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, d.y}) - kCoverEps)));
    const int j1 =
        std::min(r.h - 1, static_cast<int>(std::floor(std::max({a.y, b.y, d.y}) + kCoverEps)));
    const TriangleBoxTest test(a, b, d);
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        uint8_t& bit = r.bits[static_cast<std::size_t>(j) * r.w + i];
        if (bit) continue;
        if (test.meets(i - kCoverEps, j - kCoverEps, i + 1 + kCoverEps, j + 1 + kCoverEps)) {
          bit = 1;
          ++r.covered;
        }
      }
    }
  }
  return r;
}

// Candidate positions are scored (top edge) * size + x; the columns of a
// position are tested against ColumnIntervals, where placed charts enter
// dilated by `padding`. Unlike a skyline packer, holes left under earlier
// charts stay available to later ones.
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
  Profile prof[4];
  // Lowest position of profile p at column x (y only grows while raising, so
  // this ends after at most one raise per occupied span), or -1 when it
  // cannot beat `bound` (score (top edge) * size + x) or exceeds max_height.
  //
  // The answer is the least y at which every column is free, whatever column
  // the walk starts at (each raise goes to the least y at or above the
  // current one that its column allows, so it never passes that least y).
  // Starting at `start` (0 <= start < p.w), the column that raised y last
  // for the position before, usually gets to it in one raise: the walk then
  // ends after one clean round instead of one per raise. `start` is set to
  // the column of the last raise.
  auto lowest = [&](const Profile& p, int x, long bound, int& start) {
    int y = 0;
    for (int c = start, clean = 0; clean < p.w; c = c + 1 == p.w ? 0 : c + 1) {
      const int len = p.top[c] - p.bottom[c] + 1;
      const int free = occupied.lowest_free(x + c, y + p.bottom[c], len);
      if (free == y + p.bottom[c]) {
        ++clean;
        continue;
      }
      y = free - p.bottom[c];
      clean = 1;
      start = c;
      if (y + p.h > max_height || (static_cast<long>(y) + p.h) * size + x >= bound) return -1;
    }
    return y;
  };
  for (uint32_t ci : order) {
    Best best;
    profiles(rasters[ci], prof);
    // Wide charts are first placed on every kStride-th column, then the best
    // of those is refined column by column within +-kStride: the cost of a
    // column is the chart's width, and a texel or two of horizontal slack
    // rarely decides whether a wide chart fits.
    const int stride = std::clamp(prof[0].w / 32, 1, 4);
    for (int rot = 0; rot < 4; ++rot) {
      const Profile& p = prof[rot];
      if (p.w > size || p.h > max_height) continue;
      // The best possible score of this turn (y = 0, x = 0) cannot win.
      if (static_cast<long>(p.h) * size >= best.score) continue;
      const std::size_t positions = static_cast<std::size_t>(size - p.w) / stride + 1;
      // Fixed chunks of kGrain columns, one result slot each (parallel_for_chunks
      // may split a range at any point, so chunks are indexed explicitly).
      std::vector<Best> chunk_best((positions + kGrain - 1) / kGrain);
      // The lowest score any chunk has found so far (or the earlier turns'
      // best), shared as a pruning bound. Exact whatever the chunks' timing:
      // a position is cut only when its score is at least one found
      // elsewhere or by an earlier turn (which wins a tie), and this turn's
      // scores are distinct (one per position), so the winner is never cut.
      std::atomic<long> shared{best.score};
      parallel_for_chunks(chunk_best.size(), 1, [&](std::size_t kb, std::size_t ke) {
        for (std::size_t k = kb; k < ke; ++k) {
          const std::size_t b = k * kGrain, e = std::min(positions, b + kGrain);
          Best local = best;  // what earlier rotations found (same for every chunk)
          int start = 0;      // the column that raised y last, in the chart's columns
          for (std::size_t i = b; i < e; ++i) {
            const int x = static_cast<int>(i) * stride;
            // The same atlas column, seen from this position.
            start = i == b ? 0 : std::max(0, start - stride);
            const long bound = std::min(local.score, shared.load(std::memory_order_relaxed));
            // Scores grow with x at equal height: nothing further right in
            // this chunk can beat the bound once y = 0 cannot.
            if (static_cast<long>(p.h) * size + x >= bound) break;
            const int y = lowest(p, x, bound, start);
            if (y < 0) continue;
            const long score = (static_cast<long>(y) + p.h) * size + x;
            if (score < local.score) {
              local = {score, x, y, rot};
              long seen = shared.load(std::memory_order_relaxed);
              while (score < seen &&
                     !shared.compare_exchange_weak(seen, score, std::memory_order_relaxed)) {
              }
            }
          }
          chunk_best[k] = local;
        }
      });
      for (const Best& cb : chunk_best) {
        if (cb.score < best.score) best = cb;
      }
    }
    if (stride > 1 && best.score != std::numeric_limits<long>::max()) {
      const Profile& p = prof[best.rot];
      const int x0 = std::max(0, best.x - stride + 1),
                x1 = std::min(size - p.w, best.x + stride - 1);
      for (int x = x0; x <= x1; ++x) {
        if (x == best.x) continue;
        int start = 0;
        const int y = lowest(p, x, best.score, start);
        if (y < 0) continue;
        const long score = (static_cast<long>(y) + p.h) * size + x;
        if (score < best.score) best = {score, x, y, best.rot};
      }
    }
    if (best.score == std::numeric_limits<long>::max()) return -1;
    placed[ci] = {best.x, best.y, best.rot};
    const Profile& p = prof[best.rot];
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

Vec2 placed_texel(const ChartRaster& r, const Placement& pl, double scale, Vec2 p) {
  const double x = p.x * scale + 0.5, y = p.y * scale + 0.5;
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
  return {u + pl.x, v + pl.y};
}

}  // namespace texbake::uv_detail
