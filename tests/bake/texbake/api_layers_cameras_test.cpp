// "cameras" layers (SPEC section 10 with section 9's photos) through the
// public API: photos of one constant colour written as 8-bit PNGs beside a
// JSON camera list, a layers file naming it, and the results worked out by
// hand in linear light (the sRGB formulas written out here, not texbake's):
// the over mix at an opacity, the exposure gains making two photos agree,
// the angle fade at the angle to the camera (and the 75-degree cut), the
// occluded points keeping the base, for the vertex and the atlas targets.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>

#include "tests/bake/test_meshes.h"
#include "tests/bake/texbake/api_test_util.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

double to_linear(double s) {
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}
double to_srgb(double l) {
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
}

// A fresh folder per test.
fs::path test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(::testing::TempDir()) / "texbake_layers_cameras" / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The square [-1, 1]^2 in z = 0 facing +z, 8 x 8 cells; with UVs
// u = (x + 1) / 4, v = (y + 1) / 2 (the left half of the atlas).
MeshData plane_mesh(bool occluder = false) {
  MeshData mesh;
  test::append_grid(mesh, 8, 8, [](double s, double t) {
    return Float3{static_cast<float>(2 * s - 1), static_cast<float>(2 * t - 1), 0.f};
  });
  const std::size_t plane_vertices = mesh.positions.size();
  if (occluder) {
    // A quad at z = 1 over x in [-1.5, -0.3]: from a camera at (0, 0, 3) it
    // hides the plane's points with x <= -0.45 (similar triangles: the
    // segment to the camera crosses z = 1 at 2/3 of the point's x).
    test::append_grid(mesh, 1, 1, [](double s, double t) {
      return Float3{static_cast<float>(-1.5 + 1.2 * s), static_cast<float>(3 * t - 1.5), 1.f};
    });
  }
  test::faces_from_triangles(mesh);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Float3& p = mesh.positions[v];
    if (v < plane_vertices) {
      mesh.uvs.push_back({(p.x + 1) / 4, (p.y + 1) / 2});
    } else {  // the occluder in u in [0.6, 0.9]
      mesh.uvs.push_back({0.6f + 0.3f * (p.x + 1.5f) / 1.2f, (p.y + 1.5f) / 3});
    }
  }
  mesh.corner_uv = mesh.face_vertices;
  return mesh;
}

struct Cam {
  std::string image;
  std::array<double, 3> eye, up;
  double level;  // the photo's 8-bit level (every pixel)
};

// The camera list (PINHOLE 64 x 64, f = 32, looking at the origin) and its
// photos in `dir`; returns the list's path.
fs::path write_cameras(const fs::path& dir, const std::vector<Cam>& cams) {
  std::ofstream list(dir / "cameras.json");
  list << R"({"cameras":[)";
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const Cam& c = cams[i];
    const Image photo = test::constant_image(
        64, 64, Rgba{float(c.level / 255), float(c.level / 255), float(c.level / 255), 1});
    EXPECT_TRUE(write_image(dir / c.image, photo.view()));
    list << (i ? "," : "") << R"({"kind":"camera","model":"PINHOLE","width":64,"height":64,)"
         << R"("params":[32,32,32,32],"pose":{"eye":[)" << c.eye[0] << "," << c.eye[1] << ","
         << c.eye[2] << R"(],"target":[0,0,0],"up":[)" << c.up[0] << "," << c.up[1] << ","
         << c.up[2] << R"(]},"image":")" << c.image << R"("})";
  }
  list << "]}";
  return dir / "cameras.json";
}

LayersSpec layers(const fs::path& dir, const std::string& text) {
  std::ofstream(dir / "layers.json") << text;
  Expected<LayersSpec> spec = read_layers(dir / "layers.json");
  EXPECT_TRUE(spec) << spec.error().message;
  return spec ? *spec : LayersSpec{};
}

const Cam kTop{"top.png", {0, 0, 3}, {0, 1, 0}, 153};  // sRGB 0.6

TEST(LayersCameras, OverTheBaseAtAnOpacityByHand) {
  const fs::path dir = test_dir();
  write_cameras(dir, {kTop});
  const LayersSpec spec = layers(dir, R"({"base":[0.2,0.2,0.2,1],
      "layers":[{"cameras":"cameras.json","opacity":0.5}]})");
  const MeshData mesh = plane_mesh();
  Expected<LayerColors> baked = bake_vertex_colors_from_layers(mesh, spec, {});
  ASSERT_TRUE(baked) << baked.error().message;
  const double want = to_srgb(0.5 * to_linear(0.6) + 0.5 * to_linear(0.2));
  ASSERT_EQ(baked->colors.size(), 81u);
  for (const Rgba& c : baked->colors) {
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(c[ch], want, 1e-5);
    EXPECT_NEAR(c[3], 1, 1e-6);
  }
  ASSERT_EQ(baked->layers.size(), 1u);
  const LayerStats& s = baked->layers[0];
  EXPECT_TRUE(s.photos);
  EXPECT_EQ(s.name, "cameras.json");
  EXPECT_EQ(s.in_domain, 81u);
  EXPECT_EQ(s.visible, 81u);
  EXPECT_EQ(s.blended, 81u);
  EXPECT_NEAR(s.mean_alpha, 0.5, 1e-6);
}

// Two photos of the plane at levels 153 and 77: the exposure gains make
// them agree (geometric mean 1), so every vertex, whichever photos see it
// and whatever their blend weights, is sqrt(l1 l2) in linear light (the
// weak prior towards 1 moves that by about 1e-4).
TEST(LayersCameras, ExposureGainsMakeThePhotosAgree) {
  const fs::path dir = test_dir();
  write_cameras(dir, {kTop, Cam{"side.png", {1.2, 0.4, 2.8}, {0, 1, 0}, 77}});
  const LayersSpec spec = layers(dir, R"({"layers":[{"cameras":"cameras.json"}]})");
  Expected<LayerColors> baked = bake_vertex_colors_from_layers(plane_mesh(), spec, {});
  ASSERT_TRUE(baked) << baked.error().message;
  const double want = to_srgb(std::sqrt(to_linear(153 / 255.0) * to_linear(77 / 255.0)));
  for (const Rgba& c : baked->colors) {
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(c[ch], want, 1e-3);
    EXPECT_NEAR(c[3], 1, 1e-6);  // coverage over "none"
  }
}

// One camera low over the plane: at each vertex theta is the angle between
// +z and the direction to the camera; the fade [60, 80] gives
// a = (80 - theta) / 20, and past 75 degrees the camera does not see the
// point at all (SPEC section 9's cut), so the base stays.
TEST(LayersCameras, AngleFadeAtTheAngleToTheCameraAndThe75DegreeCut) {
  const fs::path dir = test_dir();
  const std::array<double, 3> eye{0, -5, 1.5};
  write_cameras(dir, {Cam{"low.png", eye, {0, 0, 1}, 153}});
  const LayersSpec spec = layers(dir, R"({"base":[0.2,0.2,0.2,1],
      "layers":[{"cameras":"cameras.json","angle_fade":[60,80]}]})");
  const MeshData mesh = plane_mesh();
  Expected<LayerColors> baked = bake_vertex_colors_from_layers(mesh, spec, {});
  ASSERT_TRUE(baked) << baked.error().message;
  std::size_t cut = 0, faded = 0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Float3& p = mesh.positions[v];
    const double dx = eye[0] - p.x, dy = eye[1] - p.y, dz = eye[2] - p.z;
    const double theta =
        std::acos(dz / std::sqrt(dx * dx + dy * dy + dz * dz)) * 180 / std::numbers::pi;
    double want = 0.2;
    if (std::abs(theta - 75) < 0.05) continue;  // too close to the cut to say
    if (theta < 75) {
      const double a = std::clamp((80 - theta) / 20, 0.0, 1.0);
      want = to_srgb(a * to_linear(0.6) + (1 - a) * to_linear(0.2));
      ++faded;
    } else {
      ++cut;
    }
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(baked->colors[v][ch], want, 1e-5) << "vertex " << v;
  }
  EXPECT_GT(cut, 5u);
  EXPECT_GT(faded, 30u);
}

TEST(LayersCameras, OccludedPointsKeepTheLayersBelow) {
  const fs::path dir = test_dir();
  write_cameras(dir, {kTop});
  const LayersSpec spec = layers(dir, R"({"base":[0.2,0.2,0.2,1],
      "layers":[{"cameras":"cameras.json"}]})");
  const MeshData mesh = plane_mesh(true);
  Expected<LayerColors> baked = bake_vertex_colors_from_layers(mesh, spec, {});
  ASSERT_TRUE(baked) << baked.error().message;
  for (std::size_t v = 0; v < 81; ++v) {  // the plane's vertices, x = -1, -0.75, ..., 1
    const double x = mesh.positions[v].x;
    const double want = x <= -0.45 ? 0.2 : 0.6;
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(baked->colors[v][ch], want, 1e-5) << "x " << x;
  }
}

// The atlas target through the mesh's UVs (a 64 atlas: the plane's
// x = 4 u - 1, 16 texels per unit): texels away from the chart's border and
// the shadow's edge are the over mix, or the base in the shadow.
TEST(LayersCameras, AtlasTexelsMixOrKeepTheBaseInTheShadow) {
  const fs::path dir = test_dir();
  write_cameras(dir, {kTop});
  const LayersSpec spec = layers(dir, R"({"base":[0.2,0.2,0.2,1],
      "layers":[{"cameras":"cameras.json","opacity":0.5}]})");
  AtlasOptions atlas;
  atlas.uv = UvLayout::kMesh;
  atlas.bake.size = 64;
  atlas.bake.samples = 4;
  Expected<LayerAtlas> baked = bake_atlas_texture_from_layers(plane_mesh(true), spec, {}, atlas);
  ASSERT_TRUE(baked) << baked.error().message;
  const Image& img = baked->atlas.image;
  ASSERT_EQ(img.width, 64);
  const double mix = to_srgb(0.5 * to_linear(0.6) + 0.5 * to_linear(0.2));
  std::size_t checked = 0;
  for (int y = 2; y < 62; ++y) {
    for (int x = 1; x < 31; ++x) {
      const double px = (x + 0.5) / 64 * 4 - 1;  // the texel centre's x on the plane
      double want;
      if (px < -0.75) {
        want = 0.2;  // all its samples (x within 1/32 of px) in the shadow
      } else if (px > 0.1 && px < 0.9) {
        want = mix;
      } else {
        continue;
      }
      const float* p = &img.pixels[4 * (static_cast<std::size_t>(y) * 64 + x)];
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(p[ch], want, 1e-5) << x << "," << y;
      EXPECT_NEAR(p[3], 1, 1e-6);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 900u);  // 60 rows x (2 + 13) columns
  ASSERT_EQ(baked->layers.size(), 1u);
  EXPECT_TRUE(baked->layers[0].photos);
  EXPECT_GT(baked->layers[0].visible, 0u);
  EXPECT_LT(baked->layers[0].visible, baked->layers[0].in_domain);  // the shadow
}

// The two calls over a Bake (texbake.h, "One bake description, two
// targets"): bakes of the three kinds in one list go through the same two
// calls with no branch per kind. Each bake has an option that is not the
// default and changes the result, so a dispatch that dropped the kind's
// options would fail: the image (level 51) through a plane proxy over the
// left half (x < 0) with an --outside colour for the right half (the
// atlas's own shading, clamp, must not replace it); a photo (level 153)
// from a camera so close that it sees only |x|, |y| < 0.5, the rest taking
// an --occluded colour; the same photo as a layer over "none", whose
// uncovered points take the --occluded colour's RGB with alpha 0. Each
// result carries its kind's figures (cameras for photos, layers for a
// stack, neither for an image). Per vertex, and per texel of a 16 atlas
// (texel centres and their samples never straddle x = 0 or |x|, |y| = 0.5).
TEST(OneBakeDescription, EveryKindThroughTheSameTwoCallsWithItsOwnOptions) {
  const fs::path dir = test_dir();
  const fs::path list = write_cameras(dir, {Cam{"near.png", {0, 0, 0.5}, {0, 1, 0}, 153}});
  Expected<std::vector<Photo>> photos = read_cameras(list);
  ASSERT_TRUE(photos) << photos.error().message;
  const Image image = test::constant_image(8, 8, Rgba{0.2f, 0.2f, 0.2f, 1});
  Expected<Proxy> plane = make_proxy(PlaneParams{{-1, -1, 0}, {1, 0, 0}, {0, 2, 0}});
  ASSERT_TRUE(plane);
  const Rgba other{0.8f, 0.7f, 0.1f, 1};
  VertexBakeOptions image_options;
  image_options.outside = OutsideMode::kColor;
  image_options.outside_color = other;
  PhotoBakeOptions photo_options;
  photo_options.occluded = OccludedMode::kColor;
  photo_options.occluded_color = other;
  LayersBakeOptions layer_options;
  layer_options.occluded = OccludedMode::kColor;
  layer_options.occluded_color = other;
  const std::vector<Bake> bakes{
      ImageProjection{image.view(), *plane, image_options},
      PhotoProjection{*photos, photo_options},
      LayersProjection{layers(dir, R"({"layers":[{"cameras":"cameras.json"}]})"), layer_options},
  };
  // The colour at (x, y) by hand, and whether to check it (not on a border).
  const auto want = [&](std::size_t kind, double x, double y) -> std::optional<Rgba> {
    if (kind == 0) {
      if (std::abs(x) < 1e-9) return std::nullopt;
      return x < 0 ? Rgba{0.2f, 0.2f, 0.2f, 1} : other;
    }
    if (std::abs(std::abs(x) - 0.5) < 1e-9 || std::abs(std::abs(y) - 0.5) < 1e-9) {
      return std::nullopt;
    }
    const bool seen = std::abs(x) < 0.5 && std::abs(y) < 0.5;
    if (seen) return Rgba{0.6f, 0.6f, 0.6f, 1};
    return kind == 1 ? other : Rgba{other[0], other[1], other[2], 0};
  };
  const MeshData mesh = plane_mesh();
  AtlasOptions atlas;
  atlas.uv = UvLayout::kMesh;
  atlas.bake.size = 16;
  for (std::size_t k = 0; k < bakes.size(); ++k) {
    SCOPED_TRACE("bake " + std::to_string(k));
    Expected<VertexColors> vertex = bake_vertex_colors(mesh, bakes[k]);
    ASSERT_TRUE(vertex) << vertex.error().message;
    ASSERT_EQ(vertex->colors.size(), 81u);
    std::size_t checked = 0, seen = 0;
    for (std::size_t v = 0; v < 81; ++v) {
      const Float3& p = mesh.positions[v];
      const std::optional<Rgba> w = want(k, p.x, p.y);
      if (!w) continue;
      ++checked;
      seen += (*w)[0] == 0.6f;
      for (int ch = 0; ch < 4; ++ch) {
        ASSERT_NEAR(vertex->colors[v][ch], (*w)[ch], 2e-3) << "vertex " << v << " ch " << ch;
      }
    }
    // 81 less the column x = 0, or 7 x 7 off the lines |x|, |y| = 0.5.
    EXPECT_EQ(checked, k == 0 ? 72u : 49u);
    EXPECT_EQ(seen, k == 0 ? 0u : 9u);

    Expected<BakedAtlas> baked = bake_atlas_texture(mesh, bakes[k], atlas);
    ASSERT_TRUE(baked) << baked.error().message;
    const Image& img = baked->atlas.image;
    ASSERT_EQ(img.width, 16);
    std::size_t texels = 0;
    for (int y = 0; y < 16; ++y) {
      for (int x = 0; x < 8; ++x) {  // inside the chart u in [0, 0.5]
        const double px = (x + 0.5) / 16 * 4 - 1, py = (y + 0.5) / 16 * 2 - 1;
        const std::optional<Rgba> w = want(k, px, py);
        ASSERT_TRUE(w);
        const float* t = &img.pixels[4 * (static_cast<std::size_t>(y) * 16 + x)];
        for (int ch = 0; ch < 4; ++ch) {
          ASSERT_NEAR(t[ch], (*w)[ch], 1e-5) << x << "," << y << " ch " << ch;
        }
        ++texels;
      }
    }
    EXPECT_EQ(texels, 128u);
    // Each kind's own figures, and only those.
    const std::size_t cameras = k == 1 ? 1 : 0, stack = k == 2 ? 1 : 0;
    EXPECT_EQ(vertex->cameras.size(), cameras);
    EXPECT_EQ(baked->cameras.size(), cameras);
    EXPECT_EQ(vertex->layers.size(), stack);
    EXPECT_EQ(baked->layers.size(), stack);
    if (cameras) {
      // |x|, |y| <= 0.5: the photo's edge is in view (at border weight 0).
      EXPECT_EQ(vertex->cameras[0].visible, 25u);
      EXPECT_EQ(baked->cameras[0].visible,
                baked->atlas.stats.counts.samples - baked->atlas.stats.counts.occluded);
    }
  }
}

TEST(LayersCameras, MissingCamerasOrPhotosAreInputErrors) {
  const fs::path dir = test_dir();
  {
    const LayersSpec spec = layers(dir, R"({"layers":[{"cameras":"nowhere.json"}]})");
    Expected<LayerColors> baked = bake_vertex_colors_from_layers(plane_mesh(), spec, {});
    ASSERT_FALSE(baked);
    EXPECT_EQ(category(baked.error()), ErrorCategory::kInput);
    EXPECT_NE(baked.error().message.find("layers[0]"), std::string::npos) << baked.error().message;
    EXPECT_NE(baked.error().message.find("nowhere.json"), std::string::npos)
        << baked.error().message;
  }
  {
    write_cameras(dir, {kTop});
    fs::remove(dir / "top.png");
    const LayersSpec spec = layers(dir, R"({"layers":[{"cameras":"cameras.json"}]})");
    Expected<LayerColors> baked = bake_vertex_colors_from_layers(plane_mesh(), spec, {});
    ASSERT_FALSE(baked);
    EXPECT_EQ(category(baked.error()), ErrorCategory::kInput);
    EXPECT_NE(baked.error().message.find("top.png"), std::string::npos) << baked.error().message;
  }
}

}  // namespace
}  // namespace texbake
