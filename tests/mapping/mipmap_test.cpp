// The MIP pyramid (exact box filter) and the EWA lookup of mapping/mipmap.h:
// levels by hand, a constant image returns that constant exactly, a
// magnified ramp is the bilinear lookup, a minified checkerboard converges to
// its mean, and a footprint straddling the u seam averages both sides.
#include "mapping/mipmap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "mapping/sample.h"

namespace texbake {
namespace {

struct TestImage {
  int width = 0, height = 0;
  std::vector<float> pixels;
  ImageView view() const { return {width, height, pixels.data()}; }
};

template <class F>
TestImage make_image(int w, int h, F&& red) {
  TestImage img{w, h, {}};
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float r = red(x, y);
      img.pixels.insert(img.pixels.end(), {r, 1 - r, 0.25f, 1});
    }
  }
  return img;
}

TEST(MipPyramid, EvenLevelsByHand) {
  // 4 x 2, red: top row 0 10 20 30, bottom row 100 110 120 130.
  const float red[2][4] = {{0, 10, 20, 30}, {100, 110, 120, 130}};
  const TestImage img = make_image(4, 2, [&](int x, int y) { return red[y][x]; });
  const MipPyramid mip(img.view());
  ASSERT_EQ(mip.levels(), 3);
  EXPECT_EQ(mip.level(1).width, 2);
  EXPECT_EQ(mip.level(1).height, 1);
  // (0 + 10 + 100 + 110) / 4 = 55, (20 + 30 + 120 + 130) / 4 = 75, then 65.
  EXPECT_EQ(mip.level(1).pixel(0, 0)[0], 55);
  EXPECT_EQ(mip.level(1).pixel(1, 0)[0], 75);
  EXPECT_EQ(mip.level(2).pixel(0, 0)[0], 65);
  EXPECT_EQ(mip.level(2).pixel(0, 0)[2], 0.25f);
  EXPECT_EQ(mip.level(0).data, img.pixels.data());  // level 0 is the image, not a copy
  // Levels 1 and 2, and the row means of all three levels (2 + 1 + 1 rows),
  // each computed when first asked for: (0 + 10 + 20 + 30) / 4 = 15,
  // (100 + ... + 130) / 4 = 115, then 65 and 65.
  EXPECT_EQ(mip.owned_bytes(), (2 + 1) * 4 * sizeof(float) + (2 + 1 + 1) * 4 * sizeof(double));
  EXPECT_EQ(mip.row_mean(0, 0)[0], 15);
  EXPECT_EQ(mip.row_mean(0, 1)[0], 115);
  EXPECT_EQ(mip.row_mean(1, 0)[0], 65);
  EXPECT_EQ(mip.row_mean(2, 0)[0], 65);
  EXPECT_FALSE(mip.given_levels());
}

// A MIP-mapped file's own levels (ImageView::mip_levels) are viewed as they
// are, not recomputed: here levels deliberately unlike the box reduction
// (a constant 0.25 red over a 0 / 1 checkerboard whose mean is 0.5), so
// every lookup that reaches them tells which pyramid it read.
TEST(MipPyramid, GivenLevelsAreUsedAsTheyAre) {
  const TestImage img =
      make_image(16, 8, [](int x, int y) { return static_cast<float>((x + y) % 2); });
  std::vector<TestImage> given;
  for (int w = 8, h = 4; w >= 1; w /= 2, h = std::max(1, h / 2)) {
    given.push_back(make_image(w, h, [](int, int) { return 0.25f; }));
  }
  std::vector<ImageView> views;
  for (const TestImage& g : given) views.push_back(g.view());
  ImageView base = img.view();
  base.mip_levels = views.data();
  base.mip_level_count = static_cast<int>(views.size());
  const MipPyramid mip(base);
  ASSERT_EQ(mip.levels(), 5);
  EXPECT_TRUE(mip.given_levels());
  for (int i = 1; i < 5; ++i) EXPECT_EQ(mip.level(i).data, given[i - 1].pixels.data()) << i;
  EXPECT_EQ(mip.level(0).mip_level_count, 0);
  // Only the row means are its own (8 + 4 + 2 + 1 + 1 rows).
  EXPECT_EQ(mip.owned_bytes(), (8 + 4 + 2 + 1 + 1) * 4 * sizeof(double));
  // Row means: level 0's from the checkerboard (0.5), level 2's from its own texels.
  EXPECT_EQ(mip.row_mean(0, 3)[0], 0.5);
  EXPECT_EQ(mip.row_mean(2, 1)[0], 0.25);
  // A footprint of exactly 4 level-0 texels a side: lod 2, level 2 alone.
  const UvFootprint four{{4.0 / 16, 0}, {0, 4.0 / 8}};
  for (WrapMode wu : {WrapMode::kClamp, WrapMode::kRepeat}) {
    const Rgba r = sample_ewa(mip, {0.4, 0.6}, four, wu, WrapMode::kClamp);
    EXPECT_EQ(r[0], 0.25f);
    EXPECT_EQ(r[1], 0.75f);
  }
  // The same image without its levels reduces the checkerboard: 0.5.
  const MipPyramid built(img.view());
  EXPECT_FALSE(built.given_levels());
  EXPECT_EQ(sample_ewa(built, {0.4, 0.6}, four, WrapMode::kClamp, WrapMode::kClamp)[0], 0.5f);
  // A view whose texels are transformed as they load (decode_srgb,
  // premultiply) cannot use levels made from the stored values.
  ImageView transformed = base;
  transformed.decode_srgb = true;
  EXPECT_FALSE(MipPyramid(transformed).given_levels());
  transformed.decode_srgb = false;
  transformed.premultiply = true;
  EXPECT_FALSE(MipPyramid(transformed).given_levels());
}

TEST(MipPyramid, OddLevelsAreExactBoxes) {
  // 5 x 1, red 0 1 2 3 4 -> 2 texels of 2.5 inputs each:
  // [0, 2.5): (0 + 1 + 0.5 * 2) / 2.5 = 0.8; [2.5, 5): (0.5 * 2 + 3 + 4) / 2.5 = 3.2; then 2.
  const TestImage img = make_image(5, 1, [](int x, int) { return static_cast<float>(x); });
  const MipPyramid mip(img.view());
  ASSERT_EQ(mip.levels(), 3);
  EXPECT_FLOAT_EQ(mip.level(1).pixel(0, 0)[0], 0.8f);
  EXPECT_FLOAT_EQ(mip.level(1).pixel(1, 0)[0], 3.2f);
  EXPECT_FLOAT_EQ(mip.level(2).pixel(0, 0)[0], 2.0f);
  // 37 x 23 -> 18x11 -> 9x5 -> 4x2 -> 2x1 -> 1x1.
  const TestImage odd = make_image(37, 23, [](int x, int y) { return 0.01f * x + 0.02f * y; });
  const MipPyramid m2(odd.view());
  ASSERT_EQ(m2.levels(), 6);
  EXPECT_EQ(m2.level(3).width, 4);
  EXPECT_EQ(m2.level(3).height, 2);
  // The top texel is the image's mean: 0.01 * 18 + 0.02 * 11 = 0.4.
  EXPECT_NEAR(m2.level(5).pixel(0, 0)[0], 0.4, 1e-6);
}

TEST(MipPyramid, RowChunkingDoesNotChangeIt) {
  // Rows run in chunks of 3, last chunk first: the same bits as serially.
  const TestImage img =
      make_image(37, 23, [](int x, int y) { return std::sin(0.7 * x + 0.3 * y); });
  const MipPyramid serial(img.view());
  const MipPyramid chunked(img.view(), [](std::size_t n, const auto& body) {
    for (std::size_t end = n; end > 0;) {
      const std::size_t begin = end >= 3 ? end - 3 : 0;
      body(begin, end);
      end = begin;
    }
  });
  ASSERT_EQ(serial.levels(), chunked.levels());
  for (int i = 0; i < serial.levels(); ++i) {
    const ImageView a = serial.level(i), b = chunked.level(i);
    for (int k = 0; k < a.width * a.height * 4; ++k) ASSERT_EQ(a.data[k], b.data[k]) << i;
    for (int y = 0; y < a.height; ++y) {
      for (int c = 0; c < 4; ++c) ASSERT_EQ(serial.row_mean(i, y)[c], chunked.row_mean(i, y)[c]);
    }
  }
}

TEST(Ewa, ConstantImageGivesTheConstantExactly) {
  const float c[4] = {0.3f, 0.7123f, 0.1f, 0.9f};
  TestImage img{37, 23, {}};
  for (int i = 0; i < 37 * 23; ++i) img.pixels.insert(img.pixels.end(), c, c + 4);
  const MipPyramid mip(img.view());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    const UV uv{uni(rng) * 1.4 - 0.2, uni(rng) * 1.4 - 0.2};
    // From a fraction of a texel to several image widths, any direction and eccentricity.
    const double scale = std::pow(10.0, uni(rng) * 5 - 3.5);
    const UvFootprint f{{(uni(rng) - 0.5) * scale, (uni(rng) - 0.5) * scale},
                        {(uni(rng) - 0.5) * scale * uni(rng), (uni(rng) - 0.5) * scale}};
    const WrapMode wu = trial % 2 ? WrapMode::kRepeat : WrapMode::kClamp;
    const Rgba r = sample_ewa(mip, uv, f, wu, WrapMode::kClamp);
    for (int k = 0; k < 4; ++k) ASSERT_EQ(r[k], c[k]) << trial << " scale " << scale;
  }
}

TEST(Ewa, MagnifiedRampIsTheBilinearLookup) {
  // A linear ramp; footprints up to one texel give sample_bilinear exactly.
  const TestImage img = make_image(64, 32, [](int x, int y) { return 0.01f * x + 0.003f * y; });
  const MipPyramid mip(img.view());
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int trial = 0; trial < 500; ++trial) {
    const UV uv{uni(rng), uni(rng)};
    // Major axis at most 1 texel: |a| <= 1 / 64 in u (1 / 32 in v).
    const double len = uni(rng) / std::sqrt(2.0);
    const UvFootprint f{{len / 64, len / 32}, {-len / 64 * uni(rng), len / 32 * uni(rng)}};
    for (WrapMode wu : {WrapMode::kClamp, WrapMode::kRepeat}) {
      const Rgba e = sample_ewa(mip, uv, f, wu, WrapMode::kClamp);
      const Rgba b = sample_bilinear(img.view(), uv, wu, WrapMode::kClamp);
      for (int k = 0; k < 4; ++k) ASSERT_EQ(e[k], b[k]);
    }
    // And the ramp's value itself (inside, away from the clamped border).
    const UV inner{0.1 + 0.8 * uv.u, 0.1 + 0.8 * uv.v};
    const PixelPos p = pixel_from_uv(inner, 64, 32);
    EXPECT_NEAR(sample_ewa(mip, inner, f, WrapMode::kClamp, WrapMode::kClamp)[0],
                0.01 * p.x + 0.003 * p.y, 1e-6);
  }
}

TEST(Ewa, MinifiedCheckerboardConvergesToItsMean) {
  // 3-texel squares on 384 x 384 (128 x 128 squares): the mean is exactly 0.5,
  // and no box level is flat (3 does not divide a power of 2).
  const TestImage img =
      make_image(384, 384, [](int x, int y) { return ((x / 3 + y / 3) % 2) ? 1.0f : 0.0f; });
  const MipPyramid mip(img.view());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(0, 1);
  double worst_fine = 0, worst_coarse = 0, worst_bilinear = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const UV uv{0.2 + 0.6 * uni(rng), 0.2 + 0.6 * uni(rng)};
    const double angle = uni(rng) * 6.283;
    const Vec2 dir{std::cos(angle), std::sin(angle)}, across{-dir.y, dir.x};
    auto err = [&](double texels) {
      const double s = texels / 384;
      return std::abs(sample_ewa(mip, uv, {dir * s, across * (s * (0.5 + 0.5 * uni(rng)))},
                                 WrapMode::kRepeat, WrapMode::kClamp)[0] -
                      0.5);
    };
    worst_fine = std::max(worst_fine, err(12));
    worst_coarse = std::max(worst_coarse, err(96));
    worst_bilinear = std::max(
        worst_bilinear,
        std::abs(sample_bilinear(img.view(), uv, WrapMode::kRepeat, WrapMode::kClamp)[0] - 0.5));
  }
  EXPECT_GT(worst_bilinear, 0.49);  // one tap: black or white
  EXPECT_LT(worst_fine, 0.02);      // 4 squares under the footprint (measured 0.0065)
  EXPECT_LT(worst_coarse, 0.001);   // 32 squares (measured 1.1e-4)
  EXPECT_LT(worst_coarse, worst_fine);
}

TEST(Ewa, FootprintStraddlingTheSeamAveragesBothSides) {
  // 256 x 64: red 0 on the left half, 1 on the right half.
  const TestImage img = make_image(256, 64, [](int x, int) { return x < 128 ? 0.0f : 1.0f; });
  const MipPyramid mip(img.view());
  // 16 texels wide in u, 2 tall in v, centred on the seam u = 0.
  const UvFootprint f{{16.0 / 256, 0}, {0, 2.0 / 64}};
  // Periodic: texel centres pair up across x = -0.5 (x = -1 - k wraps to the
  // right half's 1, x = k is the left half's 0) with equal weights.
  EXPECT_NEAR(sample_ewa(mip, {0, 0.5}, f, WrapMode::kRepeat, WrapMode::kClamp)[0], 0.5, 1e-6);
  EXPECT_NEAR(sample_ewa(mip, {1, 0.5}, f, WrapMode::kRepeat, WrapMode::kClamp)[0], 0.5, 1e-6);
  // Clamped, the left edge texel (0) stands in for everything left of it.
  EXPECT_EQ(sample_ewa(mip, {0, 0.5}, f, WrapMode::kClamp, WrapMode::kClamp)[0], 0);
  // Off-centre but straddling: some of each side, less of the far one.
  const float off = sample_ewa(mip, {4.0 / 256, 0.5}, f, WrapMode::kRepeat, WrapMode::kClamp)[0];
  EXPECT_GT(off, 0.05);
  EXPECT_LT(off, 0.45);
  // The same edge inside the image (u = 0.5) in either mode.
  EXPECT_NEAR(sample_ewa(mip, {0.5, 0.5}, f, WrapMode::kClamp, WrapMode::kClamp)[0], 0.5, 1e-6);
}

TEST(Ewa, PoleFootprintSpansEveryUButOnlyTheTopRows) {
  // 256 x 128: red = row / 127 (0 in the top row, v = 1), green alternates
  // by column (every row's mean is 0.5).
  TestImage img{256, 128, {}};
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 256; ++x) {
      img.pixels.insert(img.pixels.end(), {y / 127.0f, static_cast<float>(x % 2), 0.25f, 1});
    }
  }
  const MipPyramid mip(img.view());
  // The footprint at a pole (bake/shade/footprint.h): one whole period in
  // u, 2 texels in v. Every column counts (green exactly 0.5) and only the
  // top few rows (red = row / 127 stays below 3 rows' worth); the eccentricity
  // clamp alone would blur v by 256 / 8 = 32 texels.
  const UvFootprint pole{{1, 0}, {0, 2.0 / 128}};
  const Rgba r = sample_ewa(mip, {0, 1}, pole, WrapMode::kRepeat, WrapMode::kClamp);
  EXPECT_NEAR(r[1], 0.5, 1e-7);
  EXPECT_LT(r[0], 3 / 127.0);
  EXPECT_EQ(sample_ewa(mip, {0.37, 1}, pole, WrapMode::kRepeat, WrapMode::kClamp), r);  // any u
  // Growing the u extent from a third of the period to past a whole one
  // changes the result continuously (the blend between a half and a whole
  // period).
  Rgba previous =
      sample_ewa(mip, {0.2, 0.98}, {{0.3, 0}, {0, 2.0 / 128}}, WrapMode::kRepeat, WrapMode::kClamp);
  for (double k = 0.305; k <= 1.2; k += 0.005) {
    const Rgba now =
        sample_ewa(mip, {0.2, 0.98}, {{k, 0}, {0, 2.0 / 128}}, WrapMode::kRepeat, WrapMode::kClamp);
    EXPECT_LT(std::abs(now[0] - previous[0]), 0.01) << k;
    previous = now;
  }
  EXPECT_LT(previous[0], 4 / 127.0);
}

TEST(Ewa, FarAndNonFiniteCoordinatesStayDefined) {
  // Rows vary, columns do not: past the right edge (clamped) only v matters.
  const TestImage img = make_image(64, 32, [](int, int y) { return y / 31.0f; });
  const MipPyramid mip(img.view());
  const UvFootprint f{{3.0 / 64, 0}, {0, 3.0 / 32}};
  const Rgba near = sample_ewa(mip, {1.5, 0.4}, f, WrapMode::kClamp, WrapMode::kClamp);
  EXPECT_EQ(sample_ewa(mip, {1e30, 0.4}, f, WrapMode::kClamp, WrapMode::kClamp), near);
  EXPECT_EQ(sample_ewa(mip, {-1e300, 0.4}, f, WrapMode::kClamp, WrapMode::kClamp), near);
  // Periodic: whole periods away is the same lookup.
  const TestImage ramp = make_image(64, 32, [](int x, int y) { return 0.01f * x + 0.02f * y; });
  const MipPyramid mr(ramp.view());
  EXPECT_EQ(sample_ewa(mr, {5.25, 0.4}, f, WrapMode::kRepeat, WrapMode::kClamp),
            sample_ewa(mr, {0.25, 0.4}, f, WrapMode::kRepeat, WrapMode::kClamp));
  EXPECT_EQ(sample_ewa(mr, {-3.75, 0.4}, f, WrapMode::kRepeat, WrapMode::kClamp),
            sample_ewa(mr, {0.25, 0.4}, f, WrapMode::kRepeat, WrapMode::kClamp));
  const Rgba nan = sample_ewa(mr, {std::nan(""), 0.4}, f, WrapMode::kRepeat, WrapMode::kClamp);
  for (float c : nan) EXPECT_TRUE(std::isfinite(c));
}

TEST(Ewa, UnboundedFootprintIsTheImageMean) {
  // A non-finite footprint (a pole's u extent) counts as the widest: the top
  // level, the image's mean (0.25 here: a quarter of the texels are 1).
  const TestImage img =
      make_image(64, 16, [](int x, int y) { return (x < 32 && y < 8) ? 1.0f : 0.0f; });
  const MipPyramid mip(img.view());
  const double inf = std::numeric_limits<double>::infinity();
  const Rgba r =
      sample_ewa(mip, {0.3, 0.9}, {{inf, inf}, {inf, 0}}, WrapMode::kRepeat, WrapMode::kClamp);
  EXPECT_NEAR(r[0], 0.25, 1e-7);
}

}  // namespace
}  // namespace texbake
