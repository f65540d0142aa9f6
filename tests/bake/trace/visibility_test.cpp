// Visibility (SPEC section 3): shadows of a box on a plane, no
// self-occlusion of convex surfaces at any scale or position, and the offset.
#include "bake/trace/visibility.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bake/util/parallel.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

// A 20 x 20 cell grid on z = 0 over [0,1]^2 (spacing 0.05) and a box floating
// over [0.32, 0.58] x [0.22, 0.48] x [0.3, 0.5]: with the projector straight
// up, exactly the grid vertices strictly inside that footprint are shadowed:
// x in {0.35, ..., 0.55} (5 values), y in {0.25, ..., 0.45} (5 values).
struct ShadowScene {
  MeshData mesh;
  uint32_t grid_first = 0, box_first = 0;
  static constexpr int kCells = 20;
  ShadowScene() {
    grid_first = test::append_grid(mesh, kCells, kCells, [](double s, double t) {
      return Float3{static_cast<float>(s), static_cast<float>(t), 0};
    });
    box_first = test::append_box(mesh, {0.32f, 0.22f, 0.3f}, {0.58f, 0.48f, 0.5f});
    test::faces_from_triangles(mesh);
  }
  static bool in_shadow(double x, double y) { return x > 0.32 && x < 0.58 && y > 0.22 && y < 0.48; }
};

TEST(Visibility, ExactlyTheVerticesInTheBoxShadowAreOccluded) {
  ShadowScene s;
  Expected<EmbreeScene> scene = EmbreeScene::build(s.mesh, BuildQuality::kLow);
  ASSERT_TRUE(scene);
  std::vector<Vec3> points, dirs;
  for (const Float3& p : s.mesh.positions) {
    points.push_back({p.x, p.y, p.z});
    dirs.push_back({0, 0, 1});
  }
  const std::vector<uint8_t> visible = compute_visibility(*scene, points, dirs);
  int shadowed = 0;
  for (int j = 0; j <= ShadowScene::kCells; ++j) {
    for (int i = 0; i <= ShadowScene::kCells; ++i) {
      const uint32_t v = s.grid_first + j * (ShadowScene::kCells + 1) + i;
      const bool expect_shadow = ShadowScene::in_shadow(i * 0.05, j * 0.05);
      shadowed += expect_shadow;
      EXPECT_EQ(visible[v], expect_shadow ? 0 : 1) << "grid vertex " << i << "," << j;
    }
  }
  EXPECT_EQ(shadowed, 25);
  // The box's top face sees the projector; its bottom face's interior is
  // under the top (corners graze the side faces and are not asserted).
  for (int k = 4; k < 8; ++k) EXPECT_EQ(visible[s.box_first + k], 1) << "top corner " << k;
}

TEST(Visibility, ResultsDoNotDependOnTheThreadCount) {
  ShadowScene s;
  Expected<EmbreeScene> scene = EmbreeScene::build(s.mesh, BuildQuality::kLow);
  ASSERT_TRUE(scene);
  // Slanted rays, many of them, so chunks are split differently.
  std::vector<Vec3> points, dirs;
  for (int k = 0; k < 20000; ++k) {
    points.push_back({(k % 173) / 172.0, (k / 173) / 115.0, 0});
    dirs.push_back(normalize(Vec3{0.3 * std::sin(k * 0.01), 0.2, 1}));
  }
  std::vector<uint8_t> one, two;
  {
    ThreadLimit limit(1);
    one = compute_visibility(*scene, points, dirs);
  }
  {
    ThreadLimit limit(2);
    two = compute_visibility(*scene, points, dirs);
  }
  EXPECT_EQ(one, two);
  EXPECT_GT(std::count(one.begin(), one.end(), 0), 0);  // the box shadows some
}

// Rays from every vertex of a closed sphere along its outward normal leave the
// sphere (no self-hit), along the inward normal they hit the far side.
void expect_no_self_occlusion(Float3 center, double radius) {
  MeshData mesh = test::uv_sphere(center, radius, 23, 47);
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kLow);
  ASSERT_TRUE(scene);
  std::vector<Vec3> points, out, in;
  for (const Float3& p : mesh.positions) {
    const Vec3 q{p.x, p.y, p.z};
    points.push_back(q);
    out.push_back(normalize(q - Vec3{center.x, center.y, center.z}));
    in.push_back(-out.back());
  }
  const std::vector<uint8_t> outward = compute_visibility(*scene, points, out);
  const std::vector<uint8_t> inward = compute_visibility(*scene, points, in);
  for (std::size_t v = 0; v < points.size(); ++v) {
    EXPECT_EQ(outward[v], 1) << "vertex " << v << " radius " << radius;
    EXPECT_EQ(inward[v], 0) << "vertex " << v << " radius " << radius;
  }
}

TEST(Visibility, ConvexSurfaceDoesNotShadowItselfAtAnyScaleOrPosition) {
  expect_no_self_occlusion({0, 0, 0}, 1.0);
  expect_no_self_occlusion({0, 0, 0}, 1e-3);
  expect_no_self_occlusion({1e3f, -2e3f, 5e2f}, 1.0);  // far from the origin
  expect_no_self_occlusion({0, 0, 0}, 1e4);
}

TEST(Visibility, OffsetIsRelativeToTheDiagonalWithAFloatPrecisionFloor) {
  MeshData near;
  near.positions = {{0, 0, 0}, {3, 0, 0}, {0, 4, 0}};
  near.triangles = {{0, 1, 2}};
  Expected<EmbreeScene> a = EmbreeScene::build(near, BuildQuality::kLow);
  ASSERT_TRUE(a);
  EXPECT_DOUBLE_EQ(visibility_offset(*a), kVisibilityOffsetRelative * 5.0);  // diagonal 5

  MeshData far = near;  // same triangle, 1e4 away: float spacing there dominates
  for (Float3& p : far.positions) p.x += 1e4f;
  Expected<EmbreeScene> b = EmbreeScene::build(far, BuildQuality::kLow);
  ASSERT_TRUE(b);
  const double expected = kVisibilityOffsetUlps * (1e4 + 3) * std::numeric_limits<float>::epsilon();
  EXPECT_NEAR(visibility_offset(*b), expected, 1e-12);
  EXPECT_GT(visibility_offset(*b), kVisibilityOffsetRelative * 5.0);
}

TEST(Visibility, BatchCanBeReusedAfterClear) {
  ShadowScene s;
  Expected<EmbreeScene> scene = EmbreeScene::build(s.mesh, BuildQuality::kLow);
  ASSERT_TRUE(scene);
  const double offset = visibility_offset(*scene);
  VisibilityBatch batch;
  batch.add({0.45, 0.35, 0}, {0, 0, 1});  // under the box
  batch.add({0.9, 0.9, 0}, {0, 0, 1});    // in the open
  uint8_t visible[2] = {7, 7};
  batch.trace(*scene, offset, visible);
  EXPECT_EQ(visible[0], 0);
  EXPECT_EQ(visible[1], 1);
  batch.clear();
  EXPECT_EQ(batch.size(), 0u);
  batch.add({0.45, 0.35, 0}, {0, 0, -1});  // looking down: nothing below
  batch.trace(*scene, offset, visible);
  EXPECT_EQ(visible[0], 1);
}

}  // namespace
}  // namespace texbake
