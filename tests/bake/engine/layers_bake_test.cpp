// bake_vertex_layers (SPEC section 10) on small meshes built in code, with
// every expected colour worked out by hand from the SPEC's formulas in
// linear light (sRGB decode/encode by the IEC 61966-2-1 formulas written
// out here, not texbake's).
#include "bake/engine/layers_bake.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

double to_linear(double s) {
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}
double to_srgb(double l) {
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
}

// A unit grid in the z = 0 plane (facing +z), 3 x 3 vertices.
MeshData flat_grid() {
  MeshData mesh;
  test::append_grid(mesh, 2, 2, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0.f};
  });
  test::faces_from_triangles(mesh);
  return mesh;
}

// The plane proxy over the unit square: (u, v) = (x, y), d(P) = +z.
Proxy unit_plane() {
  Expected<Proxy> p = make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  EXPECT_TRUE(p);
  return *p;
}

// An image held by the test, RGBA float.
struct TestImage {
  int w, h;
  std::vector<float> px;
  ColorSpace cs = ColorSpace::kSrgb;
  ImageView view() const { return {w, h, px.data(), cs}; }
};
TestImage constant(Rgba c, int w = 2, int h = 2) {
  TestImage t{w, h, {}};
  for (int i = 0; i < w * h; ++i) t.px.insert(t.px.end(), c.begin(), c.end());
  return t;
}

LayerInput layer(const TestImage& image, Proxy proxy = unit_plane()) {
  LayerInput in;
  in.name = "test";
  in.projector = proxy;
  in.texture = image.view();
  in.visibility = LayerVisibility::kAll;
  return in;
}

void expect_rgba(const Rgba& got, std::array<double, 4> want, double tol = 2e-6) {
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[c], want[c], tol) << "channel " << c;
}

TEST(LayersBake, OverAConstantBaseMixesInLinearLight) {
  const MeshData mesh = flat_grid();
  const TestImage red = constant({1, 0, 0, 1});
  LayerInput in = layer(red);
  in.opacity = 0.5;
  LayersBakeOptions options;
  options.base = LayerBase::kColor;
  options.base_color = {0, 0, 1, 1};
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, options);
  ASSERT_TRUE(r) << r.error().message;
  // C = 0.5 red + 0.5 blue in linear light: (0.5, 0, 0.5), encoded.
  const double half = to_srgb(0.5);
  for (const Rgba& c : r->colors) expect_rgba(c, {half, 0, half, 1});
  ASSERT_EQ(r->layers.size(), 1u);
  EXPECT_EQ(r->layers[0].in_domain, 9u);
  EXPECT_EQ(r->layers[0].visible, 9u);
  EXPECT_EQ(r->layers[0].blended, 9u);
  EXPECT_NEAR(r->layers[0].mean_alpha, 0.5, 1e-12);
  EXPECT_EQ(r->uncovered, 0u);
}

TEST(LayersBake, MultiplyAddAndReplace) {
  const MeshData mesh = flat_grid();
  const double grey = 0.5, l_grey = to_linear(grey);  // base: sRGB 0.5 grey
  const TestImage image = constant({0.6f, 0.6f, 0.6f, 1});
  const double l_img = to_linear(0.6);
  LayersBakeOptions options;
  options.base = LayerBase::kColor;
  options.base_color = {0.5f, 0.5f, 0.5f, 1};
  struct Case {
    LayerMode mode;
    double opacity, want_linear;
  };
  const Case cases[] = {
      {LayerMode::kMultiply, 1.0, l_grey * l_img},
      {LayerMode::kMultiply, 0.25, l_grey * (1 - 0.25 + 0.25 * l_img)},
      {LayerMode::kAdd, 0.5, l_grey + 0.5 * l_img},
      {LayerMode::kReplace, 0.3, l_img},
  };
  for (const Case& k : cases) {
    LayerInput in = layer(image);
    in.mode = k.mode;
    in.opacity = k.opacity;
    Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, options);
    ASSERT_TRUE(r) << r.error().message;
    const double s = to_srgb(k.want_linear);
    expect_rgba(r->colors[4], {s, s, s, 1}, 2e-6);
    (void)grey;
  }
}

TEST(LayersBake, CoverageOverBaseNone) {
  const MeshData mesh = flat_grid();
  const TestImage red = constant({1, 0, 0, 1}), green = constant({0, 1, 0, 1});
  LayerInput a = layer(red), b = layer(green);
  a.opacity = 0.5;
  b.opacity = 0.5;
  Expected<LayersBakeResult> one = bake_vertex_layers(mesh, {a}, {});
  ASSERT_TRUE(one);
  expect_rgba(one->colors[0], {1, 0, 0, 0.5});  // straight colour red, coverage 0.5
  Expected<LayersBakeResult> two = bake_vertex_layers(mesh, {a, b}, {});
  ASSERT_TRUE(two);
  // Coverage 1 - 0.5 * 0.5; colour (0.5 green + 0.5 * 0.5 red) / 0.75.
  expect_rgba(two->colors[0], {to_srgb(0.25 / 0.75), to_srgb(0.5 / 0.75), 0, 0.75});
}

TEST(LayersBake, TransparentBordersDoNotDarkenTheColour) {
  // Two texels: opaque red | transparent black. At u = 0.5 (the texels'
  // common edge) the bilinear lookup weighs them equally: premultiplied,
  // the colour stays red and the alpha is 0.5 (a straight average would give
  // dark red).
  MeshData mesh;
  mesh.positions = {{0.5f, 0.2f, 0}, {0.5f, 0.8f, 0}, {0.4f, 0.5f, 0}};
  mesh.triangles = {{0, 2, 1}};
  test::faces_from_triangles(mesh);
  TestImage label{2, 1, {1, 0, 0, 1, 0, 0, 0, 0}};
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {layer(label)}, {});
  ASSERT_TRUE(r) << r.error().message;
  expect_rgba(r->colors[0], {1, 0, 0, 0.5}, 1e-5);
  // u = 0.4: texel centres at 0.25 and 0.75: 70 % red.
  expect_rgba(r->colors[2], {1, 0, 0, 0.7}, 1e-5);
}

TEST(LayersBake, MaskIsTheGreyValueOrTheAlphaAsStored) {
  const MeshData mesh = flat_grid();
  const TestImage white = constant({1, 1, 1, 1});
  const TestImage grey_mask = constant({0.25f, 0.25f, 0.25f, 1});
  LayerInput in = layer(white);
  in.mask = grey_mask.view();
  in.mask_has_alpha = false;
  LayersBakeOptions options;
  options.base = LayerBase::kColor;
  options.base_color = {0, 0, 0, 1};
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, options);
  ASSERT_TRUE(r);
  const double s = to_srgb(0.25);  // a = 0.25 over black: linear 0.25
  expect_rgba(r->colors[4], {s, s, s, 1});
  const TestImage alpha_mask = constant({1, 1, 1, 0.75f});
  in.mask = alpha_mask.view();
  in.mask_has_alpha = true;
  r = bake_vertex_layers(mesh, {in}, options);
  ASSERT_TRUE(r);
  const double t = to_srgb(0.75);
  expect_rgba(r->colors[4], {t, t, t, 1});
}

TEST(LayersBake, AngleFadeFallsLinearlyBetweenTheAngles) {
  // Triangles tilted by 0, 65 and 85 degrees about the x axis: the angle
  // between their normal and d = +z. Fade [60, 70]: 1, 0.5, 0.
  MeshData mesh;
  for (int k = 0; k < 3; ++k) {
    const double deg = k == 0 ? 0 : k == 1 ? 65 : 85, a = deg * std::numbers::pi / 180;
    const float x0 = 0.1f + 0.3f * k;
    // Edge along x, and one along (0, cos a, sin a): normal (0, -sin a, cos a).
    const uint32_t b = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.push_back({x0, 0.2f, 0});
    mesh.positions.push_back({x0 + 0.2f, 0.2f, 0});
    mesh.positions.push_back({x0, 0.2f + 0.3f * static_cast<float>(std::cos(a)),
                              0.3f * static_cast<float>(std::sin(a))});
    mesh.triangles.push_back({b, b + 1, b + 2});
  }
  test::faces_from_triangles(mesh);
  const TestImage white = constant({1, 1, 1, 1});
  LayerInput in = layer(white);
  in.angle_fade = std::array<double, 2>{60, 70};
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, {});
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_NEAR(r->colors[0][3], 1.0, 1e-6);
  EXPECT_NEAR(r->colors[3][3], 0.5, 1e-4);
  EXPECT_NEAR(r->colors[6][3], 0.0, 1e-6);
}

TEST(LayersBake, OutsideTransparentClampOrAColour) {
  // A plane proxy covering x in [0, 0.5] only: the grid's right column is outside.
  const MeshData mesh = flat_grid();
  Expected<Proxy> half = make_proxy(PlaneParams{{0, 0, 0}, {0.5, 0, 0}, {0, 1, 0}});
  ASSERT_TRUE(half);
  TestImage image{2, 1, {1, 0, 0, 1, 0, 0, 1, 1}};  // red | blue
  LayerInput in = layer(image, *half);
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, {});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->layers[0].in_domain, 6u);  // x = 0 and x = 0.5 columns
  EXPECT_EQ(r->layers[0].blended, 6u);
  EXPECT_EQ(r->colors[2][3], 0.f);  // vertex (1, 0): transparent
  in.outside = LayerOutside::kClamp;
  r = bake_vertex_layers(mesh, {in}, {});
  ASSERT_TRUE(r);
  expect_rgba(r->colors[2], {0, 0, 1, 1});  // the edge texel (blue)
  in.outside = LayerOutside::kColor;
  in.outside_color = {0, 1, 0, 0.5f};
  r = bake_vertex_layers(mesh, {in}, {});
  ASSERT_TRUE(r);
  expect_rgba(r->colors[2], {0, 1, 0, 0.5});
}

TEST(LayersBake, VisibilityFirstHidesWhatAnOccluderCovers) {
  // A small occluding square at z = 0.5 over the grid's centre vertex.
  MeshData mesh = flat_grid();
  const uint32_t b = static_cast<uint32_t>(mesh.positions.size());
  mesh.positions.push_back({0.4f, 0.4f, 0.5f});
  mesh.positions.push_back({0.6f, 0.4f, 0.5f});
  mesh.positions.push_back({0.6f, 0.6f, 0.5f});
  mesh.positions.push_back({0.4f, 0.6f, 0.5f});
  mesh.triangles.push_back({b, b + 1, b + 2});
  mesh.triangles.push_back({b, b + 2, b + 3});
  test::faces_from_triangles(mesh);
  const TestImage red = constant({1, 0, 0, 1});
  LayerInput in = layer(red);
  in.visibility = LayerVisibility::kFirst;
  LayersBakeOptions options;
  options.occluded = OccludedMode::kColor;
  options.occluded_color = {0, 1, 0, 1};
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, options);
  ASSERT_TRUE(r) << r.error().message;
  expect_rgba(r->colors[4], {0, 1, 0, 0});  // hidden: the occluded colour, coverage 0
  expect_rgba(r->colors[0], {1, 0, 0, 1});
  EXPECT_EQ(r->layers[0].visible, 12u);  // 8 grid vertices and the occluder's 4
  EXPECT_EQ(r->uncovered, 1u);
}

TEST(LayersBake, ACameraSeesOnlyWhatFacesItInFront) {
  // A pinhole camera at z = 2 looking down at the grid: sees it; a second
  // grid facing away (normal -z) at the same place is not seen.
  MeshData mesh = flat_grid();
  const uint32_t b = static_cast<uint32_t>(mesh.positions.size());
  test::append_grid(mesh, 1, 1, [](double s, double t) {
    return Float3{static_cast<float>(2 + t), static_cast<float>(s), 0.f};  // normal -z
  });
  (void)b;
  test::faces_from_triangles(mesh);
  Expected<CameraPose> pose = pose_from_look_at({1.5, 0.5, 3}, {1.5, 0.5, 0}, {0, 1, 0}, "pose");
  ASSERT_TRUE(pose);
  Expected<CameraProjector> cam =
      CameraProjector::make({CameraModel::kPinhole, 200, 200, {100, 100, 100, 100}, *pose});
  ASSERT_TRUE(cam) << cam.error().message;
  const TestImage red = constant({1, 0, 0, 1});
  LayerInput in = layer(red);
  in.projector = *cam;
  in.visibility = LayerVisibility::kFirst;
  LayersBakeOptions options;
  options.occluded = OccludedMode::kColor;
  options.occluded_color = {0, 0, 1, 1};
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {in}, options);
  ASSERT_TRUE(r) << r.error().message;
  for (uint32_t v = 0; v < 9; ++v) expect_rgba(r->colors[v], {1, 0, 0, 1});
  for (uint32_t v = 9; v < 13; ++v) expect_rgba(r->colors[v], {0, 0, 1, 0});
  EXPECT_EQ(r->layers[0].in_domain, 13u);
  EXPECT_EQ(r->layers[0].visible, 9u);
}

TEST(LayersBake, UncoveredVerticesAreFilledWithAlphaZero) {
  // The half plane again, transparent outside: the right column is filled
  // from its neighbours (red on the left, blue in the middle column).
  const MeshData mesh = flat_grid();
  Expected<Proxy> half = make_proxy(PlaneParams{{0, 0, 0}, {0.5, 0, 0}, {0, 1, 0}});
  ASSERT_TRUE(half);
  const TestImage blue = constant({0, 0, 1, 1});
  Expected<LayersBakeResult> r = bake_vertex_layers(mesh, {layer(blue, *half)}, {});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->uncovered, 3u);
  EXPECT_EQ(r->filled, 3u);
  expect_rgba(r->colors[2], {0, 0, 1, 0}, 1e-5);  // the harmonic fill of a constant
  const MeshData empty_base = flat_grid();
  LayersBakeOptions mesh_base;
  mesh_base.base = LayerBase::kMesh;
  EXPECT_FALSE(bake_vertex_layers(empty_base, {layer(blue)}, mesh_base));  // no vertex colours
}

}  // namespace
}  // namespace texbake
