// compare_images on in-memory RGBA views: the alpha-based background mask.
// Expected figures worked out by hand from the pixel values below.
#include "mesh_io/image_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace texbake {
namespace {

ImageView view_of(const std::vector<float>& px, int w, int h) {
  return {w, h, px.data()};
}

// 2x2 RGBA. Pixel order: (0,0) (1,0) (0,1) (1,1).
// A: grey fg, red fg, bg, bg.   B: grey fg, bg, black bg (alpha 0), bg.
const std::vector<float> kA = {0.5f, 0.5f, 0.5f,  1, 1.0f, 0.0f, 0.0f,  1,
                               0.3f, 0.3f, 0.35f, 0, 0.3f, 0.3f, 0.35f, 0};
const std::vector<float> kB = {0.5f, 0.5f, 0.5f, 1, 0.3f, 0.3f, 0.35f, 0,
                               0.0f, 0.0f, 0.0f, 0, 0.3f, 0.3f, 0.35f, 0};

TEST(ImageCompare, MaskKeepsPixelsThatAreForegroundInEitherImage) {
  CompareOptions options;
  options.mask_background = true;
  auto r = compare_images(view_of(kA, 2, 2), view_of(kB, 2, 2), options);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  // Pixels (0,0) and (1,0) count; (0,1) differs in RGB but is alpha 0 in both.
  EXPECT_EQ(r->compared_pixels, 2u);
  EXPECT_EQ(r->channels, 4);
  // (1,0) differs by (0.7, 0.3, 0.35, 1): squares sum to 1.7025 over 2 pixels
  // x 4 channels: MSE = 0.2128125, PSNR = -10 log10(MSE) = 6.71997 dB.
  EXPECT_NEAR(r->psnr, -10 * std::log10(1.7025 / 8), 1e-4);
  EXPECT_NEAR(r->max_difference, 1.0, 1e-6);
  EXPECT_EQ(r->max_x, 1);
  EXPECT_EQ(r->max_y, 0);
  EXPECT_EQ(r->max_channel, 3);
}

TEST(ImageCompare, WithoutMaskBackgroundDifferencesCount) {
  auto r = compare_images(view_of(kA, 2, 2), view_of(kB, 2, 2), CompareOptions{});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(r->compared_pixels, 4u);
  // Adds (0,1)'s (0.3, 0.3, 0.35, 0): 0.3025; total 2.005 over 16 values.
  EXPECT_NEAR(r->psnr, 10 * std::log10(16 / 2.005), 1e-4);
}

TEST(ImageCompare, AllBackgroundComparesNothingAndIsInfinite) {
  CompareOptions options;
  options.mask_background = true;
  const std::vector<float> bg = {0, 0, 0, 0, 1, 1, 1, 0};
  const std::vector<float> other = {1, 0, 0, 0, 0, 1, 0, 0};
  auto r = compare_images(view_of(bg, 2, 1), view_of(other, 2, 1), options);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(r->compared_pixels, 0u);
  EXPECT_TRUE(std::isinf(r->psnr));
}

TEST(ImageCompare, SizeMismatchIsAnError) {
  const std::vector<float> px(16, 0.0f);
  auto r = compare_images(view_of(px, 2, 2), view_of(px, 4, 1), CompareOptions{});
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().code, ErrorCode::kParse);
  EXPECT_NE(r.error().message.find("2x2 and 4x1"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace texbake
