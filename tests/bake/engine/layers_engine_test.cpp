// The layers engine as the single-proxy bake (issue 29 items 1-2): a proxy
// bake and the equivalent one-layer stack (base "none", the proxy's working
// space: the stored encoding, straight alpha; outside clamp) give the same
// 8-bit colours, byte for byte, for the vertex target under the area and
// EWA filters and for the atlas target under EWA; and a filter that does
// not apply to a projector is refused. The proxy bakes are the engine's
// single-projection rule over one layer (ResultAlpha::kImage:
// bake/engine/bake_vertex.cpp, bake_atlas.cpp), held by their own golden
// and reference tests; these check that a stack's coverage rule agrees
// with it where the image is opaque, as SPEC section 10 says it must.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bake/engine/bake_atlas.h"
#include "bake/engine/bake_vertex.h"
#include "bake/engine/layers_bake.h"
#include "bake/util/parallel.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

// An opaque sRGB image with detail at every scale: colour ramps plus a
// checker of period 2 texels (which the EWA filter averages away when
// minifying, and bilinear does not).
std::vector<float> detailed_image(int w, int h) {
  std::vector<float> px;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float check = ((x / 2 + y / 2) % 2) ? 0.8f : 0.1f;
      px.insert(px.end(), {static_cast<float>(x) / w, check, static_cast<float>(y) / h, 1.f});
    }
  }
  return px;
}

// What a PLY or PNG stores: the 8-bit value of each channel.
std::array<int, 4> bytes(const Rgba& c) {
  std::array<int, 4> b;
  for (int k = 0; k < 4; ++k)
    b[k] = static_cast<int>(std::lround(std::clamp(c[k], 0.f, 1.f) * 255));
  return b;
}

// The one-layer stack equivalent to a proxy bake with `filter`.
LayerInput proxy_layer(const ImageView& image, const Proxy& proxy, VertexFilter filter,
                       int samples = 16) {
  LayerInput in;
  in.name = "proxy";
  in.projector = proxy;
  in.texture = image;
  in.visibility = LayerVisibility::kAll;
  in.outside = LayerOutside::kClamp;
  in.filter = filter;
  in.samples = samples;
  in.linear = false;  // the single-proxy bake's working space
  return in;
}

void expect_same_vertex_bytes(VertexFilter filter) {
  const MeshData mesh = test::uv_sphere({0, 0, 0}, 1, 10, 20);
  Expected<Proxy> sphere = make_proxy(SphereParams{{0, 0, 0}, 2, {0, 0, 1}, Vec3{1, 0, 0}});
  ASSERT_TRUE(sphere);
  const int w = 128, h = 64;  // minified: ~20 vertices around 128 texels
  const std::vector<float> px = detailed_image(w, h);
  const ImageView image{w, h, px.data(), ColorSpace::kSrgb};

  VertexBakeOptions po;
  po.filter = filter;
  po.visibility = Visibility::kAll;
  Expected<VertexBakeResult> proxy = bake_vertex(mesh, image, *sphere, po);
  ASSERT_TRUE(proxy) << proxy.error().message;
  Expected<LayersBakeResult> layers =
      bake_vertex_layers(mesh, {proxy_layer(image, *sphere, filter)}, LayersBakeOptions{});
  ASSERT_TRUE(layers) << layers.error().message;
  ASSERT_EQ(proxy->colors.size(), layers->colors.size());
  std::size_t differ = 0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    differ += bytes(proxy->colors[v]) != bytes(layers->colors[v]);
  }
  EXPECT_EQ(differ, 0u) << "of " << mesh.positions.size() << " vertices";
  EXPECT_EQ(layers->uncovered, 0u);
}

TEST(LayersEngine, AreaFilterLayerIsTheProxyVertexBakeByteForByte) {
  expect_same_vertex_bytes(VertexFilter::kArea);
}

TEST(LayersEngine, EwaLayerIsTheProxyVertexBakeByteForByte) {
  expect_same_vertex_bytes(VertexFilter::kEwa);
}

TEST(LayersEngine, BilinearLayerIsTheProxyVertexBakeByteForByte) {
  expect_same_vertex_bytes(VertexFilter::kBilinear);
}

TEST(LayersEngine, FiltersDifferFromBilinearWhereTheImageIsMinified) {
  // The equality above is not that of three identical lookups: minifying
  // the checker, area and EWA move the colours away from bilinear.
  const MeshData mesh = test::uv_sphere({0, 0, 0}, 1, 10, 20);
  Expected<Proxy> sphere = make_proxy(SphereParams{{0, 0, 0}, 2, {0, 0, 1}, Vec3{1, 0, 0}});
  ASSERT_TRUE(sphere);
  const std::vector<float> px = detailed_image(128, 64);
  const ImageView image{128, 64, px.data(), ColorSpace::kSrgb};
  auto bake = [&](VertexFilter f) {
    Expected<LayersBakeResult> r =
        bake_vertex_layers(mesh, {proxy_layer(image, *sphere, f)}, LayersBakeOptions{});
    EXPECT_TRUE(r);
    return r->colors;
  };
  const std::vector<Rgba> bilinear = bake(VertexFilter::kBilinear);
  for (VertexFilter f : {VertexFilter::kArea, VertexFilter::kEwa}) {
    const std::vector<Rgba> other = bake(f);
    std::size_t differ = 0;
    for (std::size_t v = 0; v < other.size(); ++v) differ += bytes(other[v]) != bytes(bilinear[v]);
    EXPECT_GT(differ, other.size() / 4);
  }
}

// A wavy unit grid (z = 0.2 sin(pi x)) with UVs (x, y): the atlas's layout.
MeshData wavy_grid() {
  MeshData mesh;
  test::append_grid(mesh, 12, 12, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t),
                  static_cast<float>(0.2 * std::sin(std::numbers::pi * s))};
  });
  test::faces_from_triangles(mesh);
  std::vector<Float2> uvs;
  for (const Float3& p : mesh.positions) uvs.push_back({p.x, p.y});
  return mesh_with_triangle_uvs(mesh, uvs, mesh.triangles);
}

TEST(LayersEngine, EwaLayerIsTheProxyAtlasBakeByteForByte) {
  const MeshData mesh = wavy_grid();
  Expected<Proxy> plane = make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  ASSERT_TRUE(plane);
  const int w = 256, h = 256;  // 8:1 minified onto the 32-texel atlas
  const std::vector<float> px = detailed_image(w, h);
  const ImageView image{w, h, px.data(), ColorSpace::kSrgb};
  for (int samples : {1, 4}) {
    AtlasBakeOptions ao;
    ao.size = 32;
    ao.samples = samples;
    ao.padding = 2;
    ao.shading.filter = VertexFilter::kEwa;
    ao.shading.visibility = Visibility::kAll;
    Expected<AtlasBakeResult> proxy = bake_atlas(mesh, image, *plane, ao);
    ASSERT_TRUE(proxy) << proxy.error().message;
    LayersAtlasOptions lo;
    lo.size = ao.size;
    lo.samples = samples;
    lo.padding = ao.padding;
    Expected<LayersAtlasResult> layers =
        bake_atlas_layers(mesh, {proxy_layer(image, *plane, VertexFilter::kEwa)}, lo);
    ASSERT_TRUE(layers) << layers.error().message;
    ASSERT_EQ(proxy->baked, layers->baked);
    std::size_t differ = 0, texels = 0;
    for (std::size_t t = 0; t < proxy->baked.size(); ++t) {
      if (!proxy->baked[t]) continue;
      ++texels;
      const float* a = &proxy->atlas.pixels[4 * t];
      const float* b = &layers->atlas.pixels[4 * t];
      differ += bytes({a[0], a[1], a[2], a[3]}) != bytes({b[0], b[1], b[2], b[3]});
    }
    EXPECT_GT(texels, 900u);
    EXPECT_EQ(differ, 0u) << samples << " samples, of " << texels << " texels";
  }
}

TEST(LayersEngine, PlaneWrapRepeatTilesTheLayer) {
  // A plane over [0, 0.5]^2 repeated: the grid's point (0.75, 0.25) maps to
  // u = 1.5, i.e. the image's middle; clamped it would be its right edge.
  MeshData mesh;
  test::append_grid(mesh, 4, 4, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0.f};
  });
  test::faces_from_triangles(mesh);
  Expected<Proxy> plane = make_proxy(PlaneParams{{0, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0}});
  ASSERT_TRUE(plane);
  // Two texels: left black, right white; u = 0.5 is their bilinear middle.
  const std::vector<float> px = {0, 0, 0, 1, 1, 1, 1, 1};
  const ImageView image{2, 1, px.data(), ColorSpace::kLinear};
  LayerInput in = proxy_layer(image, *plane, VertexFilter::kBilinear);
  in.linear = true;
  in.outside = LayerOutside::kTransparent;
  in.plane_wrap = WrapMode::kRepeat;
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, LayersBakeOptions{});
  ASSERT_TRUE(r) << r.error().message;
  // Vertex (3, 1) of the 5 x 5 grid is (0.75, 0.25): u = 1.5 -> 0.5 (repeat),
  // between the texel centres 0.25 and 0.75 halfway: linear 0.5, encoded.
  const Rgba c = r->colors[1 * 5 + 3];
  const double half = 1.055 * std::pow(0.5, 1 / 2.4) - 0.055;
  EXPECT_NEAR(c[0], half, 1e-5);
  EXPECT_NEAR(c[3], 1, 1e-6);  // covered: nothing is outside a repeated plane
  EXPECT_EQ(r->uncovered, 0u);
}

TEST(LayersEngine, EwaThroughACameraIsRefused) {
  MeshData mesh;
  test::append_grid(mesh, 1, 1, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0.f};
  });
  test::faces_from_triangles(mesh);
  const std::vector<float> px = {1, 1, 1, 1};
  LayerInput in;
  in.name = "photo.png";
  Expected<CameraPose> pose = pose_from_look_at({0.5, 0.5, 3}, {0.5, 0.5, 0}, {0, 1, 0}, "pose");
  ASSERT_TRUE(pose);
  Expected<CameraProjector> camera =
      CameraProjector::make({CameraModel::kPinhole, 200, 200, {100, 100, 100, 100}, *pose});
  ASSERT_TRUE(camera) << camera.error().message;
  in.projector = *camera;
  in.texture = ImageView{1, 1, px.data(), ColorSpace::kSrgb};
  in.filter = VertexFilter::kEwa;
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, LayersBakeOptions{});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(r.error().message.find("photo.png: EWA"), std::string::npos) << r.error().message;
}

TEST(LayersEngine, StackIsIdenticalWithOneAndTwoThreads) {
  // A stack that takes every per-point path: a sphere under the area filter
  // with visibility rays (the grid and box shadow the sphere's top), a
  // camera with an angle fade (its segments, the smooth normals) and a
  // plane in multiply mode under EWA, over several blocks of vertices and
  // bands of atlas samples; then the uncovered vertices' fill. Colours,
  // counts and mean alphas are the same bits at one and two threads.
  MeshData mesh = test::uv_sphere({0, 0, 0}, 1.0, 80, 160);
  test::append_grid(mesh, 40, 40, [](double s, double t) {
    return Float3{static_cast<float>(0.4 * s - 0.2), static_cast<float>(0.4 * t - 0.2), 1.2f};
  });
  test::append_box(mesh, {-0.1f, -0.1f, 1.3f}, {0.1f, 0.1f, 1.4f});
  test::faces_from_triangles(mesh);
  ASSERT_GT(mesh.positions.size(), 3u * 4096);  // several of the engine's blocks
  const std::vector<float> px = detailed_image(64, 32);
  const ImageView image{64, 32, px.data(), ColorSpace::kSrgb};
  Expected<Proxy> sphere = make_proxy(SphereParams{{0, 0, 0}, 3, {0, 0, 1}, Vec3{1, 0, 0}});
  Expected<Proxy> plane = make_proxy(PlaneParams{{0, -1, 0}, {1, 0, 0}, {0, 2, 0}});  // x >= 0
  Expected<CameraPose> pose = pose_from_look_at({0, -3, 1}, {0, 0, 0}, {0, 0, 1}, "pose");
  ASSERT_TRUE(sphere && plane && pose);
  Expected<CameraProjector> camera =
      CameraProjector::make({CameraModel::kPinhole, 64, 32, {40, 40, 32, 16}, *pose});
  ASSERT_TRUE(camera) << camera.error().message;
  std::vector<LayerInput> stack(3);
  stack[0] = proxy_layer(image, *sphere, VertexFilter::kArea, 4);
  stack[0].visibility = LayerVisibility::kFirst;
  stack[0].linear = true;
  stack[1].name = "camera";
  stack[1].projector = *camera;
  stack[1].texture = image;
  stack[1].angle_fade = std::array<double, 2>{30, 70};
  stack[2] = proxy_layer(image, *plane, VertexFilter::kEwa);
  stack[2].linear = true;
  stack[2].mode = LayerMode::kMultiply;
  stack[2].outside = LayerOutside::kTransparent;

  struct Run {
    std::vector<Rgba> colors;
    std::vector<float> atlas;
    std::vector<LayerStats> vertex_stats, atlas_stats;
    std::size_t uncovered = 0;
  };
  const MeshData uv_mesh = [&] {
    std::vector<Float2> uvs;
    for (const Float3& p : mesh.positions) uvs.push_back({0.5f + 0.4f * p.x, 0.5f + 0.4f * p.y});
    return mesh_with_triangle_uvs(mesh, uvs, mesh.triangles);
  }();
  const auto run = [&](int threads) {
    ThreadLimit limit(threads);
    Run out;
    Expected<LayersBakeResult> v = bake_vertex_layers(mesh, stack, LayersBakeOptions{});
    EXPECT_TRUE(v) << v.error().message;
    out.colors = v->colors;
    out.vertex_stats = v->layers;
    out.uncovered = v->uncovered;
    LayersAtlasOptions ao;
    ao.size = 96;
    ao.samples = 4;
    Expected<LayersAtlasResult> a = bake_atlas_layers(uv_mesh, stack, ao);
    EXPECT_TRUE(a) << a.error().message;
    out.atlas = a->atlas.pixels;
    out.atlas_stats = a->layers;
    return out;
  };
  const Run one = run(1), two = run(2);
  EXPECT_EQ(one.colors, two.colors);
  EXPECT_EQ(one.atlas, two.atlas);
  EXPECT_EQ(one.uncovered, two.uncovered);
  EXPECT_GT(one.uncovered, 0u);  // the fill ran
  for (const auto* stats : {&one.vertex_stats, &one.atlas_stats}) {
    const auto& other = stats == &one.vertex_stats ? two.vertex_stats : two.atlas_stats;
    ASSERT_EQ(stats->size(), 3u);
    ASSERT_EQ(other.size(), 3u);
    for (std::size_t l = 0; l < 3; ++l) {
      EXPECT_EQ((*stats)[l].in_domain, other[l].in_domain) << l;
      EXPECT_EQ((*stats)[l].visible, other[l].visible) << l;
      EXPECT_EQ((*stats)[l].blended, other[l].blended) << l;
      EXPECT_EQ((*stats)[l].mean_alpha, other[l].mean_alpha) << l;
      EXPECT_GT((*stats)[l].blended, 0u) << l;  // every layer reaches some point
    }
    // The sphere's rays are blocked under the grid: seen < mapped.
    EXPECT_LT((*stats)[0].visible, (*stats)[0].in_domain);
  }
}

TEST(LayersEngine, SingleProjectionRuleTakesOneBareLayer) {
  // ResultAlpha::kImage (the proxy vertex bake's rules) takes one layer that
  // is the projection alone; anything a stack adds is refused, not ignored.
  const MeshData mesh = test::uv_sphere({0, 0, 0}, 1, 6, 12);
  Expected<Proxy> sphere = make_proxy(SphereParams{{0, 0, 0}, 2, {0, 0, 1}, Vec3{1, 0, 0}});
  ASSERT_TRUE(sphere);
  const std::vector<float> px = detailed_image(16, 8);
  const ImageView image{16, 8, px.data(), ColorSpace::kSrgb};
  LayersBakeOptions single;
  single.alpha = ResultAlpha::kImage;
  const LayerInput bare = proxy_layer(image, *sphere, VertexFilter::kBilinear);
  ASSERT_TRUE(bake_vertex_layers(mesh, {bare}, single));
  const auto refused = [&](std::vector<LayerInput> stack, LayersBakeOptions options) {
    Expected<LayersBakeResult> r = bake_vertex_layers(mesh, stack, options);
    if (r) return testing::AssertionFailure() << "baked";
    if (r.error().code != ErrorCode::kInvalidArgument ||
        r.error().message.find("single-projection") == std::string::npos) {
      return testing::AssertionFailure() << r.error().message;
    }
    return testing::AssertionSuccess();
  };
  EXPECT_TRUE(refused({bare, bare}, single));
  LayerInput faded = bare;
  faded.opacity = 0.5;
  EXPECT_TRUE(refused({faded}, single));
  LayerInput transparent = bare;
  transparent.outside = LayerOutside::kTransparent;
  EXPECT_TRUE(refused({transparent}, single));
  LayerInput multiply = bare;
  multiply.mode = LayerMode::kMultiply;
  EXPECT_TRUE(refused({multiply}, single));
  LayersBakeOptions based = single;
  based.base = LayerBase::kColor;
  EXPECT_TRUE(refused({bare}, based));
  LayerInput premultiplied = bare;  // linear light, but not straight
  premultiplied.linear = true;
  EXPECT_TRUE(refused({premultiplied}, single));
  premultiplied.straight = true;  // --linear's working space
  EXPECT_TRUE(bake_vertex_layers(mesh, {premultiplied}, single));
  // The atlas target takes the same rule, and refuses the same stacks.
  std::vector<Float2> uvs;
  for (const Float3& p : mesh.positions) uvs.push_back({0.5f + 0.4f * p.x, 0.5f + 0.4f * p.y});
  const MeshData uv_mesh = mesh_with_triangle_uvs(mesh, uvs, mesh.triangles);
  LayersAtlasOptions atlas;
  atlas.size = 16;
  atlas.layers = single;
  EXPECT_TRUE(bake_atlas_layers(uv_mesh, {bare}, atlas));
  for (const std::vector<LayerInput>& stack :
       {std::vector<LayerInput>{bare, bare}, std::vector<LayerInput>{faded},
        std::vector<LayerInput>{transparent}, std::vector<LayerInput>{multiply}}) {
    Expected<LayersAtlasResult> a = bake_atlas_layers(uv_mesh, stack, atlas);
    ASSERT_FALSE(a);
    EXPECT_EQ(a.error().code, ErrorCode::kInvalidArgument);
    EXPECT_NE(a.error().message.find("single-projection"), std::string::npos) << a.error().message;
  }
}

TEST(LayersEngine, ProxyVertexBakeIsTheSameOverASharedScene) {
  // The atlas's fill passes its scene to the vertex bake: the same colours
  // and counts as the bake that builds its own (a grid shadows the sphere).
  MeshData mesh = test::uv_sphere({0, 0, 0}, 1, 20, 40);
  test::append_grid(mesh, 8, 8, [](double s, double t) {
    return Float3{static_cast<float>(s - 0.5), static_cast<float>(t - 0.5), 1.5f};
  });
  test::faces_from_triangles(mesh);
  Expected<Proxy> plane = make_proxy(PlaneParams{{-1, -1, 0}, {2, 0, 0}, {0, 2, 0}});
  ASSERT_TRUE(plane);
  const std::vector<float> px = detailed_image(32, 32);
  const ImageView image{32, 32, px.data(), ColorSpace::kSrgb};
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kLow);
  ASSERT_TRUE(scene);
  VertexBakeOptions o;
  Expected<VertexBakeResult> own = bake_vertex(mesh, image, *plane, o);
  Expected<VertexBakeStage> stage = bake_vertex_sample(mesh, image, *plane, o, nullptr, &*scene);
  ASSERT_TRUE(own && stage);
  Expected<VertexBakeResult> shared = bake_vertex_finish(mesh, std::move(stage).value());
  ASSERT_TRUE(shared);
  EXPECT_GT(own->counts.occluded, mesh.positions.size() / 3);  // the southern half and more
  EXPECT_EQ(own->counts.occluded, shared->counts.occluded);
  EXPECT_EQ(own->counts.samples, shared->counts.samples);
  EXPECT_EQ(own->colors, shared->colors);
  EXPECT_EQ(shared->timings.scene_build, 0.0);  // nothing built
}

TEST(LayersEngine, VertexStatsCountLookupsOutsideHiddenAndUnmapped) {
  // A unit uv_sphere (10 rings of 20: 182 vertices, z = cos(pi i / 10) on
  // ring i) under four one-layer stacks whose counts follow from the
  // positions alone.
  const MeshData mesh = test::uv_sphere({0, 0, 0}, 1, 10, 20);
  const std::size_t n = mesh.positions.size();
  ASSERT_EQ(n, 182u);
  const std::vector<float> px = detailed_image(16, 8);
  const ImageView image{16, 8, px.data(), ColorSpace::kSrgb};
  const auto stats = [&](const LayerInput& layer) {
    Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {layer}, LayersBakeOptions{});
    EXPECT_TRUE(r) << r.error().message;
    return r ? r->layers.at(0) : LayerStats{};
  };
  // A sphere proxy centred on the north pole: that vertex alone has no
  // mapping; one bilinear lookup per other vertex, none outside.
  Expected<Proxy> sphere = make_proxy(SphereParams{{0, 0, 1}, 2, {0, 0, 1}, Vec3{1, 0, 0}});
  ASSERT_TRUE(sphere);
  LayerStats s = stats(proxy_layer(image, *sphere, VertexFilter::kBilinear));
  EXPECT_EQ(s.unmapped, 1u);
  EXPECT_EQ(s.lookups, n - 1);
  EXPECT_EQ(s.outside, 0u);
  EXPECT_EQ(s.hidden, 0u);
  // The area filter: 5 lookups per vertex (every vertex has a share).
  s = stats(proxy_layer(image, *sphere, VertexFilter::kArea, 5));
  EXPECT_EQ(s.lookups, 5 * (n - 1));
  // A plane over x in [0, 1], clamped: the vertices with x < 0 look up
  // outside its domain (those at phi = 3 pi / 2 have x = -2e-16 from the
  // cosine's rounding: on the domain's edge, inside).
  Expected<Proxy> half = make_proxy(PlaneParams{{0, -1, 0}, {1, 0, 0}, {0, 2, 0}});
  ASSERT_TRUE(half);
  std::size_t west = 0;
  for (const Float3& p : mesh.positions) west += p.x < -1e-6f;
  ASSERT_EQ(west, 81u);  // 9 rings of 9 vertices with phi in (pi / 2, 3 pi / 2)
  s = stats(proxy_layer(image, *half, VertexFilter::kBilinear));
  EXPECT_EQ(s.lookups, n);
  EXPECT_EQ(s.outside, west);
  EXPECT_EQ(s.unmapped, 0u);
  // The plane over the whole sphere projecting along +z, with visibility:
  // the southern rings (6 to 9) and the south pole are behind the northern
  // half (81 vertices); the 20 on the equator graze it either way.
  Expected<Proxy> full = make_proxy(PlaneParams{{-1, -1, 0}, {2, 0, 0}, {0, 2, 0}});
  ASSERT_TRUE(full);
  LayerInput seen = proxy_layer(image, *full, VertexFilter::kBilinear);
  seen.visibility = LayerVisibility::kFirst;
  s = stats(seen);
  EXPECT_GE(s.hidden, 81u);
  EXPECT_LE(s.hidden, 101u);
  EXPECT_EQ(s.visible, n - s.hidden);
  EXPECT_EQ(s.lookups, s.visible);  // hidden vertices take no lookup
}

}  // namespace
}  // namespace texbake
