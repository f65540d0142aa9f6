#include "bake/atlas/dilate.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <vector>

#include "bake/util/parallel.h"

namespace texbake {
namespace {

constexpr std::size_t kRowGrain = 8;  // rows per parallel chunk

struct Level {
  int w = 0, h = 0;
  std::vector<std::array<float, 4>> c;  // colour
  std::vector<float> wt;                // weight in [0, 1]
};

}  // namespace

int default_padding(int size) {
  return std::max(1, static_cast<int>(std::lround(8.0 * size / 2048.0)));
}

// Ring by ring over a frontier instead of `texels` passes over the whole
// image: ring 0's candidates are the unbaked 8-neighbours of baked texels
// (one parallel scan), ring k+1's the unbaked neighbours of ring k. Each
// candidate takes the average of its neighbours baked before its ring, which
// is exactly what a full pass computes, so the result is the same while the
// work after the scan is proportional to the texels filled (at 4096 with 16
// rings: 16 full passes over 16.7M texels before).
std::size_t dilate(std::span<float> rgba, std::span<uint8_t> baked, int width, int height,
                   int texels) {
  const std::size_t count = static_cast<std::size_t>(width) * height;
  assert(rgba.size() >= count * 4 && baked.size() >= count);
  if (texels <= 0 || count == 0) return 0;

  // Ring 0: per row band, the unbaked texels with a baked neighbour,
  // ascending; concatenated in band order.
  const std::size_t row_chunks = (static_cast<std::size_t>(height) + kRowGrain - 1) / kRowGrain;
  std::vector<std::vector<uint32_t>> per_chunk(row_chunks);
  parallel_for_chunks(row_chunks, 1, [&](std::size_t c_begin, std::size_t c_end) {
    for (std::size_t c = c_begin; c < c_end; ++c) {
      const int y_begin = static_cast<int>(c * kRowGrain);
      const int y_end = std::min(height, y_begin + static_cast<int>(kRowGrain));
      for (int y = y_begin; y < y_end; ++y) {
        const uint8_t* up = y > 0 ? &baked[static_cast<std::size_t>(y - 1) * width] : nullptr;
        const uint8_t* row = &baked[static_cast<std::size_t>(y) * width];
        const uint8_t* down =
            y + 1 < height ? &baked[static_cast<std::size_t>(y + 1) * width] : nullptr;
        for (int x = 0; x < width; ++x) {
          if (row[x]) continue;
          const int x0 = std::max(x - 1, 0), x1 = std::min(x + 1, width - 1);
          bool near = false;
          for (int xx = x0; xx <= x1 && !near; ++xx) {
            near = row[xx] || (up && up[xx]) || (down && down[xx]);
          }
          if (near) per_chunk[c].push_back(static_cast<uint32_t>(y * width + x));
        }
      }
    }
  });
  std::vector<uint32_t> ring, next;
  for (auto& v : per_chunk) {
    ring.insert(ring.end(), v.begin(), v.end());
    v = {};
  }

  // queued: a texel is in the current or next ring (never listed twice).
  std::vector<uint8_t> queued(count, 0);
  for (uint32_t i : ring) queued[i] = 1;
  std::size_t filled = 0;
  for (int pass = 0; pass < texels && !ring.empty(); ++pass) {
    // Writes go only to this ring's texels (unbaked), reads only to baked
    // ones: no race, and the result does not depend on the order.
    parallel_for_chunks(ring.size(), 4096, [&](std::size_t begin, std::size_t end) {
      for (std::size_t r = begin; r < end; ++r) {
        const std::size_t i = ring[r];
        const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
        float sum[4] = {0, 0, 0, 0};
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          const int yy = y + dy;
          if (yy < 0 || yy >= height) continue;
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx;
            if (xx < 0 || xx >= width || (dx == 0 && dy == 0)) continue;
            const std::size_t j = static_cast<std::size_t>(yy) * width + xx;
            if (!baked[j]) continue;
            for (int c = 0; c < 4; ++c) sum[c] += rgba[j * 4 + c];
            ++n;
          }
        }
        // n > 0: every ring texel has a neighbour baked before its ring.
        for (int c = 0; c < 4; ++c) rgba[i * 4 + c] = sum[c] / n;
      }
    });
    for (uint32_t i : ring) baked[i] = 1;
    filled += ring.size();
    if (pass + 1 == texels) break;
    next.clear();
    for (uint32_t i : ring) {
      const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= height) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= width) continue;
          const std::size_t j = static_cast<std::size_t>(yy) * width + xx;
          if (baked[j] || queued[j]) continue;
          queued[j] = 1;
          next.push_back(static_cast<uint32_t>(j));
        }
      }
    }
    ring.swap(next);
  }
  return filled;
}

// Level 0 is the image itself (read through `rgba` and `baked`, written
// in place), so the pyramid costs a third of the image's texels, not 4/3:
// at 16384 a copy of level 0 alone would be 5 GB. Every level is computed
// row-parallel from the one before, each texel from its own inputs only, so
// the result does not depend on the thread count. Work: linear in texels.
std::size_t push_pull_fill(std::span<float> rgba, std::span<const uint8_t> baked, int width,
                           int height, PushPullMode mode) {
  const std::size_t count = static_cast<std::size_t>(width) * height;
  assert(rgba.size() >= count * 4 && baked.size() >= count);
  const std::size_t baked_count =
      count - static_cast<std::size_t>(std::count(baked.begin(), baked.begin() + count, 0));
  const std::size_t holes = count - baked_count;
  if (baked_count == 0 || holes == 0) return 0;

  // Pull: each coarser texel is the weighted mean of its (up to) 2 x 2
  // children; its weight is their summed weight, clamped to 1. Level 0's
  // weights are 1 (baked) or 0.
  std::vector<Level> levels;  // levels[k] is level k + 1
  int fw = width, fh = height;
  while (fw > 1 || fh > 1) {
    const Level* fine = levels.empty() ? nullptr : &levels.back();
    Level coarse;
    coarse.w = (fw + 1) / 2;
    coarse.h = (fh + 1) / 2;
    coarse.c.assign(static_cast<std::size_t>(coarse.w) * coarse.h, {0, 0, 0, 0});
    coarse.wt.assign(coarse.c.size(), 0.f);
    parallel_for_chunks(coarse.h, kRowGrain, [&](std::size_t y_begin, std::size_t y_end) {
      for (int y = static_cast<int>(y_begin); y < static_cast<int>(y_end); ++y) {
        for (int x = 0; x < coarse.w; ++x) {
          double sw = 0, sc[4] = {0, 0, 0, 0};
          for (int dy = 0; dy < 2; ++dy) {
            for (int dx = 0; dx < 2; ++dx) {
              const int cx = 2 * x + dx, cy = 2 * y + dy;
              if (cx >= fw || cy >= fh) continue;
              const std::size_t j = static_cast<std::size_t>(cy) * fw + cx;
              const double w = fine ? fine->wt[j] : (baked[j] ? 1.0 : 0.0);
              if (w == 0) continue;
              const float* c = fine ? fine->c[j].data() : &rgba[j * 4];
              sw += w;
              for (int ch = 0; ch < 4; ++ch) sc[ch] += w * c[ch];
            }
          }
          const std::size_t i = static_cast<std::size_t>(y) * coarse.w + x;
          if (sw > 0) {
            for (int ch = 0; ch < 4; ++ch) coarse.c[i][ch] = static_cast<float>(sc[ch] / sw);
          }
          coarse.wt[i] = static_cast<float>(std::min(1.0, sw));
        }
      }
    });
    fw = coarse.w;
    fh = coarse.h;
    levels.push_back(std::move(coarse));
  }

  // Push, from the coarsest level down. Fine texel x sits at coarse
  // position (x + 0.5) / 2 - 0.5; edges clamp. Holes (weight < 1; level-0
  // holes have weight 0) become c = w c + (1 - w) up, where up is:
  //  - kOpaque: the bilinear upsampling of the (already filled) coarser level;
  //  - kMipSafe: if x's parent holds data (weight > 0), the bilinear
  //    upsampling over those of the four coarse texels that hold data
  //    (weights renormalised; the parent is one of them), else the parent's
  //    filled value. So a hole takes its value from the first level up where
  //    its ancestor holds data, from that ancestor and its data-holding
  //    neighbours only: inside any 2^k-aligned block that holds baked texels,
  //    every filled value is a convex combination of baked texels of that
  //    block and its 8 neighbours, and the block's box mean (its mip texel)
  //    stays within their range. The plain bilinear push can draw from
  //    farther (a neighbour filled from much coarser levels).
  for (int k = static_cast<int>(levels.size()) - 1; k >= 0; --k) {
    Level* fine = k > 0 ? &levels[k - 1] : nullptr;
    const Level& coarse = levels[k];
    const int w_fine = fine ? fine->w : width, h_fine = fine ? fine->h : height;
    parallel_for_chunks(h_fine, kRowGrain, [&](std::size_t y_begin, std::size_t y_end) {
      for (int y = static_cast<int>(y_begin); y < static_cast<int>(y_end); ++y) {
        for (int x = 0; x < w_fine; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * w_fine + x;
          const float w = fine ? fine->wt[i] : (baked[i] ? 1.f : 0.f);
          if (w >= 1) continue;
          float* out = fine ? fine->c[i].data() : &rgba[i * 4];
          const double cx = (x + 0.5) / 2 - 0.5, cy = (y + 0.5) / 2 - 0.5;
          const int x0 = static_cast<int>(std::floor(cx)), y0 = static_cast<int>(std::floor(cy));
          const double fx = cx - x0, fy = cy - y0;
          auto index = [&](int xx, int yy) {
            xx = std::clamp(xx, 0, coarse.w - 1);
            yy = std::clamp(yy, 0, coarse.h - 1);
            return static_cast<std::size_t>(yy) * coarse.w + xx;
          };
          const std::size_t corner[4] = {index(x0, y0), index(x0 + 1, y0), index(x0, y0 + 1),
                                         index(x0 + 1, y0 + 1)};
          double bw[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
          const std::size_t parent = static_cast<std::size_t>(y / 2) * coarse.w + x / 2;
          const bool inherit = mode == PushPullMode::kMipSafe && coarse.wt[parent] == 0;
          if (mode == PushPullMode::kMipSafe && !inherit) {
            double sum = 0;
            for (int q = 0; q < 4; ++q) {
              if (coarse.wt[corner[q]] == 0) bw[q] = 0;
              sum += bw[q];
            }
            for (double& b : bw) b /= sum;  // sum > 0: the parent is a corner
          }
          for (int ch = 0; ch < 4; ++ch) {
            double up = 0;
            if (inherit) {
              up = coarse.c[parent][ch];
            } else if (mode == PushPullMode::kOpaque) {
              // The bilinear form of the original implementation (same bits).
              const double top = coarse.c[corner[0]][ch] +
                                 fx * (coarse.c[corner[1]][ch] - coarse.c[corner[0]][ch]);
              const double bottom = coarse.c[corner[2]][ch] +
                                    fx * (coarse.c[corner[3]][ch] - coarse.c[corner[2]][ch]);
              up = top + fy * (bottom - top);
            } else {
              for (int q = 0; q < 4; ++q) up += bw[q] * coarse.c[corner[q]][ch];
            }
            const double own = fine ? fine->c[i][ch] : 0.0;
            out[ch] = static_cast<float>(w * own + (1 - w) * up);
          }
          if (!fine && mode == PushPullMode::kMipSafe) out[3] = 0.f;
        }
      }
    });
  }
  return holes;
}

}  // namespace texbake
