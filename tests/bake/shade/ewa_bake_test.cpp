// --filter ewa in the bakes (issue #16 item 2): the footprints the vertex and
// atlas targets hand to sample_ewa, worked out by hand on a flat grid under
// an identity plane proxy, and a constant image baked exactly (sphere proxy
// onto the bunny, poles included).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bake/engine/bake_atlas.h"
#include "bake/engine/bake_vertex.h"
#include "mapping/mipmap.h"
#include "tests/bake/atlas/atlas_test_util.h"
#include "tests/bake/bunny_earth.h"
#include "tests/bake/test_meshes.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

// 256 x 256, red: 3-texel checkerboard (no MIP level is flat), green: a ramp.
Image checker_image() {
  Image img;
  img.width = img.height = 256;
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 256; ++x) {
      const float r = ((x / 3 + y / 3) % 2) ? 1.0f : 0.0f;
      img.pixels.insert(img.pixels.end(), {r, x / 255.0f, 0.5f, 1});
    }
  }
  return img;
}

Image constant_image(int w, int h, Rgba c) {
  Image img;
  img.width = w;
  img.height = h;
  for (int i = 0; i < w * h; ++i) img.pixels.insert(img.pixels.end(), c.begin(), c.end());
  return img;
}

// (u, v) = (x, y) on z = 0.
Proxy identity_plane() {
  return make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).value();
}

TEST(EwaBake, AtlasFootprintIsOneTexelOfTheLayout) {
  // Two triangles covering [0, 1]^2 with UV = position: an atlas texel of a
  // 16 x 16 atlas is 1/16 x 1/16 of the image under the identity plane, so
  // with one sample per texel each texel is sample_ewa at its centre with
  // 0.85 of the ellipse through the texel's corners (README, Footprint
  // filtering): semi-axes 0.85 (1/16, 0) / sqrt(2), 0.85 (0, 1/16) / sqrt(2).
  const double h = 0.85 / (16 * std::sqrt(2.0));
  const MeshData mesh = test::make_flat_uv_soup({{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}});
  const Image img = checker_image();
  AtlasBakeOptions o;
  o.size = 16;
  o.samples = 1;
  o.padding = 0;
  o.shading.visibility = Visibility::kAll;
  o.shading.filter = VertexFilter::kEwa;
  const AtlasBakeResult r = bake_atlas(mesh, img.view(), identity_plane(), o).value();
  const MipPyramid mip(img.view());
  int compared = 0;
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      const std::size_t t = static_cast<std::size_t>(y) * 16 + x;
      ASSERT_TRUE(r.baked[t]);
      const UV uv{(x + 0.5) / 16, 1 - (y + 0.5) / 16};
      const Rgba e = sample_ewa(mip, uv, {{h, 0}, {0, h}}, WrapMode::kClamp, WrapMode::kClamp);
      for (int k = 0; k < 4; ++k) {
        EXPECT_NEAR(r.atlas.pixels[t * 4 + k], e[k], 1e-5) << x << " " << y << " " << k;
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 256);
  // 16 texels of the image under each atlas texel: the checkerboard's
  // squares (3 texels) are averaged away, unlike the bilinear bake's.
  o.shading.filter = VertexFilter::kBilinear;
  const AtlasBakeResult b = bake_atlas(mesh, img.view(), identity_plane(), o).value();
  double spread_ewa = 0, spread_bilinear = 0;
  for (int t = 0; t < 256; ++t) {
    spread_ewa = std::max(spread_ewa, std::abs(r.atlas.pixels[t * 4] - 0.5));
    spread_bilinear = std::max(spread_bilinear, std::abs(b.atlas.pixels[t * 4] - 0.5));
  }
  EXPECT_LT(spread_ewa, 0.1);
  EXPECT_GT(spread_bilinear, 0.49);
}

TEST(EwaBake, AtlasSupersamplesShareTheTexel) {
  // Four samples per texel: each has a cell of half a texel a side (1/16 of
  // the image), so the texel is the mean of four lookups with semi-axes
  // 1/16 / sqrt(2) at the cells' centres (sample_offset(s, 4) = +-0.25 texel).
  const double h = 1 / (16 * std::sqrt(2.0));
  const MeshData mesh = test::make_flat_uv_soup({{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}});
  const Image img = checker_image();
  AtlasBakeOptions o;
  o.size = 8;
  o.samples = 4;
  o.padding = 0;
  o.shading.visibility = Visibility::kAll;
  o.shading.filter = VertexFilter::kEwa;
  const AtlasBakeResult r = bake_atlas(mesh, img.view(), identity_plane(), o).value();
  const MipPyramid mip(img.view());
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      double mean = 0;
      for (double dy : {-0.25, 0.25}) {
        for (double dx : {-0.25, 0.25}) {
          const UV uv{(x + 0.5 + dx) / 8, 1 - (y + 0.5 + dy) / 8};
          mean += sample_ewa(mip, uv, {{h, 0}, {0, h}}, WrapMode::kClamp, WrapMode::kClamp)[0] / 4;
        }
      }
      EXPECT_NEAR(r.atlas.pixels[(static_cast<std::size_t>(y) * 8 + x) * 4], mean, 1e-5)
          << x << " " << y;
    }
  }
}

TEST(EwaBake, VertexFootprintIsTheVertexShare) {
  // An 8 x 8 grid on [0, 1]^2: an interior vertex has six triangles of area
  // h^2 / 2 (h = 1/8), its share is a third of them, h^2, so its footprint
  // is two perpendicular tangents of length h; under the identity plane that
  // is a circle of radius h in (u, v).
  MeshData mesh;
  test::append_grid(mesh, 8, 8, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0};
  });
  test::faces_from_triangles(mesh);
  const Image img = checker_image();
  VertexBakeOptions o;
  o.visibility = Visibility::kAll;
  o.filter = VertexFilter::kEwa;
  const VertexBakeResult r = bake_vertex(mesh, img.view(), identity_plane(), o).value();
  EXPECT_EQ(r.counts.samples, 81u);  // one lookup per vertex
  const MipPyramid mip(img.view());
  const double h = 1.0 / 8;
  for (int j = 1; j < 8; ++j) {
    for (int i = 1; i < 8; ++i) {
      const Rgba e =
          sample_ewa(mip, {i * h, j * h}, {{h, 0}, {0, h}}, WrapMode::kClamp, WrapMode::kClamp);
      const Rgba& c = r.colors[static_cast<std::size_t>(j) * 9 + i];
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(c[k], e[k], 1e-6) << i << " " << j;
    }
  }
}

TEST(EwaBake, ThePoleNeitherSmearsNorPinches) {
  // A UV sphere (32 rings: the first ring 5.6 degrees from the pole, 8 image
  // rows of a 512 x 256 map) on the sphere proxy. Red: 1 in the top 8 rows
  // only; green = 0.5 + 0.5 cos(2 pi u), whose mean over u is 0.5.
  const MeshData mesh = test::uv_sphere({0, 0, 0}, 1, 32, 64);
  const Proxy sphere = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{1, 0, 0}}).value();
  Image img;
  img.width = 512;
  img.height = 256;
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 512; ++x) {
      const double u = (x + 0.5) / 512;
      img.pixels.insert(img.pixels.end(),
                        {y < 8 ? 1.0f : 0.0f,
                         static_cast<float>(0.5 + 0.5 * std::cos(2 * 3.14159265358979 * u)), 0, 1});
    }
  }
  VertexBakeOptions o;
  o.visibility = Visibility::kAll;
  o.filter = VertexFilter::kEwa;
  const Rgba ewa = bake_vertex(mesh, img.view(), sphere, o).value().colors[0];  // the north pole
  o.filter = VertexFilter::kBilinear;
  const Rgba bilinear = bake_vertex(mesh, img.view(), sphere, o).value().colors[0];
  // Not smeared: the pole's footprint reaches about 4 rows down (half the
  // first ring), so red stays near 1 (the eccentricity clamp alone would
  // smear it over the top quarter of the map: red 0.125 measured).
  EXPECT_GT(ewa[0], 0.9) << ewa[0] << " " << ewa[1];
  // Not pinched: every u counts at the pole (green 0.5), where one bilinear
  // tap reads the u = 0 column (green ~ 1).
  EXPECT_NEAR(ewa[1], 0.5, 0.01);
  EXPECT_GT(bilinear[1], 0.99);
}

TEST(EwaBake, ConstantImageIsThatConstantOnTheBunny) {
  const test::BunnyEarth* scene = test::bunny_earth();
  ASSERT_NE(scene, nullptr);
  const Rgba c{0.3f, 0.6f, 0.9f, 1.0f};
  const Image img = constant_image(512, 256, c);
  VertexBakeOptions vo;
  vo.visibility = Visibility::kAll;
  vo.filter = VertexFilter::kEwa;
  const VertexBakeResult v = bake_vertex(scene->mesh, img.view(), scene->proxy, vo).value();
  for (const Rgba& col : v.colors) {
    for (int k = 0; k < 4; ++k) ASSERT_EQ(col[k], c[k]);
  }
  // The atlas over the proxy's own layout: two triangles hold a pole (the
  // footprint spanning every u). No padding: the opaque texels are the baked ones.
  AtlasOptions ao;
  ao.uv = UvLayout::kProxy;
  ao.bake.size = 128;
  ao.bake.padding = 0;
  ao.bake.shading = vo;
  const Atlas a = bake_atlas_texture(scene->mesh, img.view(), scene->proxy, ao).value();
  std::size_t opaque = 0;
  for (std::size_t t = 0; t < a.image.pixels.size() / 4; ++t) {
    if (a.image.pixels[t * 4 + 3] != 1) continue;
    ++opaque;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a.image.pixels[t * 4 + k], c[k]) << t;
  }
  EXPECT_GT(opaque, 5000u);
}

}  // namespace
}  // namespace texbake
