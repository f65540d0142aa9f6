// bake_atlas_layers (SPEC section 10, the atlas target) on a unit square
// whose UVs are its (x, y), so that texel (i, j) of an N x N atlas is the
// square [i/N, (i+1)/N] x [1 - (j+1)/N, 1 - j/N] of the surface. Expected
// values worked out by hand in linear light (sRGB by the IEC 61966-2-1
// formulas written out here), with 4 samples per texel at the centres of
// its 2 x 2 sub-cells (offsets +-1/4 texel).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bake/engine/bake_atlas.h"
#include "bake/engine/layers_bake.h"
#include "tests/bake/atlas/atlas_test_util.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

double to_linear(double s) {
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}
double to_srgb(double l) {
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
}

// The unit square in z = 0 (facing +z), 2 x 2 cells, UV = (x, y) per corner.
MeshData uv_square() {
  MeshData mesh;
  test::append_grid(mesh, 2, 2, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0.f};
  });
  test::faces_from_triangles(mesh);
  for (const Float3& p : mesh.positions) mesh.uvs.push_back({p.x, p.y});
  mesh.corner_uv = mesh.face_vertices;
  return mesh;
}

// The plane proxy over [0, width] x [0, 1]: u = x / width, v = y, d(P) = +z.
Proxy plane(double width) {
  Expected<Proxy> p = make_proxy(PlaneParams{{0, 0, 0}, {width, 0, 0}, {0, 1, 0}});
  EXPECT_TRUE(p);
  return *p;
}

struct TestImage {
  int w = 2, h = 2;
  std::vector<float> px;
  ImageView view() const { return {w, h, px.data(), ColorSpace::kSrgb}; }
};
TestImage constant(Rgba c) {
  TestImage t;
  for (int i = 0; i < 4; ++i) t.px.insert(t.px.end(), c.begin(), c.end());
  return t;
}

LayerInput layer(const TestImage& image, double width = 1) {
  LayerInput in;
  in.name = "test";
  in.projector = plane(width);
  in.texture = image.view();
  in.visibility = LayerVisibility::kAll;
  return in;
}

Rgba texel(const LayersAtlasResult& r, int x, int y) {
  const float* p = &r.atlas.pixels[4 * (static_cast<std::size_t>(y) * r.atlas.width + x)];
  return {p[0], p[1], p[2], p[3]};
}

void expect_rgba(const Rgba& got, std::array<double, 4> want, double tol = 2e-6) {
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[c], want[c], tol) << "channel " << c;
}

LayersAtlasOptions atlas_options(int size) {
  LayersAtlasOptions o;
  o.size = size;
  o.samples = 4;
  o.padding = 0;
  return o;
}

TEST(LayersAtlas, OverAConstantBaseMixesEveryTexelInLinearLight) {
  const MeshData mesh = uv_square();
  const TestImage orange = constant({1, 0.5f, 0, 1});
  LayerInput in = layer(orange);
  in.opacity = 0.5;
  LayersAtlasOptions o = atlas_options(8);
  o.layers.base = LayerBase::kColor;
  o.layers.base_color = {0.2f, 0.4f, 0.6f, 1};
  Expected<LayersAtlasResult> r = bake_atlas_layers(mesh, {in}, o);
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_EQ(r->texels, 64u);  // the square covers the whole atlas
  const std::array<double, 3> l{1, 0.5, 0}, b{0.2, 0.4, 0.6};
  std::array<double, 4> want{0, 0, 0, 1};
  for (int c = 0; c < 3; ++c) want[c] = to_srgb(0.5 * to_linear(l[c]) + 0.5 * to_linear(b[c]));
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) expect_rgba(texel(*r, x, y), want, 1e-5);
  }
  EXPECT_TRUE(r->opaque);
  ASSERT_EQ(r->layers.size(), 1u);
  EXPECT_EQ(r->layers[0].in_domain, 256u);
  EXPECT_EQ(r->layers[0].visible, 256u);
  EXPECT_EQ(r->layers[0].blended, 256u);
  EXPECT_NEAR(r->layers[0].mean_alpha, 0.5, 1e-12);
}

TEST(LayersAtlas, CoverageAveragesInPremultipliedLight) {
  // The layer covers x < 0.35 (outside: transparent). At 4 x 4 texels,
  // column 0 (x in [0, 0.25]) is wholly covered; column 1 has samples at
  // x = 0.3125 (covered) and 0.4375 (not): coverage 1/2, colour the
  // layer's own (premultiplied mean over alpha), not darkened; columns 2
  // and 3 are uncovered: alpha 0 and, under --occluded R,G,B, its RGB.
  const MeshData mesh = uv_square();
  const TestImage orange = constant({1, 0.5f, 0, 1});
  LayerInput in = layer(orange, 0.35);
  LayersAtlasOptions o = atlas_options(4);
  o.layers.occluded = OccludedMode::kColor;
  o.layers.occluded_color = {0, 1, 0, 1};
  Expected<LayersAtlasResult> r = bake_atlas_layers(mesh, {in}, o);
  ASSERT_TRUE(r) << r.error().message;
  for (int y = 0; y < 4; ++y) {
    expect_rgba(texel(*r, 0, y), {1, 0.5, 0, 1}, 1e-5);
    expect_rgba(texel(*r, 1, y), {1, 0.5, 0, 0.5}, 1e-5);
    expect_rgba(texel(*r, 2, y), {0, 1, 0, 0});
    expect_rgba(texel(*r, 3, y), {0, 1, 0, 0});
  }
  EXPECT_FALSE(r->opaque);
  EXPECT_EQ(r->uncovered, 4u * (2 + 4 + 4));  // samples: half of column 1, columns 2 and 3
  EXPECT_EQ(r->layers[0].blended, 4u * (4 + 2));
  EXPECT_NEAR(r->layers[0].mean_alpha, 6.0 / 16, 1e-12);
}

TEST(LayersAtlas, BaseTextureIsKeptExactlyAtItsOwnSize) {
  // A 4 x 4 base texture with a different colour per texel, through the
  // square's UVs, at the texture's size: a multiply layer of white (the
  // identity) leaves every texel as it is.
  const MeshData mesh = uv_square();
  TestImage base;
  base.w = base.h = 4;
  for (int i = 0; i < 16; ++i) {
    base.px.insert(base.px.end(), {i / 15.f, 1 - i / 15.f, (i % 4) / 3.f, 1});
  }
  const TestImage white = constant({1, 1, 1, 1});
  LayerInput in = layer(white);
  in.mode = LayerMode::kMultiply;
  LayersAtlasOptions o = atlas_options(4);
  o.layers.base = LayerBase::kMesh;
  o.base_texture = base.view();
  Expected<LayersAtlasResult> r = bake_atlas_layers(mesh, {in}, o);
  ASSERT_TRUE(r) << r.error().message;
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const float* b = &base.px[4 * (y * 4 + x)];
      expect_rgba(texel(*r, x, y), {b[0], b[1], b[2], 1}, 1e-5);
    }
  }
}

TEST(LayersAtlas, BaseVertexColoursInterpolateAndBadInputIsRefused) {
  MeshData mesh = uv_square();
  const TestImage white = constant({1, 1, 1, 1});
  LayerInput in = layer(white);
  in.opacity = 0;  // the base alone
  LayersAtlasOptions o = atlas_options(4);
  o.layers.base = LayerBase::kMesh;
  // No vertex colours, no texture: refused.
  Expected<LayersAtlasResult> r = bake_atlas_layers(mesh, {in}, o);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("neither a texture nor vertex colours"), std::string::npos);
  // Vertex colours linear in x in linear light (sRGB 0 at x = 0, 1 at x = 1,
  // 0.5 linear at x = 0.5 is sRGB to_srgb(0.5)): a texel's mean over its
  // samples is the linear value at its centre.
  for (const Float3& p : mesh.positions) {
    const float s = static_cast<float>(to_srgb(p.x));
    mesh.vertex_colors.push_back({s, s, s, 1});
  }
  r = bake_atlas_layers(mesh, {in}, o);
  ASSERT_TRUE(r) << r.error().message;
  for (int x = 0; x < 4; ++x) {
    const double g = to_srgb((x + 0.5) / 4);
    expect_rgba(texel(*r, x, 1), {g, g, g, 1}, 1e-5);
  }
  o.padding = -7;
  EXPECT_FALSE(bake_atlas_layers(mesh, {in}, o));
  EXPECT_FALSE(bake_atlas_layers(mesh, {}, atlas_options(4)));
}

TEST(LayersAtlas, OverlappingLayoutTakesTheSurfaceSomeLayerSees) {
  // Two unit squares with the same UVs, (x, y), at z = 0 and z = 1; the
  // plane's rays go towards +z, so the square at z = 0 is hidden behind the
  // other. With resolve_overlaps every sample takes the visible square
  // (whichever comes first in the mesh): the layer's colour, coverage 1.
  // Without, each sample keeps its lowest-index triangle: where that is
  // the hidden square, no coverage, and the constant's RGB with alpha 0.
  auto square = [](float z) {
    return std::vector<Float3>{{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 0, z}, {1, 1, z}, {0, 1, z}};
  };
  const TestImage green = constant({0, 0.75f, 0, 1});
  LayerInput in = layer(green);
  in.visibility = LayerVisibility::kFirst;
  const int n = 16;
  for (bool hidden_first : {true, false}) {
    std::vector<Float3> pos = square(hidden_first ? 0.f : 1.f);
    const std::vector<Float3> other = square(hidden_first ? 1.f : 0.f);
    pos.insert(pos.end(), other.begin(), other.end());
    std::vector<Float2> uv;
    for (const Float3& p : pos) uv.push_back({p.x, p.y});
    const MeshData mesh = test::make_triangle_soup(pos, uv);
    for (bool resolve : {true, false}) {
      LayersAtlasOptions o = atlas_options(n);
      o.padding = 0;
      o.resolve_overlaps = resolve;
      o.layers.occluded = OccludedMode::kColor;
      o.layers.occluded_color = {1, 0, 0, 1};
      Expected<LayersAtlasResult> r = bake_atlas_layers(mesh, {in}, o);
      ASSERT_TRUE(r) << r.error().message;
      ASSERT_EQ(r->texels, std::size_t(n * n));
      const bool green_everywhere = resolve || !hidden_first;
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          SCOPED_TRACE(testing::Message() << "texel " << x << ", " << y << " hidden first "
                                          << hidden_first << " resolve " << resolve);
          if (green_everywhere) {
            expect_rgba(texel(*r, x, y), {0, 0.75, 0, 1});
          } else {
            expect_rgba(texel(*r, x, y), {1, 0, 0, 0});
          }
        }
      }
      // The counts are the chosen samples': all seen, or all hidden.
      const std::size_t samples = std::size_t(n * n) * 4;
      EXPECT_EQ(r->layers[0].visible, green_everywhere ? samples : 0u);
      EXPECT_EQ(r->layers[0].hidden, green_everywhere ? 0u : samples);
      EXPECT_EQ(r->uncovered, green_everywhere ? 0u : samples);
    }
  }
}

TEST(LayersAtlas, SingleProjectionIsThePlainMeanOfItsSamples) {
  // ResultAlpha::kImage on the atlas: a texel is the plain mean of its
  // samples' RGBA in the stored encoding (alpha a colour channel, not a
  // coverage): an image half transparent on the left half of the plane
  // gives texels alpha 0 and their colour, not the constant.
  TestImage half;
  half.w = 2;
  half.h = 1;
  half.px = {0.2f, 0.4f, 0.6f, 0.f, 0.8f, 0.6f, 0.4f, 1.f};
  LayerInput in = layer(half);
  in.linear = false;
  in.outside = LayerOutside::kClamp;
  LayersAtlasOptions o = atlas_options(8);
  o.layers.alpha = ResultAlpha::kImage;
  Expected<LayersAtlasResult> r = bake_atlas_layers(uv_square(), {in}, o);
  ASSERT_TRUE(r) << r.error().message;
  // Texel x's samples sit at u = (x + 0.5 -+ 0.25) / 8; the image's
  // bilinear lookup (SPEC section 1) at u is the texel centres' blend with
  // weight clamp(2u - 0.5, 0, 1) on the right one.
  for (int x = 0; x < 8; ++x) {
    double w = 0;
    for (double du : {-0.25, 0.25}) w += std::clamp(2 * (x + 0.5 + du) / 8 - 0.5, 0.0, 1.0) / 2;
    const std::array<double, 4> want{0.2 + 0.6 * w, 0.4 + 0.2 * w, 0.6 - 0.2 * w, w};
    for (int y = 0; y < 8; ++y) expect_rgba(texel(*r, x, y), want, 1e-6);
  }
  EXPECT_EQ(r->layers[0].lookups, 256u);
  EXPECT_EQ(r->layers[0].outside, 0u);
}

}  // namespace
}  // namespace texbake
