// Tiled views (mapping/tiled_image.h, issue #16 item 1): an ImageView read
// a tile at a time from a TileSource gives the same bits as the same image
// in memory, for single texels, bilinear lookups, the MIP pyramid and EWA;
// the linearised working image (decode_srgb) equals a linearised copy; a
// failed read is reported, never crashes. The source here holds the image
// in memory, so the expected values come from the in-memory path, which
// the rest of the suite checks against hand-worked and OpenCV values.
#include "mapping/tiled_image.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

#include "mapping/mipmap.h"
#include "mapping/sample.h"

namespace texbake {
namespace {

// A TileSource over an RGBA float image in memory; `bad_tile_x` (when >= 0)
// makes every read touching that column of 64-texel tiles fail.
class MemoryTiles final : public TileSource {
 public:
  MemoryTiles(int w, int h, std::vector<float> rgba) : w_(w), h_(h), rgba_(std::move(rgba)) {}
  bool read(int x0, int y0, int w, int h, int stride, bool decode_srgb, bool premultiply,
            float* out) const override {
    ++reads;
    EXPECT_GE(x0, 0);
    EXPECT_GE(y0, 0);
    EXPECT_LE(x0 + w, w_);
    EXPECT_LE(y0 + h, h_);
    const bool bad =
        bad_tile_x >= 0 && x0 / kTileSize <= bad_tile_x && (x0 + w - 1) / kTileSize >= bad_tile_x;
    for (int r = 0; r < h; ++r) {
      for (int c = 0; c < w; ++c) {
        float* d = out + (static_cast<std::size_t>(r) * stride + c) * 4;
        const float* s = &rgba_[(static_cast<std::size_t>(y0 + r) * w_ + x0 + c) * 4];
        for (int k = 0; k < 4; ++k) d[k] = bad ? 0.f : s[k];
        if (!bad) transform_texel(d, decode_srgb, premultiply);
      }
    }
    if (bad)
      set_error("tiles.tif: cannot decode (truncated or corrupt?): tile " +
                std::to_string(bad_tile_x));
    return !bad;
  }
  int bad_tile_x = -1;
  mutable std::atomic<int> reads{0};

 private:
  int w_, h_;
  std::vector<float> rgba_;
};

struct Pair {
  std::vector<float> rgba;
  std::unique_ptr<MemoryTiles> tiles;
  ImageView memory, tiled;
};

// w x h random texels in [0, 1] (alpha too), as an in-memory and a tiled view.
Pair make_pair(int w, int h, unsigned seed) {
  Pair p;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  p.rgba.resize(static_cast<std::size_t>(w) * h * 4);
  for (float& v : p.rgba) v = unit(rng);
  p.tiles = std::make_unique<MemoryTiles>(w, h, p.rgba);
  p.memory = ImageView{w, h, p.rgba.data()};
  p.tiled = ImageView{w, h, nullptr};
  p.tiled.tiles = p.tiles.get();
  return p;
}

bool same_bits(const Rgba& a, const Rgba& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(TiledImage, EveryTexelEqualsTheInMemoryTexelIncludingPartialEdgeTiles) {
  // 300 x 170: the last tile column is 44 wide, the last tile row 42 high.
  Pair p = make_pair(300, 170, 1);
  EXPECT_TRUE(p.tiled.has_texels());
  for (int y = 0; y < 170; ++y) {
    for (int x = 0; x < 300; ++x) {
      ASSERT_TRUE(same_bits(p.tiled.texel(x, y), p.memory.texel(x, y))) << x << "," << y;
    }
  }
  // Row by row in order: each tile is read once, not per texel (a tile row
  // fits the cache's window, and its rows revisit tiles still resident).
  const int t = TileSource::kTileSize;
  ASSERT_LE((300 + t - 1) / t, TileSource::kCacheWindow);
  EXPECT_EQ(p.tiles->reads.load(), ((300 + t - 1) / t) * ((170 + t - 1) / t));
}

TEST(TiledImage, TilesThatShareASlotReplaceEachOtherCorrectly) {
  // Tiles 0 and kCacheWindow of a row fall in the same slot of the
  // direct-mapped cache.
  const int t = TileSource::kTileSize, far = TileSource::kCacheWindow * t;
  Pair p = make_pair(far + t + 5, 70, 2);
  for (int round = 0; round < 3; ++round) {
    for (int x : {3, far + 3, t - 4, far + t - 4, far + t + 4}) {
      ASSERT_TRUE(same_bits(p.tiled.texel(x, 7), p.memory.texel(x, 7))) << x;
    }
  }
}

TEST(TiledImage, BilinearLookupsAreBitIdenticalForBothWrapModes) {
  Pair p = make_pair(257, 131, 3);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> coord(-0.3, 1.3);  // past both edges
  for (int i = 0; i < 20000; ++i) {
    const UV uv{coord(rng), coord(rng)};
    for (WrapMode u : {WrapMode::kRepeat, WrapMode::kClamp}) {
      ASSERT_TRUE(same_bits(sample_bilinear(p.tiled, uv, u, WrapMode::kClamp),
                            sample_bilinear(p.memory, uv, u, WrapMode::kClamp)))
          << uv.u << "," << uv.v;
    }
  }
}

TEST(TiledImage, MipLevelsAndEwaLookupsAreBitIdentical) {
  // Odd sizes take the fractional box taps, even ones the 2 x 2 blocks.
  for (auto [w, h] : {std::pair{200, 100}, std::pair{201, 99}}) {
    Pair p = make_pair(w, h, 5);
    const MipPyramid from_memory(p.memory), from_tiles(p.tiled);
    ASSERT_EQ(from_memory.levels(), from_tiles.levels());
    for (int i = 1; i < from_memory.levels(); ++i) {
      const ImageView& a = from_memory.level(i);
      const ImageView& b = from_tiles.level(i);
      ASSERT_EQ(std::memcmp(a.data, b.data, sizeof(float) * 4 * a.width * a.height), 0) << i;
    }
    for (int i = 0; i < from_memory.levels(); ++i) {
      for (int y = 0; y < from_memory.level(i).height; ++y) {
        ASSERT_EQ(
            std::memcmp(from_memory.row_mean(i, y), from_tiles.row_mean(i, y), 4 * sizeof(double)),
            0);
      }
    }
    std::mt19937 rng(6);
    std::uniform_real_distribution<double> unit(0, 1), size(0, 0.05);
    for (int k = 0; k < 3000; ++k) {
      const UV uv{unit(rng), unit(rng)};
      const UvFootprint f{{size(rng), size(rng) * 0.3}, {-size(rng) * 0.2, size(rng)}};
      ASSERT_TRUE(same_bits(sample_ewa(from_tiles, uv, f, WrapMode::kRepeat, WrapMode::kClamp),
                            sample_ewa(from_memory, uv, f, WrapMode::kRepeat, WrapMode::kClamp)));
    }
  }
}

TEST(TiledImage, TransformTexelIsTheSrgbCurveThenAlpha) {
  // By hand: sRGB 0.5 is linear 0.2140; premultiplied by alpha 0.5.
  float t[4] = {0.5f, 0.f, 1.f, 0.5f};
  transform_texel(t, true, true);
  EXPECT_NEAR(t[0], 0.214041 * 0.5, 1e-6);
  EXPECT_EQ(t[1], 0.f);
  EXPECT_NEAR(t[2], 0.5, 1e-7);
  EXPECT_EQ(t[3], 0.5f);
  float u[4] = {0.5f, 0.25f, 1.f, 0.5f};
  transform_texel(u, false, true);
  EXPECT_EQ(u[0], 0.25f);
  EXPECT_EQ(u[1], 0.125f);
}

TEST(TiledImage, DecodeSrgbEqualsALinearisedCopy) {
  Pair p = make_pair(130, 70, 7);
  std::vector<float> linear = p.rgba;
  for (std::size_t i = 0; i < linear.size(); ++i) {
    if (i % 4 != 3) linear[i] = srgb_to_linear(linear[i]);
  }
  const ImageView copy{130, 70, linear.data(), ColorSpace::kLinear};
  ImageView decoded = p.tiled;
  decoded.decode_srgb = true;
  for (int y = 0; y < 70; y += 3) {
    for (int x = 0; x < 130; ++x) {
      ASSERT_TRUE(same_bits(decoded.texel(x, y), copy.texel(x, y)));
      // The undecoded view of the same source is cached apart from it.
      ASSERT_TRUE(same_bits(p.tiled.texel(x, y), p.memory.texel(x, y)));
      // And premultiplied (a layer's texture): R, G, B times alpha.
      ImageView pre = decoded;
      pre.premultiply = true;
      const Rgba l = copy.texel(x, y), q = pre.texel(x, y);
      for (int k = 0; k < 3; ++k) ASSERT_EQ(q[k], l[k] * l[3]);
    }
  }
}

TEST(TiledImage, ReadRowsGivesTheRowsOfEitherView) {
  Pair p = make_pair(150, 40, 8);
  std::vector<float> a(150 * 7 * 4), b(150 * 7 * 4);
  ASSERT_TRUE(read_rows(p.memory, 20, 27, a.data()));
  ASSERT_TRUE(read_rows(p.tiled, 20, 27, b.data()));
  EXPECT_EQ(std::memcmp(a.data(), &p.rgba[20 * 150 * 4], a.size() * sizeof(float)), 0);
  EXPECT_EQ(a, b);
}

TEST(TiledImage, TwoThreadsReadTheSameSourceAlike) {
  Pair p = make_pair(500, 300, 9);
  std::atomic<int> mismatches{0};
  auto work = [&](int phase) {
    for (int y = phase; y < 300; y += 2) {
      for (int x = 0; x < 500; ++x) {
        if (!same_bits(p.tiled.texel(x, y), p.memory.texel(x, y))) ++mismatches;
      }
    }
  };
  std::thread a(work, 0), b(work, 1);
  a.join();
  b.join();
  EXPECT_EQ(mismatches.load(), 0);
}

TEST(TiledImage, AFailedReadGivesZerosAndTheSourcesErrorAfterThePass) {
  Pair p = make_pair(200, 64, 10);
  p.tiles->bad_tile_x = 1;
  EXPECT_TRUE(check_texels_read(p.tiled).has_value());
  EXPECT_TRUE(same_bits(p.tiled.texel(10, 10), p.memory.texel(10, 10)));
  EXPECT_TRUE(same_bits(p.tiled.texel(TileSource::kTileSize + 6, 10), Rgba{0, 0, 0, 0}));
  const Status s = check_texels_read(p.tiled);
  ASSERT_FALSE(s.has_value());
  EXPECT_EQ(s.error().code, ErrorCode::kParse);
  EXPECT_EQ(s.error().message, "tiles.tif: cannot decode (truncated or corrupt?): tile 1");
  // An in-memory view has nothing to fail.
  EXPECT_TRUE(check_texels_read(p.memory).has_value());
}

// A MIP-mapped file read through the cache has a source per level: a tile
// lost in a level above 0 fails the pass too (with that level's error),
// even when level 0 read well.
TEST(TiledImage, AFailedReadInAMipLevelFailsThePass) {
  Pair base = make_pair(200, 64, 10);
  Pair l1 = make_pair(100, 32, 11), l2 = make_pair(50, 16, 12);
  l2.tiles->bad_tile_x = 1;
  const ImageView levels[] = {l1.tiled, l2.tiled};
  ImageView view = base.tiled;
  view.mip_levels = levels;
  view.mip_level_count = 2;
  (void)view.texel(5, 5);
  (void)levels[0].texel(5, 5);
  EXPECT_TRUE(check_texels_read(view).has_value());  // nothing failed yet
  EXPECT_TRUE(same_bits(levels[1].texel(TileSource::kTileSize + 1, 3), Rgba{0, 0, 0, 0}));
  const Status s = check_texels_read(view);
  ASSERT_FALSE(s.has_value());
  EXPECT_EQ(s.error().code, ErrorCode::kParse);
  EXPECT_EQ(s.error().message, "tiles.tif: cannot decode (truncated or corrupt?): tile 1");
  // An in-memory level 0 with a failed tiled level fails as well.
  ImageView memory = base.memory;
  memory.mip_levels = levels;
  memory.mip_level_count = 2;
  EXPECT_FALSE(check_texels_read(memory).has_value());
}

}  // namespace
}  // namespace texbake
