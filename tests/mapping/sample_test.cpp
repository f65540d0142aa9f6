// Bilinear sampling (SPEC section 1) on small hand-made images. Each
// expectation is worked out by hand from x = u*W - 0.5, y = (1-v)*H - 0.5.
#include "mapping/sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <type_traits>
#include <vector>

namespace texbake {
namespace {

// 4 x 2 image, stored top row first. Red: top row 0 10 20 30, bottom row
// 100 110 120 130; green = 2 * red; blue 7; alpha 1.
class FourByTwo : public testing::Test {
 protected:
  FourByTwo() {
    const float red[2][4] = {{0, 10, 20, 30}, {100, 110, 120, 130}};
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 4; ++x) {
        pixels_.insert(pixels_.end(), {red[y][x], 2 * red[y][x], 7, 1});
      }
    }
    view_ = {4, 2, pixels_.data()};
  }
  float red(UV uv, WrapMode wu = WrapMode::kClamp, WrapMode wv = WrapMode::kClamp) const {
    return sample_bilinear(view_, uv, wu, wv)[0];
  }

  std::vector<float> pixels_;
  ImageView view_;
};

TEST_F(FourByTwo, TexelCentreGivesTheTexel) {
  // (0.375, 0.75): x = 1.5 - 0.5 = 1, y = 0.5 - 0.5 = 0: texel (1, 0).
  EXPECT_FLOAT_EQ(red({0.375, 0.75}), 10);
  // (0.875, 0.25): x = 3, y = 1: texel (3, 1).
  EXPECT_FLOAT_EQ(red({0.875, 0.25}), 130);
}

TEST_F(FourByTwo, InteriorInterpolatesAllChannels) {
  // (0.5, 0.5): x = 1.5, y = 0.5: (10 + 20 + 110 + 120) / 4 = 65.
  const Rgba c = sample_bilinear(view_, {0.5, 0.5}, WrapMode::kClamp, WrapMode::kClamp);
  EXPECT_FLOAT_EQ(c[0], 65);
  EXPECT_FLOAT_EQ(c[1], 130);
  EXPECT_FLOAT_EQ(c[2], 7);
  EXPECT_FLOAT_EQ(c[3], 1);
  // (0.3, 0.6): x = 0.7, y = 0.3: top 0 + 0.7*10 = 7, bottom 107,
  // 7 + 0.3*100 = 37.
  EXPECT_NEAR(red({0.3, 0.6}), 37, 1e-4);
}

TEST_F(FourByTwo, EdgesClampToTheEdgeTexel) {
  // (0, 0.75): x = -0.5, both columns clamp to 0: 0.
  EXPECT_FLOAT_EQ(red({0, 0.75}), 0);
  // (1, 1): x = 3.5, y = -0.5: texel (3, 0) = 30.
  EXPECT_FLOAT_EQ(red({1, 1}), 30);
  // Half a texel in from the right edge on the bottom row: (0.875, 0) y = 1.5 -> 130.
  EXPECT_FLOAT_EQ(red({0.875, 0}), 130);
}

TEST_F(FourByTwo, URepeatsAcrossTheSeam) {
  // (0, 0.75): x = -0.5 lies between column 3 (wrapped from -1) and 0:
  // 0.5*30 + 0.5*0 = 15; u = 1 (x = 3.5) lands on the same blend.
  EXPECT_FLOAT_EQ(red({0, 0.75}, WrapMode::kRepeat), 15);
  EXPECT_FLOAT_EQ(red({1, 0.75}, WrapMode::kRepeat), 15);
  // (0.05, 0.75): x = -0.3, columns 3 and 0 with fx = 0.7: 30 - 0.7*30 = 9.
  EXPECT_NEAR(red({0.05, 0.75}, WrapMode::kRepeat), 9, 1e-5);
  // One period further away gives the same colour.
  EXPECT_NEAR(red({-0.95, 0.75}, WrapMode::kRepeat), 9, 1e-4);
  EXPECT_NEAR(red({2.05, 0.75}, WrapMode::kRepeat), 9, 1e-4);
}

TEST_F(FourByTwo, VClampsAtZeroAndOne) {
  // v = 0: y = 1.5, rows 1 and (clamped) 1: 110 at x = 1.
  EXPECT_FLOAT_EQ(red({0.375, 0}), 110);
  // v = 1: y = -0.5, rows (clamped) 0 and 0: 10.
  EXPECT_FLOAT_EQ(red({0.375, 1}), 10);
  // Far outside still clamps.
  EXPECT_FLOAT_EQ(red({0.375, -40}), 110);
  EXPECT_FLOAT_EQ(red({0.375, 1e300}), 10);
  // Repeat in v would blend rows 1 and 0 at v = 0: (110 + 10)/2.
  EXPECT_FLOAT_EQ(red({0.375, 0}, WrapMode::kClamp, WrapMode::kRepeat), 60);
}

TEST(SampleBilinear, OneByOneImageIsOneColour) {
  const float pixel[4] = {0.25f, 0.5f, 0.75f, 1.0f};
  const ImageView view{1, 1, pixel};
  for (UV uv : {UV{0, 0}, UV{1, 1}, UV{0.5, 0.5}, UV{-3.2, 7.9}, UV{0.999, 0.001}}) {
    for (WrapMode mode : {WrapMode::kClamp, WrapMode::kRepeat}) {
      const Rgba c = sample_bilinear(view, uv, mode, mode);
      EXPECT_EQ(c[0], 0.25f);
      EXPECT_EQ(c[1], 0.5f);
      EXPECT_EQ(c[2], 0.75f);
      EXPECT_EQ(c[3], 1.0f);
    }
  }
}

TEST(SampleBilinear, NonFiniteUvDoesNotCrash) {
  const float pixels[8] = {1, 1, 1, 1, 3, 3, 3, 1};
  const ImageView view{2, 1, pixels};
  const Rgba c = sample_bilinear(view, {std::nan(""), 0.5}, WrapMode::kRepeat, WrapMode::kClamp);
  EXPECT_TRUE(std::isfinite(c[0]));
}

TEST(Srgb, KnownValuesAndRoundTrip) {
  // ((0.5 + 0.055)/1.055)^2.4 = 0.2140411 (by hand: exp(2.4 ln 0.526066)).
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.2140411f, 1e-6);
  EXPECT_NEAR(linear_to_srgb(0.2140411f), 0.5f, 1e-6);
  EXPECT_EQ(srgb_to_linear(0.0f), 0.0f);
  EXPECT_NEAR(srgb_to_linear(1.0f), 1.0f, 1e-6);
  // Linear segment: 0.02 / 12.92.
  EXPECT_NEAR(srgb_to_linear(0.02f), 0.02f / 12.92f, 1e-9);
  // The two pieces meet: 0.04045 / 12.92 = 0.0031308.
  EXPECT_NEAR(srgb_to_linear(0.04045f), 0.0031308f, 1e-7);
  for (int i = 0; i <= 1000; ++i) {
    const float c = i / 1000.0f;
    EXPECT_NEAR(linear_to_srgb(srgb_to_linear(c)), c, 2e-6) << c;
  }
}

// The 8-bit values (b / 255 and b * (1 / 255), the two ways readers
// decode a byte) go through a table: the same bits as SPEC section 1's
// formula, evaluated here in float as it is written; values between them,
// the signed zeros, values out of [0, 1] and NaN through the formula too.
TEST(Srgb, EightBitValuesAreTheFormulasBitForBit) {
  const auto formula = [](float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  };
  const auto same_bits = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (int b = 0; b < 256; ++b) {
    for (const float c : {static_cast<float>(b) / 255.0f, static_cast<float>(b) * (1.0f / 255.0f),
                          std::nextafter(static_cast<float>(b) / 255.0f, 2.0f),
                          std::nextafter(static_cast<float>(b) / 255.0f, -1.0f)}) {
      EXPECT_TRUE(same_bits(srgb_to_linear(c), formula(c))) << b << " " << c;
    }
  }
  for (const float c : {0.0f, -0.0f, -0.5f, 1.5f, 1e-30f, 0.999999f}) {
    EXPECT_TRUE(same_bits(srgb_to_linear(c), formula(c))) << c;
  }
  EXPECT_TRUE(std::signbit(srgb_to_linear(-0.0f)));
  EXPECT_TRUE(std::isnan(srgb_to_linear(std::nanf(""))));
}

TEST(Srgb, ColourFormsConvertRgbAndNeverAlpha) {
  const Rgba lin = srgb_to_linear(Rgba{0.5f, 1.f, 0.02f, 0.5f});
  EXPECT_NEAR(lin[0], 0.2140411f, 1e-6);
  EXPECT_NEAR(lin[1], 1.f, 1e-6);
  EXPECT_NEAR(lin[2], 0.02f / 12.92f, 1e-9);
  EXPECT_EQ(lin[3], 0.5f);
  const Rgba back = linear_to_srgb(Rgba{0.2140411f, 0.f, 0.02f / 12.92f, 0.25f});
  EXPECT_NEAR(back[0], 0.5f, 1e-6);
  EXPECT_EQ(back[1], 0.f);
  EXPECT_NEAR(back[2], 0.02f, 1e-7);
  EXPECT_EQ(back[3], 0.25f);
}

TEST(Vec2, ArithmeticDotAndCross) {
  constexpr Vec2 a{1, 2}, b{3, -4};
  static_assert(a + b == Vec2{4, -2});
  static_assert(a - b == Vec2{-2, 6});
  static_assert(a * 2 == Vec2{2, 4});
  static_assert(dot(a, b) == 3 - 8);
  static_assert(cross(a, b) == 1 * -4 - 2 * 3);  // clockwise from a to b: negative
  static_assert(cross(Vec2{1, 0}, Vec2{0, 1}) == 1);
  // A pixel position is a Vec2 (one 2-D type).
  static_assert(std::is_same_v<PixelPos, Vec2>);
  EXPECT_EQ(pixel_from_uv({0.5, 0.5}, 4, 2), (PixelPos{1.5, 0.5}));
}

}  // namespace
}  // namespace texbake
