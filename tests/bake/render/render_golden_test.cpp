// Golden images: renders compared with committed PNGs in tests/golden/.
//
// Tolerance: PSNR >= 40 dB over all channels (values in [0, 1]) of the
// pixels that are mesh in either image (background in both is masked out,
// so a small mesh in a large frame is not diluted by identical background).
// 8-bit quantisation alone costs about 59 dB, so 40 dB leaves room for
// compiler, Embree and libm differences (a BVH that splits a tie the other
// way changes an edge pixel) while any real change of camera, shading,
// sampling or mapping (which moves many pixels by many levels) fails.
// Measured on the bunny (view 120,20, 128 x 128): a generated UV layout for a
// different atlas size (500, 640, 1024 instead of 512) stays at 45-49 dB, so
// a change of the packer alone does not break the atlas golden; the vertex
// bake against the atlas bake gives 37 dB, direct projection (no visibility)
// against the visibility-first atlas bake 25.5 dB.
//
// Regenerate after an intended change (then look at the images and commit):
//   TEXBAKE_UPDATE_GOLDEN=1 build-dev/test_bake --gtest_filter='RenderGolden*'
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>

#include "bake/engine/bake_vertex.h"
#include "bake/render/render_preview.h"
#include "bake/trace/embree_scene.h"
#include "mesh_io/image_compare.h"
#include "mesh_io/image_io.h"
#include "tests/bake/bunny_earth.h"

namespace texbake {
namespace {

constexpr double kMinPsnr = 40.0;

std::filesystem::path golden_path(const std::string& name) {
  return std::filesystem::path(TEXBAKE_SOURCE_DIR) / "tests" / "golden" / name;
}

// Writes `image` as an 8-bit PNG and compares the file's stored values with
// the golden file's (mesh_io/image_compare.h), or rewrites the golden file
// when TEXBAKE_UPDATE_GOLDEN is set. Going through the file checks what users
// get, alpha included.
void expect_matches_golden(const ImageView& image, const std::string& name) {
  const auto path = golden_path(name);
  if (std::getenv("TEXBAKE_UPDATE_GOLDEN")) {
    ASSERT_TRUE(write_image(path, image).has_value());
    std::printf("updated %s\n", path.c_str());
    return;
  }
  const auto rendered = std::filesystem::temp_directory_path() /
                        ("texbake_golden_" + std::to_string(::getpid()) + "_" + name);
  ASSERT_TRUE(write_image(rendered, image).has_value());
  CompareOptions options;
  options.mask_background = true;
  auto r = compare_image_files(rendered, path, options);
  std::filesystem::remove(rendered);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  std::printf("%s: PSNR %.2f dB against the golden image\n", name.c_str(), r->psnr);
  EXPECT_GE(r->psnr, kMinPsnr) << name << ": max difference " << r->max_difference << " at ("
                               << r->max_x << ", " << r->max_y << ")";
}

// A UV sphere of radius 1 at the origin, lat x lon quads split in two.
MeshData uv_sphere(int lat, int lon) {
  MeshData m;
  for (int i = 0; i <= lat; ++i) {
    const double th = std::numbers::pi * i / lat;
    for (int j = 0; j < lon; ++j) {
      const double ph = 2 * std::numbers::pi * j / lon;
      m.positions.push_back({static_cast<float>(std::sin(th) * std::cos(ph)),
                             static_cast<float>(std::sin(th) * std::sin(ph)),
                             static_cast<float>(std::cos(th))});
    }
  }
  auto id = [&](int i, int j) { return static_cast<uint32_t>(i * lon + (j % lon)); };
  m.face_offsets.push_back(0);
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    const uint32_t corner = static_cast<uint32_t>(m.face_vertices.size());
    m.face_vertices.insert(m.face_vertices.end(), {a, b, c});
    m.face_offsets.push_back(corner + 3);
    m.triangle_face.push_back(static_cast<uint32_t>(m.triangles.size()));
    m.triangles.push_back({a, b, c});
    m.triangle_corners.push_back({corner, corner + 1, corner + 2});
  };
  for (int i = 0; i < lat; ++i) {
    for (int j = 0; j < lon; ++j) {
      if (i > 0) add(id(i, j), id(i + 1, j), id(i, j + 1));
      if (i < lat - 1) add(id(i, j + 1), id(i + 1, j), id(i + 1, j + 1));
    }
  }
  return m;
}

// 64 x 32 test texture: an 8 x 4 checker of orange and blue cells, green
// rising towards the top row (north), a white column at u in [0, 1/64).
std::vector<float> test_texture() {
  std::vector<float> px;
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool odd = ((x / 8) + (y / 8)) % 2;
      const float g = 0.8f * (31 - y) / 31.0f;
      if (x == 0) {
        px.insert(px.end(), {1, 1, 1, 1});
      } else {
        px.insert(px.end(), {odd ? 0.95f : 0.1f, g, odd ? 0.1f : 0.9f, 1});
      }
    }
  }
  return px;
}

TEST(RenderGolden, SphereWithDirectProjection) {
  const MeshData sphere = uv_sphere(32, 64);
  auto scene = EmbreeScene::build(sphere, BuildQuality::kMedium);
  ASSERT_TRUE(scene.has_value()) << scene.error().message;
  const std::vector<float> texels = test_texture();
  auto proxy = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{1, 0, 0}});
  ASSERT_TRUE(proxy.has_value()) << proxy.error().message;
  RenderOptions o;
  o.width = o.height = 128;
  o.samples_per_pixel = 4;
  o.azimuth_deg = 30;
  o.elevation_deg = 20;
  auto img = render_preview(sphere, *scene,
                            ProjectionSource{*proxy, ImageView{64, 32, texels.data()}, {}}, o);
  ASSERT_TRUE(img.has_value()) << img.error().message;
  expect_matches_golden(img->view(), "sphere_projection.png");
}

// The demo's bake (scripts/demo.sh): the Earth map through a sphere proxy
// (pole +y) onto the bunny per vertex, default options (area filter,
// visibility first, occluded vertices filled).
TEST(RenderGolden, BunnyWithBakedVertexColors) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_NE(be, nullptr);
  auto baked = bake_vertex(be->mesh, be->earth.view(), be->proxy, VertexBakeOptions{});
  ASSERT_TRUE(baked.has_value()) << baked.error().message;
  MeshData mesh = be->mesh;
  mesh.vertex_colors = std::move(baked->colors);
  auto scene = EmbreeScene::build(mesh, BuildQuality::kMedium);
  ASSERT_TRUE(scene.has_value()) << scene.error().message;
  auto img = render_preview(mesh, *scene, VertexColorSource{}, test::bunny_view(128, 4));
  ASSERT_TRUE(img.has_value()) << img.error().message;
  expect_matches_golden(img->view(), "bunny_vertex.png");
}

// The same projection baked into a 512 atlas over generated UVs (--uv
// generate), default options, rendered through the atlas.
TEST(RenderGolden, BunnyWithBakedAtlas) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_NE(be, nullptr);
  constexpr int kSize = 512;
  auto mesh = test::bunny_with_generated_uvs(be->mesh, kSize);
  ASSERT_TRUE(mesh.has_value()) << mesh.error().message;
  AtlasBakeOptions ao;
  ao.size = kSize;
  auto baked = bake_atlas(*mesh, be->earth.view(), be->proxy, ao);
  ASSERT_TRUE(baked.has_value()) << baked.error().message;
  auto scene = EmbreeScene::build(*mesh, BuildQuality::kMedium);
  ASSERT_TRUE(scene.has_value()) << scene.error().message;
  auto img =
      render_preview(*mesh, *scene, AtlasSource{baked->atlas.view()}, test::bunny_view(128, 4));
  ASSERT_TRUE(img.has_value()) << img.error().message;
  expect_matches_golden(img->view(), "bunny_atlas.png");
}

}  // namespace
}  // namespace texbake
