// render_preview: camera conventions, hand-computed Phong values, the
// projection's wrap and linear rules, analytic shadows, thread-count
// independence, contact sheets.
//
// All meshes are built here; the expected values come from the conventions
// stated in bake/render/render_preview.h worked out by hand (or analytically), not
// from the renderer's own helpers, except that the shadow test shoots its
// analytic rays through the renderer's Camera (the camera itself is checked
// separately in CameraConventions).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "bake/render/render_preview.h"
#include "bake/util/parallel.h"

namespace texbake {
namespace {

constexpr double kPi = std::numbers::pi;

// A MeshData from positions and triangles (each triangle its own face).
MeshData make_mesh(std::vector<Float3> positions, std::vector<std::array<uint32_t, 3>> tris) {
  MeshData m;
  m.positions = std::move(positions);
  m.face_offsets.push_back(0);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const uint32_t c = static_cast<uint32_t>(m.face_vertices.size());
    for (uint32_t v : tris[t]) m.face_vertices.push_back(v);
    m.face_offsets.push_back(c + 3);
    m.triangles.push_back(tris[t]);
    m.triangle_corners.push_back({c, c + 1, c + 2});
    m.triangle_face.push_back(static_cast<uint32_t>(t));
  }
  return m;
}

// The square x, z in [-1, 1] in the plane y = 0, facing -Y (the camera of
// view (0, 0)), with per-corner UVs u = (x+1)/2, v = (z+1)/2.
MeshData facing_quad() {
  MeshData m = make_mesh({{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}}, {{0, 2, 1}, {0, 3, 2}});
  // (v1 - v0) x (v2 - v0) for {0, 2, 1}: (2,0,2) x (2,0,0) = (0, 4, 0): +Y;
  // rendering is two-sided, so the winding does not matter.
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (uint32_t v : m.face_vertices) m.corner_uv.push_back(v);
  return m;
}

// Appends a UV sphere (lat x lon quads split in two) to `m`.
void add_sphere(MeshData& m, Vec3 c, double r, int lat, int lon) {
  std::vector<Float3> pos;
  std::vector<std::array<uint32_t, 3>> tris;
  const uint32_t base = static_cast<uint32_t>(m.positions.size());
  for (int i = 0; i <= lat; ++i) {
    const double th = kPi * i / lat;
    for (int j = 0; j < lon; ++j) {
      const double ph = 2 * kPi * j / lon;
      pos.push_back({static_cast<float>(c.x + r * std::sin(th) * std::cos(ph)),
                     static_cast<float>(c.y + r * std::sin(th) * std::sin(ph)),
                     static_cast<float>(c.z + r * std::cos(th))});
    }
  }
  auto id = [&](int i, int j) { return base + static_cast<uint32_t>(i * lon + (j % lon)); };
  for (int i = 0; i < lat; ++i) {
    for (int j = 0; j < lon; ++j) {
      if (i > 0) tris.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
      if (i < lat - 1) tris.push_back({id(i, j + 1), id(i + 1, j), id(i + 1, j + 1)});
    }
  }
  // Append to m (indices already offset by `base`).
  const uint32_t corner_base = static_cast<uint32_t>(m.face_vertices.size());
  const uint32_t face_base = static_cast<uint32_t>(m.triangles.size());
  if (m.face_offsets.empty()) m.face_offsets.push_back(0);
  m.positions.insert(m.positions.end(), pos.begin(), pos.end());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    for (uint32_t v : tris[t]) m.face_vertices.push_back(v);
    m.face_offsets.push_back(static_cast<uint32_t>(m.face_vertices.size()));
    m.triangles.push_back(tris[t]);
    const uint32_t c0 = corner_base + static_cast<uint32_t>(3 * t);
    m.triangle_corners.push_back({c0, c0 + 1, c0 + 2});
    m.triangle_face.push_back(face_base + static_cast<uint32_t>(t));
  }
}

// The floor square x, y in [-s, s] at z = 0.
MeshData floor_square(double s) {
  const float f = static_cast<float>(s);
  return make_mesh({{-f, -f, 0}, {f, -f, 0}, {f, f, 0}, {-f, f, 0}}, {{0, 1, 2}, {0, 2, 3}});
}

EmbreeScene build_scene(const MeshData& m) {
  auto scene = EmbreeScene::build(m, BuildQuality::kMedium);
  EXPECT_TRUE(scene.has_value()) << scene.error().message;
  return std::move(scene).value();
}

// Explicit Phong parameters, so the hand computations below do not depend on
// the defaults.
PhongParams test_phong() {
  PhongParams p;
  p.ambient = 0.2;
  p.key_direction = {-1, 1, 2};
  p.key_diffuse = 0.7;
  p.key_specular = 0.3;
  p.fill_direction = {1, 0, 1};
  p.fill_diffuse = 0.3;
  p.fill_specular = 0.0;
  p.shininess = 32;
  return p;
}

// Phong value (per channel) of albedo a on a surface facing the camera
// squarely (N = V = towards the camera). With lights given in the camera
// frame (right, up, back), N.L is the back component of the unit light
// direction: key (-1,1,2)/sqrt(6) -> 2/sqrt(6), fill (1,0,1)/sqrt(2) ->
// 1/sqrt(2). For V = N, R.V = 2 (N.L)(N.V) - L.V = N.L.
double facing_phong(double a) {
  const double key = 2 / std::sqrt(6.0), fill = 1 / std::sqrt(2.0);
  return a * (0.2 + 0.7 * key + 0.3 * fill) + 0.3 * std::pow(key, 32);
}

TEST(RenderPreview, CameraConventions) {
  BoundingSphere bs{{1, 2, 3}, 2};
  RenderOptions o;
  o.width = 64;
  o.height = 32;
  o.elevation_deg = 0;
  const double dist = kFrameMargin * 2 / std::sin(15 * kPi / 180);

  auto c0 = make_camera(bs, o, 0);
  ASSERT_TRUE(c0.has_value());
  // Azimuth 0 looks from -Y (up = +Z), right = +X, up = +Z.
  EXPECT_NEAR(c0->position.x, 1, 1e-9);
  EXPECT_NEAR(c0->position.y, 2 - dist, 1e-9);
  EXPECT_NEAR(c0->position.z, 3, 1e-9);
  EXPECT_NEAR(c0->right.x, 1, 1e-12);
  EXPECT_NEAR(c0->up.z, 1, 1e-12);
  EXPECT_NEAR(c0->forward.y, 1, 1e-12);
  // The image centre looks at the sphere's centre.
  const Ray centre = c0->ray(32, 16);
  EXPECT_NEAR(centre.direction.y, 1, 1e-12);
  // 30 degrees on the shorter (vertical) side: the ray through the top edge's
  // middle is 15 degrees off the axis, and the sphere (inflated by the margin)
  // is tangent to it.
  const Ray top = c0->ray(32, 0);
  EXPECT_NEAR(std::acos(dot(top.direction, c0->forward)) * 180 / kPi, 15, 1e-9);
  EXPECT_NEAR(length(cross(bs.center - top.origin, top.direction)), kFrameMargin * 2, 1e-9);
  // The left edge is wider by the aspect ratio: tan = 2 tan(15 deg).
  const Ray left = c0->ray(0, 16);
  EXPECT_NEAR(std::tan(std::acos(dot(left.direction, c0->forward))), 2 * std::tan(15 * kPi / 180),
              1e-9);
  EXPECT_LT(dot(left.direction, c0->right), 0);

  // Azimuth 90 looks from +X, counter-clockwise seen from above.
  auto c90 = make_camera(bs, o, 90);
  EXPECT_NEAR(c90->position.x, 1 + dist, 1e-9);
  EXPECT_NEAR(c90->right.y, 1, 1e-12);

  // Elevation 90: straight down, right = +X, image up = +Y.
  o.elevation_deg = 90;
  auto top_view = make_camera(bs, o, 0);
  EXPECT_NEAR(top_view->position.z, 3 + dist, 1e-9);
  EXPECT_NEAR(top_view->right.x, 1, 1e-12);
  EXPECT_NEAR(top_view->up.y, 1, 1e-12);

  // up = +Y (Stanford meshes): azimuth 0 looks from +Z, right = +X.
  o.elevation_deg = 0;
  o.up = {0, 5, 0};
  auto y_up = make_camera(bs, o, 0);
  EXPECT_NEAR(y_up->position.z, 3 + dist, 1e-9);
  EXPECT_NEAR(y_up->right.x, 1, 1e-12);
  EXPECT_NEAR(y_up->up.y, 1, 1e-12);

  o.up = {0, 0, 0};
  EXPECT_FALSE(make_camera(bs, o, 0).has_value());
  o.up = {0, 0, 1};
  o.elevation_deg = 91;
  EXPECT_FALSE(make_camera(bs, o, 0).has_value());
}

TEST(RenderPreview, FacingQuadCentreHasHandComputedPhongValue) {
  MeshData quad = facing_quad();
  quad.vertex_colors.assign(4, {0.8f, 0.4f, 0.2f, 1.0f});
  const EmbreeScene scene = build_scene(quad);
  RenderOptions o;
  o.width = o.height = 65;  // odd: pixel 32's centre ray is the optical axis
  o.elevation_deg = 0;
  o.phong = test_phong();
  auto img = render_preview(quad, scene, VertexColorSource{}, o);
  ASSERT_TRUE(img.has_value()) << img.error().message;
  const float* c = img->pixel(32, 32);
  // 0.8 * 0.983680 + 0.000457 = 0.787401; 0.393929; 0.197193.
  EXPECT_NEAR(c[0], facing_phong(0.8), 1e-5);
  EXPECT_NEAR(c[1], facing_phong(0.4), 1e-5);
  EXPECT_NEAR(c[2], facing_phong(0.2), 1e-5);
  EXPECT_NEAR(c[0], 0.787401, 1e-5);  // the same number, worked out by hand
  EXPECT_EQ(c[3], 1.0f);
  // The corner pixel sees past the quad: exactly the background, alpha 0.
  const float* bg = img->pixel(0, 0);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(bg[k], o.background[k]);
  EXPECT_EQ(bg[3], 0.0f);
}

// Issue #28 item 16: a colour's alpha (layers over base "none") composites
// the shaded colour over the background RGB. Exact, with no golden image:
// an atlas whose left half is transparent (alpha 0) renders there exactly
// as the background, its opaque right half as the hand-computed Phong
// value; vertex colours of alpha 0.25 give 0.25 x shaded + 0.75 x
// background. Coverage (the pixel's alpha) stays 1 on the quad.
TEST(RenderPreview, AlphaShowsTheBackgroundThroughTheSurface) {
  // 4x1 texture, alpha 0 in texels 0 and 1, 1 in texels 2 and 3 (u < 0.5
  // and u > 0.5 by at least a texel's half: bilinear lookups there see only
  // one kind).
  const std::vector<float> texels = {1,    0,    0,    0, 1,    0,    0,    0,
                                     0.8f, 0.4f, 0.2f, 1, 0.8f, 0.4f, 0.2f, 1};
  const ImageView tex{4, 1, texels.data()};
  MeshData quad = facing_quad();
  const EmbreeScene scene = build_scene(quad);
  RenderOptions o;
  o.width = o.height = 65;
  o.elevation_deg = 0;
  o.phong = test_phong();
  o.background = {0.25f, 0.5f, 0.75f, 0};
  auto atlas = render_preview(quad, scene, AtlasSource{tex}, o);
  ASSERT_TRUE(atlas.has_value()) << atlas.error().message;
  // Image x runs along +X, so u grows to the right: pixel columns 20 and 44
  // look at x ~ -0.57 and +0.57 (half the view is 1.54 wide there), u ~ 0.22
  // and 0.78, texel positions 0.37 and 2.63.
  const float* left = atlas->pixel(20, 32);
  const float* right = atlas->pixel(44, 32);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(left[k], o.background[k]) << k;
  EXPECT_EQ(left[3], 1.0f);  // the quad covers the pixel
  EXPECT_EQ(right[3], 1.0f);
  // The right half is opaque: shaded as before (not facing squarely off
  // the axis, so compared with an opaque render of the same texels).
  std::vector<float> opaque = texels;
  for (std::size_t i = 3; i < opaque.size(); i += 4) opaque[i] = 1;
  auto full = render_preview(quad, scene, AtlasSource{ImageView{4, 1, opaque.data()}}, o);
  ASSERT_TRUE(full.has_value());
  for (int k = 0; k < 4; ++k) EXPECT_EQ(right[k], full->pixel(44, 32)[k]) << k;
  EXPECT_NE(full->pixel(20, 32)[0], o.background[0]);  // red where the texels are opaque

  quad.vertex_colors.assign(4, {0.8f, 0.4f, 0.2f, 0.25f});
  auto quarter = render_preview(quad, scene, VertexColorSource{}, o);
  ASSERT_TRUE(quarter.has_value());
  const float* c = quarter->pixel(32, 32);
  const double shaded[3] = {facing_phong(0.8), facing_phong(0.4), facing_phong(0.2)};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(c[k], 0.25 * shaded[k] + 0.75 * o.background[k], 1e-6) << k;
  }
  EXPECT_EQ(c[3], 1.0f);
}

TEST(RenderPreview, AtlasAndProjectionSampleTheTextureAtTheHitPoint) {
  // 2x2 texture; at (u, v) = (0.5, 0.5) bilinear sampling averages all four
  // texels (SPEC section 1: x = 0.5 * 2 - 0.5 = 0.5): (0.5, 0.5, 0.5).
  const std::vector<float> texels = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1};
  const ImageView tex{2, 2, texels.data()};
  const MeshData quad = facing_quad();
  const EmbreeScene scene = build_scene(quad);
  RenderOptions o;
  o.width = o.height = 65;
  o.elevation_deg = 0;
  o.phong = test_phong();

  auto atlas = render_preview(quad, scene, AtlasSource{tex}, o);
  ASSERT_TRUE(atlas.has_value()) << atlas.error().message;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(atlas->pixel(32, 32)[k], facing_phong(0.5), 1e-5);

  // A plane proxy whose (u, v) equals the quad's UVs: origin (-1, 0, -1),
  // u_axis (2, 0, 0), v_axis (0, 0, 2).
  auto plane = make_proxy(PlaneParams{{-1, 0, -1}, {2, 0, 0}, {0, 0, 2}});
  ASSERT_TRUE(plane.has_value()) << plane.error().message;
  auto proj = render_preview(quad, scene, ProjectionSource{*plane, tex, std::nullopt}, o);
  ASSERT_TRUE(proj.has_value()) << proj.error().message;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(proj->pixel(32, 32)[k], facing_phong(0.5), 1e-5);
  // Same texture through the same (u, v) everywhere: the images agree.
  for (std::size_t i = 0; i < atlas->pixels.size(); ++i) {
    ASSERT_NEAR(atlas->pixels[i], proj->pixels[i], 1e-5) << "value " << i;
  }

  EXPECT_FALSE(render_preview(quad, scene, VertexColorSource{}, o).has_value());  // no colours
}

// Phong with the ambient term only (ambient 1): a pixel is its albedo.
PhongParams albedo_only() {
  PhongParams p;
  p.ambient = 1;
  p.key_diffuse = p.key_specular = p.fill_diffuse = p.fill_specular = 0;
  return p;
}

// The projected albedo at the facing quad's centre (0, 0, 0), the centre
// pixel of a 65 x 65 view (0, 0), through a plane with axes (2, 0, 0) and
// (0, 0, 2) at `origin`: (u, v) = (-origin.x / 2, -origin.z / 2).
class PlaneProjection : public testing::Test {
 protected:
  PlaneProjection() {
    // 4 x 2, top row first. Red: top row 0 .1 .2 .3, bottom row .4 .5 .6 .7;
    // green .5, blue .25. x = 4u - 0.5, y = 1.5 - 2v (SPEC section 1).
    const float red[2][4] = {{0.f, 0.1f, 0.2f, 0.3f}, {0.4f, 0.5f, 0.6f, 0.7f}};
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 4; ++x) texels_.insert(texels_.end(), {red[y][x], 0.5f, 0.25f, 1.f});
    }
    options_.width = options_.height = 65;
    options_.elevation_deg = 0;
    options_.phong = albedo_only();
  }
  RenderImage render(Vec3 origin, WrapMode wrap, std::optional<Rgba> outside = std::nullopt) {
    auto plane = make_proxy(PlaneParams{origin, {2, 0, 0}, {0, 0, 2}});
    EXPECT_TRUE(plane.has_value());
    ProjectionSource src{*plane, {4, 2, texels_.data()}, outside};
    src.plane_wrap = wrap;
    auto img = render_preview(quad_, scene_, src, options_);
    EXPECT_TRUE(img.has_value()) << img.error().message;
    return std::move(img).value();
  }
  float centre_red(Vec3 origin, WrapMode wrap, std::optional<Rgba> outside = std::nullopt) {
    return render(origin, wrap, outside).pixel(32, 32)[0];
  }

  std::vector<float> texels_;
  MeshData quad_ = facing_quad();
  EmbreeScene scene_ = build_scene(quad_);
  RenderOptions options_;
};

TEST_F(PlaneProjection, WrapRepeatTilesTheTextureInUAndV) {
  const WrapMode kRepeat = WrapMode::kRepeat, kClamp = WrapMode::kClamp;
  // (0.5, 0.5): x = 1.5, y = 0.5: (.1 + .2 + .5 + .6) / 4 = .35, either way.
  EXPECT_NEAR(centre_red({-1, 0, -1}, kRepeat), 0.35f, 1e-5);
  EXPECT_NEAR(centre_red({-1, 0, -1}, kClamp), 0.35f, 1e-5);
  // (1.5, 0.5): repeat tiles to (0.5, 0.5); clamp takes column 3, (.3 + .7) / 2.
  EXPECT_NEAR(centre_red({-3, 0, -1}, kRepeat), 0.35f, 1e-5);
  EXPECT_NEAR(centre_red({-3, 0, -1}, kClamp), 0.5f, 1e-5);
  // Nothing is outside a tiled plane: --outside does not apply.
  EXPECT_NEAR(centre_red({-3, 0, -1}, kRepeat, Rgba{1, 0, 0, 1}), 0.35f, 1e-5);
  EXPECT_NEAR(centre_red({-3, 0, -1}, kClamp, Rgba{1, 0, 0, 1}), 1.f, 1e-5);
  // (0, 0.25): x = -0.5, y = 1. Repeat: columns 3 and 0, (.7 + .4) / 2;
  // clamp: column 0, .4.
  EXPECT_NEAR(centre_red({0, 0, -0.5}, kRepeat), 0.55f, 1e-5);
  EXPECT_NEAR(centre_red({0, 0, -0.5}, kClamp), 0.4f, 1e-5);
  // (0.25, 1): x = 0.5, y = -0.5. Repeat: rows 1 and 0, (.4 + .5 + 0 + .1) / 4;
  // clamp: row 0, (0 + .1) / 2.
  EXPECT_NEAR(centre_red({-0.5, 0, -2}, kRepeat), 0.25f, 1e-5);
  EXPECT_NEAR(centre_red({-0.5, 0, -2}, kClamp), 0.05f, 1e-5);

  // The whole view: moving the origin by one tile (u_axis) changes nothing
  // when the plane repeats, and does when it clamps.
  const RenderImage base = render({-1, 0, -1}, kRepeat);
  const RenderImage shifted = render({-3, 0, -1}, kRepeat);
  const RenderImage clamped = render({-3, 0, -1}, kClamp);
  ASSERT_EQ(base.pixels.size(), shifted.pixels.size());
  double max_diff = 0, clamp_diff = 0;
  for (std::size_t i = 0; i < base.pixels.size(); ++i) {
    max_diff = std::max(max_diff, std::abs(double{base.pixels[i]} - shifted.pixels[i]));
    clamp_diff = std::max(clamp_diff, std::abs(double{base.pixels[i]} - clamped.pixels[i]));
  }
  EXPECT_LT(max_diff, 1e-5);
  EXPECT_GT(clamp_diff, 0.1);
}

TEST(RenderPreview, PlaneWrapIsIgnoredByTheOtherProxies) {
  // 2 x 2: top row black, white; bottom row red, green. Tiling v would blend
  // the rows near the poles (v < 0.25, v > 0.75), which the view sees.
  const std::vector<float> texels = {0, 0, 0, 1, 1, 1, 1, 1, 1, 0, 0, 1, 0, 1, 0, 1};
  MeshData m;
  add_sphere(m, {0, 0, 0}, 1, 8, 16);
  const EmbreeScene scene = build_scene(m);
  RenderOptions o;
  o.width = o.height = 32;
  auto sphere = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, {}});
  ASSERT_TRUE(sphere.has_value());
  ProjectionSource src{*sphere, {2, 2, texels.data()}, std::nullopt};
  auto clamp = render_preview(m, scene, src, o);
  src.plane_wrap = WrapMode::kRepeat;
  auto repeat = render_preview(m, scene, src, o);
  ASSERT_TRUE(clamp.has_value() && repeat.has_value());
  EXPECT_TRUE(clamp->pixels == repeat->pixels);  // bit for bit
}

TEST_F(PlaneProjection, LinearInterpolatesInLinearLight) {
  // 2 x 1: red 0 and 1, green .5 in both. At (u, v) = (0.5, 0.5) (x = 0.5),
  // halfway: stored-value red .5; in linear light (0 + 1) / 2 = .5, encoded
  // back to sRGB 1.055 * 0.5^(1/2.4) - 0.055 = 0.7353570. Green stays .5.
  const std::vector<float> texels = {0, 0.5f, 0, 1, 1, 0.5f, 0, 1};
  auto plane = make_proxy(PlaneParams{{-1, 0, -1}, {2, 0, 0}, {0, 0, 2}});
  ASSERT_TRUE(plane.has_value());
  ProjectionSource src{*plane, {2, 1, texels.data()}, std::nullopt};
  auto stored = render_preview(quad_, scene_, src, options_);
  src.linear = true;
  auto linear = render_preview(quad_, scene_, src, options_);
  ASSERT_TRUE(stored.has_value() && linear.has_value());
  EXPECT_NEAR(stored->pixel(32, 32)[0], 0.5f, 1e-5);
  EXPECT_NEAR(linear->pixel(32, 32)[0], 0.7353570f, 1e-5);
  EXPECT_NEAR(linear->pixel(32, 32)[1], 0.5f, 1e-5);
}

// A sphere (centre (0, 0, h), radius R) above the floor z = 0, seen straight
// down, lit by the key light. The expected shadow is analytic: a floor point
// P is shadowed iff the ray P + t L (t > 0) passes within R of the centre.
TEST(RenderPreview, SphereCastsItsShadowOnTheExpectedFloorPixels) {
  const double h = 0.8, R = 0.5, half = 2;
  const Vec3 C{0, 0, h};
  MeshData m = floor_square(half);
  add_sphere(m, C, R, 64, 128);
  const EmbreeScene scene = build_scene(m);
  RenderOptions o;
  o.width = o.height = 128;
  o.elevation_deg = 90;
  o.shadows = true;
  o.smooth_normals = true;
  o.phong = test_phong();
  auto img = render_preview(m, scene, GreySource{}, o);
  ASSERT_TRUE(img.has_value()) << img.error().message;
  o.shadows = false;
  auto unshadowed = render_preview(m, scene, GreySource{}, o);
  ASSERT_TRUE(unshadowed.has_value());

  // Camera straight down: right = +X, up = +Y, back = +Z, so the key light
  // (-1, 1, 2) in the camera frame is (-1, 1, 2)/sqrt(6) in the world.
  const Vec3 L = normalize(Vec3{-1, 1, 2});
  auto bounds = bounding_sphere(m);
  o.shadows = true;
  auto cam = make_camera(*bounds, o, 0);
  ASSERT_TRUE(cam.has_value());
  // Floor values: lit = 0.7 (0.2 + 0.7 L.z + 0.3 fill.z) + specular,
  // shadowed = 0.7 (0.2 + 0.3 fill.z); classify against the midpoint.
  const double fill_z = 1 / std::sqrt(2.0);
  const double lit = kGreyAlbedo * (0.2 + 0.7 * L.z + 0.3 * fill_z);
  const double dark = kGreyAlbedo * (0.2 + 0.3 * fill_z);
  const double mid = 0.5 * (lit + dark);

  const double pixel_size = 2 * (cam->position.z) * std::tan(15 * kPi / 180) / o.width;
  const double band = 1.5 * pixel_size;  // boundary pixels are not judged
  int shadowed = 0, lit_count = 0;
  for (int y = 0; y < o.height; ++y) {
    for (int x = 0; x < o.width; ++x) {
      const Ray r = cam->ray(x + 0.5, y + 0.5);
      // Skip rays that hit, or graze, the sphere.
      const Vec3 oc = C - r.origin;
      const double miss = length(cross(oc, r.direction)) - R;
      if (miss < band) continue;
      const double t = -r.origin.z / r.direction.z;
      const Vec3 p = r.origin + r.direction * t;
      if (std::abs(p.x) > half - band || std::abs(p.y) > half - band) continue;
      const Vec3 pc = C - p;
      const double along = dot(pc, L);
      const double dist = along > 0 ? length(cross(pc, L)) : length(pc);
      const double margin = dist - R;
      if (std::abs(margin) < band) continue;
      const bool expect_shadow = margin < 0;
      const double value = img->pixel(x, y)[0];
      EXPECT_EQ(value < mid, expect_shadow) << "pixel " << x << "," << y << " value " << value;
      EXPECT_GT(unshadowed->pixel(x, y)[0], mid) << "pixel " << x << "," << y;
      if (expect_shadow) {
        ++shadowed;
        EXPECT_NEAR(value, dark, 1e-5);
      } else {
        ++lit_count;
      }
    }
  }
  // The visible part of the shadow is a crescent of roughly 0.3 x 1 units,
  // about 6 x 20 pixels at this scale: the test must judge many of them.
  EXPECT_GT(shadowed, 60);
  EXPECT_GT(lit_count, 4000);
}

TEST(RenderPreview, ImageDoesNotDependOnThreadCount) {
  MeshData m = floor_square(2);
  add_sphere(m, {0, 0, 0.8}, 0.5, 24, 48);
  m.vertex_colors.resize(m.vertex_count());
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    const Float3 p = m.positions[v];
    m.vertex_colors[v] = {0.5f + 0.25f * p.x, 0.5f + 0.25f * p.y, p.z, 1.0f};
  }
  const EmbreeScene scene = build_scene(m);
  RenderOptions o;
  o.width = 80;
  o.height = 60;
  o.samples_per_pixel = 5;
  o.shadows = true;
  o.views = 3;
  auto render_with = [&](int threads) {
    ThreadLimit limit(threads);
    auto img = render_preview(m, scene, VertexColorSource{}, o);
    EXPECT_TRUE(img.has_value());
    return std::move(img).value();
  };
  const RenderImage one = render_with(1);
  const RenderImage two = render_with(2);
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_TRUE(one.pixels == two.pixels);  // bit for bit
  // Supersampling antialiases: some pixels are partly covered.
  int partial = 0;
  for (std::size_t i = 3; i < one.pixels.size(); i += 4) {
    partial += one.pixels[i] > 0 && one.pixels[i] < 1;
  }
  EXPECT_GT(partial, 10);
}

TEST(RenderPreview, ContactSheetCellsAreTheSingleViews) {
  MeshData m;
  add_sphere(m, {0, 0, 0}, 1, 8, 16);
  m.vertex_colors.resize(m.vertex_count());
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    m.vertex_colors[v] = {m.positions[v].x * 0.5f + 0.5f, 0.3f, 0.6f, 1.0f};
  }
  const EmbreeScene scene = build_scene(m);
  RenderOptions o;
  o.width = 24;
  o.height = 20;
  o.views = 3;  // 2 x 2 grid, last cell empty
  o.azimuth_deg = 10;
  auto sheet = render_preview(m, scene, VertexColorSource{}, o);
  ASSERT_TRUE(sheet.has_value());
  EXPECT_EQ(sheet->width, 48);
  EXPECT_EQ(sheet->height, 40);
  o.views = 1;
  o.azimuth_deg = 10 + 240;  // view 2: cell (0, 1)
  auto single = render_preview(m, scene, VertexColorSource{}, o);
  ASSERT_TRUE(single.has_value());
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 24; ++x) {
      for (int k = 0; k < 4; ++k) {
        ASSERT_EQ(sheet->pixel(x, 20 + y)[k], single->pixel(x, y)[k]) << x << "," << y;
      }
    }
  }
  for (int k = 0; k < 3; ++k) EXPECT_EQ(sheet->pixel(30, 30)[k], o.background[k]);  // empty cell
  EXPECT_EQ(sheet->pixel(30, 30)[3], 0.0f);
}

}  // namespace
}  // namespace texbake
