// The shading rule (bake/shade/shade.h) for each map status, outside mode,
// wrap rule and occluded mode, on a 4 x 2 image; the sample patterns
// (bake/shade/sample_pattern.h). Every expected value is worked out by hand
// from SPEC section 1 (x = u*W - 0.5, y = (1 - v)*H - 0.5) and the IEC
// 61966-2-1 curves, written next to it.
#include "bake/shade/shade.h"

#include <gtest/gtest.h>

#include <vector>

#include "bake/shade/sample_pattern.h"

namespace texbake {
namespace {

// 4 x 2 image, top row first. Red: top row 0 .1 .2 .3, bottom row .4 .5 .6 .7;
// green .5, blue .25, alpha 1. x = 4u - 0.5, y = 1.5 - 2v.
std::vector<float> four_by_two() {
  const float red[2][4] = {{0.f, 0.1f, 0.2f, 0.3f}, {0.4f, 0.5f, 0.6f, 0.7f}};
  std::vector<float> px;
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) px.insert(px.end(), {red[y][x], 0.5f, 0.25f, 1.f});
  }
  return px;
}

Proxy unit_plane() {
  return make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).value();
}
Proxy unit_sphere() {
  return make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, {}}).value();
}

MapResult mapped(double u, double v, MapStatus status = MapStatus::kOk) {
  return {{u, v}, {0, 0, 1}, status};
}
MapResult unmapped() {
  return {{0, 0}, {0, 0, 1}, MapStatus::kUndefined};
}

class ShadeRuleTest : public testing::Test {
 protected:
  ShadeRule rule(const Proxy& proxy, const VertexBakeOptions& o = {}) const {
    return make_shade_rule(view_, proxy, o);
  }
  float red(const ShadeRule& r, const MapResult& m, Shade kind) const {
    const Shaded s = r.project(m);
    EXPECT_EQ(s.kind, kind);
    return s.color[0];
  }

  std::vector<float> pixels_ = four_by_two();
  ImageView view_{4, 2, pixels_.data()};
};

TEST_F(ShadeRuleTest, InsideTheDomainIsTheBilinearSample) {
  const ShadeRule r = rule(unit_plane());
  // (0.5, 0.5): x = 1.5, y = 0.5: (.1 + .2 + .5 + .6) / 4 = .35.
  const Shaded s = r.project(mapped(0.5, 0.5));
  EXPECT_EQ(s.kind, Shade::kImage);
  EXPECT_NEAR(s.color[0], 0.35f, 1e-6);
  EXPECT_NEAR(s.color[1], 0.5f, 1e-6);
  EXPECT_NEAR(s.color[2], 0.25f, 1e-6);
  EXPECT_NEAR(s.color[3], 1.f, 1e-6);
  // (0.375, 0.75): x = 1, y = 0: texel (1, 0) itself.
  EXPECT_FLOAT_EQ(red(r, mapped(0.375, 0.75), Shade::kImage), 0.1f);
}

TEST_F(ShadeRuleTest, UndefinedHasNoColour) {
  EXPECT_EQ(rule(unit_plane()).project(unmapped()).kind, Shade::kNone);
  EXPECT_EQ(rule(unit_sphere()).project(unmapped()).kind, Shade::kNone);
}

TEST_F(ShadeRuleTest, OutsideClampsToTheEdgeTexelOrTakesTheConstant) {
  const ShadeRule clamp = rule(unit_plane());
  // (1.5, 0.5): x = 5.5 -> column 3, y = 0.5: (.3 + .7) / 2 = .5.
  EXPECT_NEAR(red(clamp, mapped(1.5, 0.5, MapStatus::kOutside), Shade::kOutside), 0.5f, 1e-6);
  // (0.25, -1): x = 0.5, y = 3.5 -> row 1: (.4 + .5) / 2 = .45.
  EXPECT_NEAR(red(clamp, mapped(0.25, -1, MapStatus::kOutside), Shade::kOutside), 0.45f, 1e-6);

  VertexBakeOptions o;
  o.outside = OutsideMode::kColor;
  o.outside_color = {1, 0, 0.5f, 0.25f};
  const ShadeRule constant = rule(unit_plane(), o);
  const Shaded s = constant.project(mapped(1.5, 0.5, MapStatus::kOutside));
  EXPECT_EQ(s.kind, Shade::kOutside);
  EXPECT_EQ(s.color, (Rgba{1, 0, 0.5f, 0.25f}));
  // Inside points are not affected by --outside.
  EXPECT_NEAR(red(constant, mapped(0.5, 0.5), Shade::kImage), 0.35f, 1e-6);
}

TEST_F(ShadeRuleTest, PlaneRepeatTilesUAndVAndHasNoOutside) {
  VertexBakeOptions o;
  o.plane_wrap = WrapMode::kRepeat;
  o.outside = OutsideMode::kColor;  // ignored: nothing is outside a tiled plane
  o.outside_color = {1, 0, 0, 1};
  const ShadeRule r = rule(unit_plane(), o);
  EXPECT_EQ(r.wrap_u, WrapMode::kRepeat);
  EXPECT_EQ(r.wrap_v, WrapMode::kRepeat);
  EXPECT_FALSE(r.has_outside);
  // (1.5, 0.5) tiles to (0.5, 0.5): .35.
  EXPECT_NEAR(red(r, mapped(1.5, 0.5, MapStatus::kOutside), Shade::kImage), 0.35f, 1e-6);
  // (0, 0.25): x = -0.5 -> columns 3 and 0, y = 1: (.7 + .4) / 2 = .55.
  EXPECT_NEAR(red(r, mapped(0, 0.25), Shade::kImage), 0.55f, 1e-6);
  // (0.25, 1): x = 0.5, y = -0.5 -> rows 1 and 0: (.4 + .5 + 0 + .1) / 4 = .25.
  EXPECT_NEAR(red(r, mapped(0.25, 1), Shade::kImage), 0.25f, 1e-6);
  // (-0.75, 2.75) tiles to (0.25, 0.75): x = 0.5, y = 0: (0 + .1) / 2 = .05.
  EXPECT_NEAR(red(r, mapped(-0.75, 2.75, MapStatus::kOutside), Shade::kImage), 0.05f, 1e-6);

  // The same points on the default (clamped) plane.
  const ShadeRule c = rule(unit_plane());
  EXPECT_EQ(c.wrap_u, WrapMode::kClamp);
  EXPECT_NEAR(red(c, mapped(0, 0.25), Shade::kImage), 0.4f, 1e-6);   // column 0, row 1
  EXPECT_NEAR(red(c, mapped(0.25, 1), Shade::kImage), 0.05f, 1e-6);  // row 0: (0 + .1) / 2
}

TEST_F(ShadeRuleTest, PeriodicProxiesWrapUOnlyWhateverThePlaneWrap) {
  VertexBakeOptions o;
  o.plane_wrap = WrapMode::kRepeat;  // the plane's only
  for (const ShadeRule& r : {rule(unit_sphere()), rule(unit_sphere(), o)}) {
    EXPECT_EQ(r.wrap_u, WrapMode::kRepeat);
    EXPECT_EQ(r.wrap_v, WrapMode::kClamp);
    EXPECT_TRUE(r.has_outside);
    EXPECT_NEAR(red(r, mapped(0, 0.25), Shade::kImage), 0.55f, 1e-6);  // u wraps
    EXPECT_NEAR(red(r, mapped(0.25, 1), Shade::kImage), 0.05f, 1e-6);  // v clamps
  }
}

TEST_F(ShadeRuleTest, OccludedModesPerSample) {
  const MapResult inside = mapped(0.5, 0.5);
  const MapResult outside = mapped(1.5, 0.5, MapStatus::kOutside);
  VertexBakeOptions o;

  o.occluded = OccludedMode::kFill;
  ShadeRule r = rule(unit_plane(), o);
  EXPECT_FALSE(r.needs_fill(inside, true));
  EXPECT_TRUE(r.needs_fill(inside, false));
  EXPECT_TRUE(r.needs_fill(unmapped(), true));
  EXPECT_EQ(r.shade(inside, false).kind, Shade::kFill);
  EXPECT_EQ(r.shade(unmapped(), true).kind, Shade::kFill);
  EXPECT_EQ(r.shade(inside, true).kind, Shade::kImage);
  EXPECT_NEAR(r.shade(inside, true).color[0], 0.35f, 1e-6);
  EXPECT_EQ(r.shade(outside, true).kind, Shade::kOutside);

  o.occluded = OccludedMode::kProject;  // occluded samples keep their projected colour
  r = rule(unit_plane(), o);
  EXPECT_FALSE(r.needs_fill(inside, false));
  EXPECT_TRUE(r.needs_fill(unmapped(), false));  // nothing to project
  EXPECT_EQ(r.shade(inside, false).kind, Shade::kImage);
  EXPECT_NEAR(r.shade(inside, false).color[0], 0.35f, 1e-6);
  EXPECT_EQ(r.shade(outside, false).kind, Shade::kOutside);
  EXPECT_NEAR(r.shade(outside, false).color[0], 0.5f, 1e-6);
  EXPECT_EQ(r.shade(unmapped(), true).kind, Shade::kFill);

  o.occluded = OccludedMode::kColor;
  o.occluded_color = {0, 1, 0, 0.5f};
  r = rule(unit_plane(), o);
  EXPECT_FALSE(r.needs_fill(inside, false));
  EXPECT_FALSE(r.needs_fill(unmapped(), true));
  for (const Shaded& s : {r.shade(inside, false), r.shade(outside, false),
                          r.shade(unmapped(), true), r.shade(unmapped(), false)}) {
    EXPECT_EQ(s.kind, Shade::kConstant);
    EXPECT_EQ(s.color, (Rgba{0, 1, 0, 0.5f}));
  }
  EXPECT_EQ(r.shade(inside, true).kind, Shade::kImage);  // visible: the image
}

TEST_F(ShadeRuleTest, LinearInterpolatesInLinearLightAndConvertsTheConstants) {
  const WorkingImage linear = working_image(view_, true);
  VertexBakeOptions o;
  o.linear = true;
  o.outside = OutsideMode::kColor;
  o.outside_color = {0.5f, 1, 0, 0.5f};
  o.occluded = OccludedMode::kColor;
  o.occluded_color = {0.5f, 0.5f, 0.5f, 1};
  const ShadeRule r = make_shade_rule(linear.view, unit_plane(), o);
  EXPECT_TRUE(r.linear);
  // ((0.5 + 0.055) / 1.055)^2.4 = 0.2140411; alpha is never converted.
  EXPECT_NEAR(r.outside_color[0], 0.2140411f, 1e-6);
  EXPECT_FLOAT_EQ(r.outside_color[1], 1.f);
  EXPECT_FLOAT_EQ(r.outside_color[2], 0.f);
  EXPECT_EQ(r.outside_color[3], 0.5f);
  EXPECT_NEAR(r.occluded_color[2], 0.2140411f, 1e-6);
  EXPECT_EQ(r.occluded_color[3], 1.f);
  // (0.25, 0.75): x = 0.5, y = 0, halfway between red 0 and red .1. In linear
  // light: (0 + 0.0100228) / 2 = 0.0050114 ((.1 + .055) / 1.055)^2.4 / 2),
  // back to sRGB 1.055 * 0.0050114^(1/2.4) - 0.055 = 0.0611188 (not 0.05).
  const Shaded s = r.project(mapped(0.25, 0.75));
  EXPECT_NEAR(s.color[0], 0.0050114f, 1e-6);
  EXPECT_NEAR(r.stored(s.color)[0], 0.0611188f, 1e-5);
  EXPECT_EQ(r.stored(s.color)[3], 1.f);
  // Without --linear, stored() and working() are the identity.
  const ShadeRule plain = rule(unit_plane());
  EXPECT_EQ(plain.stored({0.5f, 0.25f, 0, 1}), (Rgba{0.5f, 0.25f, 0, 1}));
  EXPECT_EQ(plain.working({0.5f, 0.25f, 0, 1}), (Rgba{0.5f, 0.25f, 0, 1}));
}

// (Was image_io's srgb_to_linear_in_place test: the image-wide conversion is
// working_image's now.)
TEST(WorkingImage, LinearisesTheColourChannelsOnly) {
  const std::vector<float> px = {0.5f, 1.f, 0.f, 0.5f};
  const WorkingImage w = working_image({1, 1, px.data()}, true);
  ASSERT_EQ(w.pixels.size(), 4u);
  ASSERT_EQ(w.view.data, w.pixels.data());
  EXPECT_EQ(px[0], 0.5f);  // the input is not touched
  // IEC 61966-2-1: ((0.5 + 0.055) / 1.055)^2.4 = 0.2140411...
  EXPECT_NEAR(w.view.data[0], 0.2140411f, 1e-6);
  EXPECT_FLOAT_EQ(w.view.data[1], 1.f);
  EXPECT_FLOAT_EQ(w.view.data[2], 0.f);
  EXPECT_EQ(w.view.data[3], 0.5f);
  const Rgba back = linear_to_srgb(Rgba{w.view.data[0], w.view.data[1], w.view.data[2], 0.5f});
  EXPECT_NEAR(back[0], 0.5f, 1e-6);

  const WorkingImage same = working_image({1, 1, px.data()}, false);
  EXPECT_TRUE(same.pixels.empty());
  EXPECT_EQ(same.view.data, px.data());
}

TEST(SamplePattern, SplitMix64AndRadicalInverseKnownValues) {
  // SplitMix64 seeded with 0: its first two outputs (Vigna's splitmix64.c).
  EXPECT_EQ(splitmix64(0), 0xE220A8397B1DCDAFull);
  EXPECT_EQ(splitmix64(0x9E3779B97F4A7C15ull), 0x6E789E6AA1B965F4ull);
  EXPECT_EQ(unit_double(~0ull), 1 - 0x1.0p-53);
  EXPECT_EQ(unit_double(1ull << 63), 0.5);
  // Bits reversed: 1 -> .1b, 2 -> .01b, 3 -> .11b, 6 -> .011b.
  EXPECT_EQ(radical_inverse2(0), 0.0);
  EXPECT_EQ(radical_inverse2(1), 0.5);
  EXPECT_EQ(radical_inverse2(2), 0.25);
  EXPECT_EQ(radical_inverse2(3), 0.75);
  EXPECT_EQ(radical_inverse2(6), 0.375);
}

}  // namespace
}  // namespace texbake
