// The working encoding for a linear texture (issue #11): the shading rule
// and the public bakes take an ImageView whose color_space is kLinear as
// linear light, use it as it is, and give sRGB-encoded results. Expected
// values: the IEC 61966-2-1 formula by hand (tests/mesh_io/colour_testing.h).
#include <gtest/gtest.h>

#include <vector>

#include "bake/shade/shade.h"
#include "tests/bake/test_meshes.h"
#include "tests/mesh_io/colour_testing.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

using colour_testing::srgb_decode;

// A 1 x 1 texel of sRGB (128, 64, 255) / 255, stored in linear light.
std::vector<float> linear_texel() {
  return {static_cast<float>(srgb_decode(128 / 255.0)), static_cast<float>(srgb_decode(64 / 255.0)),
          1.f, 1.f};
}

Proxy unit_plane() {
  return make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).value();
}

TEST(LinearTexture, IsUsedAsItIsAndTheRuleWorksInLinearLight) {
  const std::vector<float> px = linear_texel();
  const ImageView view{1, 1, px.data(), ColorSpace::kLinear};
  for (bool linear_flag : {false, true}) {
    const WorkingImage w = working_image(view, linear_flag);
    EXPECT_TRUE(w.pixels.empty());  // no copy, no conversion
    EXPECT_EQ(w.view.data, px.data());
    EXPECT_TRUE(works_in_linear(view, linear_flag));
    VertexBakeOptions o;
    o.linear = linear_flag;
    o.occluded = OccludedMode::kColor;
    o.occluded_color = {0.5f, 0.5f, 0.5f, 1};
    const ShadeRule r = make_shade_rule(w.view, unit_plane(), o);
    EXPECT_TRUE(r.linear);
    // ((0.5 + 0.055) / 1.055)^2.4 = 0.2140411: the constant is sRGB-encoded.
    EXPECT_NEAR(r.occluded_color[0], 0.2140411f, 1e-6);
    const Shaded s = r.project({{0.5, 0.5}, {0, 0, 1}, MapStatus::kOk});
    EXPECT_FLOAT_EQ(s.color[0], px[0]);
    EXPECT_NEAR(r.stored(s.color)[0], 128 / 255.f, 1e-6);
    EXPECT_NEAR(r.stored(s.color)[1], 64 / 255.f, 1e-6);
  }
  // An sRGB view without --linear: stored values, as before.
  const std::vector<float> srgb = {128 / 255.f, 64 / 255.f, 1.f, 1.f};
  const ImageView sview{1, 1, srgb.data()};
  EXPECT_EQ(sview.color_space, ColorSpace::kSrgb);  // the default
  EXPECT_FALSE(works_in_linear(sview, false));
  EXPECT_FALSE(make_shade_rule(working_image(sview, false).view, unit_plane(), {}).linear);
}

TEST(LinearTexture, PublicBakesGiveSrgbEncodedResults) {
  const std::vector<float> px = linear_texel();
  const ImageView view{1, 1, px.data(), ColorSpace::kLinear};
  const MeshData mesh = test::uv_sphere({0, 0, 0}, 1, 6, 12);
  const Proxy sphere = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{1, 0, 0}}).value();
  Expected<VertexColors> v = bake_vertex_colors(mesh, view, sphere);
  ASSERT_TRUE(v) << v.error().message;
  ASSERT_EQ(v->colors.size(), mesh.positions.size());
  for (const Rgba& c : v->colors) {
    EXPECT_NEAR(c[0], 128 / 255.f, 1e-5);
    EXPECT_NEAR(c[1], 64 / 255.f, 1e-5);
    EXPECT_NEAR(c[2], 1.f, 1e-5);
  }
  AtlasOptions ao;
  ao.uv = UvLayout::kProxy;
  ao.bake.size = 16;
  Expected<Atlas> a = bake_atlas_texture(mesh, view, sphere, ao);
  ASSERT_TRUE(a) << a.error().message;
  EXPECT_EQ(a->image.color_space, ColorSpace::kSrgb);
  int covered = 0;
  for (std::size_t i = 0; i < a->image.pixels.size(); i += 4) {
    if (a->image.pixels[i + 3] == 0) continue;
    ++covered;
    EXPECT_NEAR(a->image.pixels[i], 128 / 255.f, 1e-5) << i;
    EXPECT_NEAR(a->image.pixels[i + 1], 64 / 255.f, 1e-5) << i;
  }
  EXPECT_GT(covered, 16);
}

}  // namespace
}  // namespace texbake
