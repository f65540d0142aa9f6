// Gutter padding: ring dilation and push-pull, against hand-computed values.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "bake/atlas/dilate.h"
#include "bake/util/parallel.h"

namespace texbake {
namespace {

constexpr float kUnset = -7;  // sentinel for texels that must stay untouched

struct Img {
  int w, h;
  std::vector<float> rgba;
  std::vector<uint8_t> baked;
  Img(int w_, int h_) : w(w_), h(h_), rgba(w_ * h_ * 4, kUnset), baked(w_ * h_, 0) {}
  void set(int x, int y, float v) {
    for (int c = 0; c < 4; ++c) rgba[(y * w + x) * 4 + c] = v;
    baked[y * w + x] = 1;
  }
  float at(int x, int y, int c = 0) const { return rgba[(y * w + x) * 4 + c]; }
};

TEST(AtlasDilate, DefaultPaddingScalesWithSize) {
  EXPECT_EQ(default_padding(2048), 8);
  EXPECT_EQ(default_padding(4096), 16);
  EXPECT_EQ(default_padding(1024), 4);
  EXPECT_EQ(default_padding(512), 2);
  EXPECT_EQ(default_padding(256), 1);    // 8 * 256 / 2048 = 1
  EXPECT_EQ(default_padding(16), 1);     // 0.0625 rounds to 0, at least 1
  EXPECT_EQ(default_padding(3000), 12);  // 11.72 rounds to 12
}

// 5 x 1: baked 0.2 at x = 0 and 1.0 at x = 4. Pass 1 fills x = 1 (0.2) and
// x = 3 (1.0); pass 2 fills x = 2 with their mean 0.6.
TEST(AtlasDilate, RowHandComputed) {
  Img img(5, 1);
  img.set(0, 0, 0.2f);
  img.set(4, 0, 1.0f);
  EXPECT_EQ(dilate(img.rgba, img.baked, 5, 1, 1), 2u);
  EXPECT_FLOAT_EQ(img.at(1, 0), 0.2f);
  EXPECT_FLOAT_EQ(img.at(3, 0), 1.0f);
  EXPECT_EQ(img.at(2, 0), kUnset);
  EXPECT_EQ(img.baked[2], 0);
  EXPECT_EQ(dilate(img.rgba, img.baked, 5, 1, 5), 1u);
  EXPECT_FLOAT_EQ(img.at(2, 0), 0.6f);
  EXPECT_FLOAT_EQ(img.at(0, 0), 0.2f);
  EXPECT_FLOAT_EQ(img.at(4, 0), 1.0f);
}

// 3 x 3, baked (0,0) = 1, (2,0) = 0, (0,2) = 0.5. Pass 1 (8-neighbours
// baked before the pass): (1,0) = (1+0)/2, (0,1) = (1+0.5)/2,
// (1,1) = (1+0+0.5)/3, (2,1) = 0, (1,2) = 0.5; (2,2) has none. Pass 2:
// (2,2) = ((1,1) + (2,1) + (1,2)) / 3 = (0.5 + 0 + 0.5) / 3.
TEST(AtlasDilate, EightNeighbourhoodHandComputed) {
  Img img(3, 3);
  img.set(0, 0, 1.0f);
  img.set(2, 0, 0.0f);
  img.set(0, 2, 0.5f);
  EXPECT_EQ(dilate(img.rgba, img.baked, 3, 3, 1), 5u);
  EXPECT_FLOAT_EQ(img.at(1, 0), 0.5f);
  EXPECT_FLOAT_EQ(img.at(0, 1), 0.75f);
  EXPECT_FLOAT_EQ(img.at(1, 1), 0.5f);
  EXPECT_FLOAT_EQ(img.at(2, 1), 0.0f);
  EXPECT_FLOAT_EQ(img.at(1, 2), 0.5f);
  EXPECT_EQ(img.at(2, 2), kUnset);
  EXPECT_EQ(dilate(img.rgba, img.baked, 3, 3, 1), 1u);
  EXPECT_FLOAT_EQ(img.at(2, 2), 1.0f / 3);
  // All four channels alike; baked texels unchanged.
  EXPECT_FLOAT_EQ(img.at(2, 2, 3), 1.0f / 3);
  EXPECT_FLOAT_EQ(img.at(0, 0), 1.0f);
  EXPECT_FLOAT_EQ(img.at(0, 2), 0.5f);
}

// 4 x 4, baked (0,0) = 1 and (3,3) = 0. Pull: level 1 (2 x 2) =
// [[1, -], [-, 0]], level 2 (1 x 1) = 0.5. Push: level 1 holes = 0.5.
// Level 0 holes = bilinear of level 1 [[1, .5], [.5, 0]] at
// ((x + .5)/2 - .5, (y + .5)/2 - .5), edges clamped:
//   (1,0): (0.25, -0.25) -> row 0: 1 + 0.25 (0.5 - 1) = 0.875
//   (1,1): (0.25, 0.25)  -> 0.875 + 0.25 (0.375 - 0.875) = 0.75
//   (2,1): (0.75, 0.25)  -> 0.625 + 0.25 (0.125 - 0.625) = 0.5
//   (0,3): (-0.25, 1.25) -> column 0, row 1: 0.5
//   (3,0): (1.25, -0.25) -> column 1, row 0: 0.5
TEST(AtlasDilate, PushPullHandComputed) {
  Img img(4, 4);
  img.set(0, 0, 1.0f);
  img.set(3, 3, 0.0f);
  EXPECT_EQ(push_pull_fill(img.rgba, img.baked, 4, 4), 14u);
  EXPECT_FLOAT_EQ(img.at(1, 0), 0.875f);
  EXPECT_FLOAT_EQ(img.at(1, 1), 0.75f);
  EXPECT_FLOAT_EQ(img.at(2, 1), 0.5f);
  EXPECT_FLOAT_EQ(img.at(0, 3), 0.5f);
  EXPECT_FLOAT_EQ(img.at(3, 0), 0.5f);
  EXPECT_FLOAT_EQ(img.at(0, 0), 1.0f);
  EXPECT_FLOAT_EQ(img.at(3, 3), 0.0f);
  // Symmetry of the set-up: (x, y) and (y, x) agree.
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_FLOAT_EQ(img.at(x, y), img.at(y, x));
}

TEST(AtlasDilate, PushPullNothingBakedLeavesImage) {
  Img img(3, 2);
  EXPECT_EQ(push_pull_fill(img.rgba, img.baked, 3, 2), 0u);
  for (float v : img.rgba) EXPECT_EQ(v, kUnset);
}

// About 5 % of the texels baked with random values in [0.25, 0.75].
Img random_sparse(int w, int h, unsigned seed) {
  Img img(w, h);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> val(0.25f, 0.75f), unit(0, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (unit(rng) < 0.05f) img.set(x, y, val(rng));
  return img;
}

// A larger odd-sized image with random baked texels: every hole is filled
// with a convex combination of baked values (within their range), baked
// texels are bit-identical, results do not depend on the thread count.
TEST(AtlasDilate, PushPullFillsEverythingWithinRangeAndIsDeterministic) {
  const int w = 77, h = 45;
  const Img img = random_sparse(w, h, 3);
  Img one = img, two = img, dil1 = img, dil2 = img;
  {
    ThreadLimit limit(1);
    push_pull_fill(one.rgba, one.baked, w, h);
    dilate(dil1.rgba, dil1.baked, w, h, 3);
  }
  {
    ThreadLimit limit(2);
    push_pull_fill(two.rgba, two.baked, w, h);
    dilate(dil2.rgba, dil2.baked, w, h, 3);
  }
  EXPECT_EQ(one.rgba, two.rgba);
  EXPECT_EQ(dil1.rgba, dil2.rgba);
  EXPECT_EQ(dil1.baked, dil2.baked);
  for (std::size_t i = 0; i < one.baked.size(); ++i) {
    for (int c = 0; c < 4; ++c) {
      const float v = one.rgba[i * 4 + c];
      if (img.baked[i]) {
        EXPECT_EQ(v, img.rgba[i * 4 + c]);
        EXPECT_EQ(dil1.rgba[i * 4 + c], img.rgba[i * 4 + c]);
      }
      EXPECT_GE(v, 0.25f);
      EXPECT_LE(v, 0.75f);
    }
  }
}

// The mip-safe push on the 4 x 4 set-up above (baked (0,0) = 1 and
// (3,3) = 0). Pull as before: level 1 [[1, -], [-, 0]] (weights 1, 0, 0,
// 1), level 2 = 0.5. Push: level-1 holes take the level-2 texel: 0.5.
// Level 0, each hole from its parent at level 1 (x / 2, y / 2):
//   (1,0): parent (0,0) holds data; bilinear corners at (0.25, -0.25)
//          clamp to (0,0) and (1,0), only (0,0) holds data: 1
//   (1,1): parent (0,0); corners at (0.25, 0.25): (0,0) weight 9/16 (1),
//          (1,1) weight 1/16 (0), the other two hold none: (9/16) / (10/16) = 0.9
//   (2,2): parent (1,1) = 0; at (0.75, 0.75): (0,0) 1/16 (1), (1,1) 9/16 (0): 0.1
//   (2,1), (3,0), (0,3): parents (1,0) / (0,1) hold no data: inherit 0.5
// Alpha of every filled texel: 0.
TEST(AtlasDilate, MipSafePushPullHandComputed) {
  Img img(4, 4);
  img.set(0, 0, 1.0f);
  img.set(3, 3, 0.0f);
  EXPECT_EQ(push_pull_fill(img.rgba, img.baked, 4, 4, PushPullMode::kMipSafe), 14u);
  EXPECT_FLOAT_EQ(img.at(1, 0), 1.0f);
  EXPECT_FLOAT_EQ(img.at(1, 1), 0.9f);
  EXPECT_FLOAT_EQ(img.at(2, 2), 0.1f);
  EXPECT_FLOAT_EQ(img.at(2, 1), 0.5f);
  EXPECT_FLOAT_EQ(img.at(3, 0), 0.5f);
  EXPECT_FLOAT_EQ(img.at(0, 3), 0.5f);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      if (img.baked[y * 4 + x]) {
        EXPECT_EQ(img.at(x, y, 3), img.at(x, y, 0));  // baked: untouched
      } else {
        EXPECT_EQ(img.at(x, y, 3), 0.f) << x << "," << y;
        EXPECT_FLOAT_EQ(img.at(x, y), img.at(y, x));  // the set-up's symmetry
      }
    }
  }
}

// Random odd-sized image as above: the mip-safe fill is deterministic and
// within the baked range, holes transparent.
TEST(AtlasDilate, MipSafePushPullWithinRangeAndDeterministic) {
  const int w = 77, h = 45;
  const Img img = random_sparse(w, h, 5);
  Img one = img, two = img;
  {
    ThreadLimit limit(1);
    push_pull_fill(one.rgba, one.baked, w, h, PushPullMode::kMipSafe);
  }
  {
    ThreadLimit limit(2);
    push_pull_fill(two.rgba, two.baked, w, h, PushPullMode::kMipSafe);
  }
  EXPECT_EQ(one.rgba, two.rgba);
  for (std::size_t i = 0; i < one.baked.size(); ++i) {
    for (int c = 0; c < 4; ++c) {
      const float v = one.rgba[i * 4 + c];
      if (img.baked[i]) {
        EXPECT_EQ(v, img.rgba[i * 4 + c]);
      } else if (c == 3) {
        EXPECT_EQ(v, 0.f);
      } else {
        EXPECT_GE(v, 0.25f);
        EXPECT_LE(v, 0.75f);
      }
    }
  }
}

}  // namespace
}  // namespace texbake
