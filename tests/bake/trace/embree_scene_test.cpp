// EmbreeScene: hits at known t and barycentrics (worked by hand), misses,
// ray segments, batches larger than the internal block, thread safety.
#include "bake/trace/embree_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "bake/util/parallel.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

// One triangle (0,0,0), (1,0,0), (0,1,0) plus an unreferenced far vertex.
MeshData unit_triangle() {
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {100, 100, 100}};
  mesh.triangles = {{0, 1, 2}};
  test::faces_from_triangles(mesh);
  return mesh;
}

// Owns SoA arrays for a RayBatch.
struct Rays {
  std::vector<float> ox, oy, oz, dx, dy, dz, tnear, tfar;
  void add(float x, float y, float z, float a, float b, float c, float tn = 0,
           float tf = std::numeric_limits<float>::infinity()) {
    ox.push_back(x), oy.push_back(y), oz.push_back(z);
    dx.push_back(a), dy.push_back(b), dz.push_back(c);
    tnear.push_back(tn), tfar.push_back(tf);
  }
  RayBatch batch() const {
    return RayBatch{ox.data(), oy.data(),    oz.data(),   dx.data(), dy.data(),
                    dz.data(), tnear.data(), tfar.data(), ox.size()};
  }
};

TEST(EmbreeScene, RayWithAllOnesMaskHitsKnownTriangleAtKnownTAndBarycentrics) {
  Expected<EmbreeScene> scene = EmbreeScene::build(unit_triangle(), BuildQuality::kLow);
  ASSERT_TRUE(scene) << scene.error().message;
  Rays rays;
  // Straight down onto (0.25, 0.5, 0) from height 2: t = 2, b1 = x, b2 = y.
  rays.add(0.25f, 0.5f, 2.0f, 0, 0, -1);
  // Direction of length 4: t is in units of the direction, 2 / 4 = 0.5.
  rays.add(0.25f, 0.5f, 2.0f, 0, 0, -4);
  Hit hits[2];
  scene->intersect(rays.batch(), hits);
  for (const Hit& hit : hits) {
    EXPECT_EQ(hit.triangle, 0u);
    EXPECT_NEAR(hit.b1, 0.25f, 1e-6);
    EXPECT_NEAR(hit.b2, 0.5f, 1e-6);
    // (v1 - v0) x (v2 - v0) = (1,0,0) x (0,1,0) = (0,0,1)
    EXPECT_FLOAT_EQ(hit.normal.x, 0);
    EXPECT_FLOAT_EQ(hit.normal.y, 0);
    EXPECT_FLOAT_EQ(hit.normal.z, 1);
  }
  EXPECT_NEAR(hits[0].t, 2.0f, 1e-6);
  EXPECT_NEAR(hits[1].t, 0.5f, 1e-6);
  uint8_t occluded[2] = {0, 0};
  scene->occluded(rays.batch(), occluded);
  EXPECT_EQ(occluded[0], 1);
  EXPECT_EQ(occluded[1], 1);
}

TEST(EmbreeScene, MissesAndRaySegmentsAreRespected) {
  Expected<EmbreeScene> scene = EmbreeScene::build(unit_triangle(), BuildQuality::kMedium);
  ASSERT_TRUE(scene) << scene.error().message;
  Rays rays;
  rays.add(0.8f, 0.8f, 1, 0, 0, -1);              // beside the hypotenuse: miss
  rays.add(0.2f, 0.2f, 1, 0, 0, 1);               // pointing away: miss
  rays.add(0.2f, 0.2f, 1, 0, 0, -1, 0, 0.9f);     // segment ends before the triangle
  rays.add(0.2f, 0.2f, 1, 0, 0, -1, 1.1f);        // segment starts behind it
  rays.add(0.2f, 0.2f, 1, 0, 0, -1, 0.9f, 1.1f);  // segment straddles it: hit
  std::vector<Hit> hits(rays.ox.size());
  scene->intersect(rays.batch(), hits.data());
  std::vector<uint8_t> occluded(rays.ox.size(), 7);
  scene->occluded(rays.batch(), occluded.data());
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(hits[i].triangle, kNoHit) << "ray " << i;
    EXPECT_EQ(occluded[i], 0) << "ray " << i;
  }
  EXPECT_EQ(hits[4].triangle, 0u);
  EXPECT_NEAR(hits[4].t, 1.0f, 1e-6);
  EXPECT_EQ(occluded[4], 1);
}

TEST(EmbreeScene, DefaultSegmentIsZeroToInfinity) {
  Expected<EmbreeScene> scene = EmbreeScene::build(unit_triangle(), BuildQuality::kLow);
  ASSERT_TRUE(scene);
  const float ox = 0.1f, oy = 0.1f, oz = 1e6f, dx = 0, dy = 0, dz = -1;
  RayBatch far_ray{&ox, &oy, &oz, &dx, &dy, &dz, nullptr, nullptr, 1};
  Hit hit;
  scene->intersect(far_ray, &hit);
  EXPECT_EQ(hit.triangle, 0u);
  EXPECT_NEAR(hit.t, 1e6f, 1.0f);
}

TEST(EmbreeScene, DiagonalCoversOnlyReferencedVertices) {
  Expected<EmbreeScene> scene = EmbreeScene::build(unit_triangle(), BuildQuality::kLow);
  ASSERT_TRUE(scene);
  EXPECT_DOUBLE_EQ(scene->diagonal(), std::sqrt(2.0));  // box [0,1]x[0,1]x[0,0]
  EXPECT_DOUBLE_EQ(scene->max_abs_coordinate(), 1.0);
}

TEST(EmbreeScene, PicksTheRightTriangleOfAGrid) {
  MeshData mesh;
  test::append_grid(mesh, 4, 4, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0};
  });
  test::faces_from_triangles(mesh);
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kMedium);
  ASSERT_TRUE(scene);
  // Cell (i=2, j=1) spans [0.5,0.75]x[0.25,0.5]; below its diagonal is triangle
  // 2 * (1 * 4 + 2) = 12 with vertices (2,1), (3,1), (3,2).
  Rays rays;
  rays.add(0.7f, 0.3f, 1, 0, 0, -1);
  rays.add(0.55f, 0.45f, 1, 0, 0, -1);  // above the diagonal: triangle 13
  Hit hits[2];
  scene->intersect(rays.batch(), hits);
  EXPECT_EQ(hits[0].triangle, 12u);
  EXPECT_EQ(hits[1].triangle, 13u);
  // Triangle 12: p = v0 + b1 (v1 - v0) + b2 (v2 - v0) with v0 = (0.5, 0.25),
  // v1 - v0 = (0.25, 0), v2 - v0 = (0.25, 0.25): b2 = 0.05 / 0.25, b1 = 0.2/0.25 - b2.
  EXPECT_NEAR(hits[0].b2, 0.2f, 1e-5);
  EXPECT_NEAR(hits[0].b1, 0.6f, 1e-5);
}

TEST(EmbreeScene, LargeBatchesMatchTheAnalyticAnswerAndAreThreadSafe) {
  Expected<EmbreeScene> scene = EmbreeScene::build(unit_triangle(), BuildQuality::kLow);
  ASSERT_TRUE(scene);
  // 101 x 101 rays straight down over [-0.25, 1.25]^2: more than one internal
  // block, hitting exactly where x >= 0, y >= 0, x + y <= 1 (points chosen off
  // the edges so rounding cannot decide).
  Rays rays;
  std::vector<uint8_t> expected;
  for (int j = 0; j <= 100; ++j) {
    for (int i = 0; i <= 100; ++i) {
      const double x = -0.2537 + 1.5 * i / 100, y = -0.2537 + 1.5 * j / 100;
      rays.add(static_cast<float>(x), static_cast<float>(y), 1, 0, 0, -1);
      expected.push_back(x > 0 && y > 0 && x + y < 1 ? 1 : 0);
    }
  }
  const RayBatch all = rays.batch();
  std::vector<uint8_t> occluded(all.count, 9);
  // In parallel, in chunks of 97 rays: every chunk calls occluded() at once.
  parallel_for_chunks(all.count, 97, [&](std::size_t begin, std::size_t end) {
    RayBatch part = all;
    part.org_x += begin, part.org_y += begin, part.org_z += begin;
    part.dir_x += begin, part.dir_y += begin, part.dir_z += begin;
    part.tnear += begin, part.tfar += begin;
    part.count = end - begin;
    scene->occluded(part, occluded.data() + begin);
  });
  EXPECT_EQ(occluded, expected);
  std::vector<Hit> hits(all.count);
  scene->intersect(all, hits.data());
  for (std::size_t i = 0; i < all.count; ++i) {
    EXPECT_EQ(hits[i].triangle != kNoHit, expected[i] == 1) << "ray " << i;
  }
}

// Robust mode (RTC_SCENE_FLAG_ROBUST): rays aimed exactly at shared edges of
// a tilted grid must not slip through the cracks between its triangles.
TEST(EmbreeScene, RaysThroughSharedEdgesHit) {
  MeshData mesh;
  test::append_grid(mesh, 24, 24, [](double s, double t) {
    return Float3{static_cast<float>(0.8 * s + 0.3 * t), static_cast<float>(-0.2 * s + 0.9 * t),
                  static_cast<float>(0.35 * s - 0.45 * t)};
  });
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kLow);
  ASSERT_TRUE(scene);
  Rays rays;
  const float eye[3] = {0.37f, 0.21f, 3.0f};
  auto aim = [&](Float3 target) {
    rays.add(eye[0], eye[1], eye[2], target.x - eye[0], target.y - eye[1], target.z - eye[2]);
  };
  // Midpoints of the interior edges (boundary edges belong to one triangle:
  // a ray through them may legitimately hit or miss).
  std::map<std::pair<uint32_t, uint32_t>, int> edge_count;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      ++edge_count[std::minmax(t[k], t[(k + 1) % 3])];
    }
  }
  for (const auto& [edge, count] : edge_count) {
    if (count != 2) continue;
    const Float3 a = mesh.positions[edge.first], b = mesh.positions[edge.second];
    aim({(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2});
  }
  std::vector<uint8_t> occluded(rays.ox.size(), 0);
  scene->occluded(rays.batch(), occluded.data());
  const auto misses = std::count(occluded.begin(), occluded.end(), 0);
  EXPECT_EQ(misses, 0) << "of " << occluded.size() << " rays";
}

TEST(EmbreeScene, EmptyMeshBuildsAndEveryRayIsFree) {
  MeshData mesh;
  mesh.positions = {{0, 0, 0}};
  mesh.face_offsets = {0};
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kLow);
  ASSERT_TRUE(scene) << scene.error().message;
  const float o = 0, d = 1;
  RayBatch ray{&o, &o, &o, &d, &o, &o, nullptr, nullptr, 1};
  uint8_t occluded = 5;
  scene->occluded(ray, &occluded);
  EXPECT_EQ(occluded, 0);
  EXPECT_EQ(scene->diagonal(), 0.0);
}

TEST(EmbreeScene, MovedSceneStillTraces) {
  Expected<EmbreeScene> built = EmbreeScene::build(unit_triangle(), BuildQuality::kLow);
  ASSERT_TRUE(built);
  EmbreeScene moved = std::move(built).value();
  EmbreeScene assigned = std::move(moved);
  const float ox = 0.2f, oy = 0.2f, oz = 1, dx = 0, dz = -1;
  RayBatch ray{&ox, &oy, &oz, &dx, &dx, &dz, nullptr, nullptr, 1};
  uint8_t occluded = 0;
  assigned.occluded(ray, &occluded);
  EXPECT_EQ(occluded, 1);
}

}  // namespace
}  // namespace texbake
