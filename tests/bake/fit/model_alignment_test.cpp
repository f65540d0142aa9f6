// measure_model_alignment (bake/fit/model_alignment.h) on a unit sphere,
// whose bounding box [-1, 1]^3 has the diagonal D = 2 sqrt(3): the box is
// grown by 0.1 D = 0.346 and "near" is within 0.01 D = 0.0346 of the
// surface. Points are the sphere's own vertices (distance 0: they are
// corners of its triangles) or those pushed out to radius 1.2 (about 0.2
// from the surface, still in the grown box), so every figure is counted by
// hand.
#include "bake/fit/model_alignment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

std::vector<Vec3> vertices(const MeshData& mesh, double scale = 1, Vec3 shift = {}) {
  std::vector<Vec3> v;
  for (const Float3& p : mesh.positions) v.push_back(Vec3{p.x, p.y, p.z} * scale + shift);
  return v;
}

// The vertices, those whose index modulo 10 is below `off_tenths` pushed
// out to radius 1.2; `near` is set to the count left on the surface.
std::vector<Vec3> partly_off(const MeshData& mesh, int off_tenths, std::size_t& near) {
  std::vector<Vec3> v = vertices(mesh);
  near = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (static_cast<int>(i % 10) < off_tenths) {
      v[i] = v[i] * 1.2;
    } else {
      ++near;
    }
  }
  return v;
}

TEST(ModelAlignment, TheSpheresOwnVerticesAreAligned) {
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 1, 32, 64);
  const std::vector<Vec3> points = vertices(sphere);
  Expected<ModelAlignment> a = measure_model_alignment(sphere, points);
  ASSERT_TRUE(a) << a.error().message;
  EXPECT_EQ(a->points, points.size());
  EXPECT_EQ(a->measured, points.size());
  EXPECT_EQ(a->in_box, points.size());
  EXPECT_EQ(a->near, points.size());
  EXPECT_LT(a->median_distance, 1e-6);
  EXPECT_EQ(a->verdict, AlignmentVerdict::kAligned);
}

TEST(ModelAlignment, SharesNearTheSurfaceGiveTheVerdict) {
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 1, 32, 64);
  const double diagonal = 2 * std::sqrt(3.0);
  struct Case {
    int off_tenths;
    AlignmentVerdict verdict;
  };
  // 30 % off: share 0.7, aligned; 70 % off: 0.3, doubtful; all off: 0, misaligned.
  for (const Case& c : {Case{3, AlignmentVerdict::kAligned}, Case{7, AlignmentVerdict::kDoubtful},
                        Case{10, AlignmentVerdict::kMisaligned}}) {
    std::size_t near = 0;
    const std::vector<Vec3> points = partly_off(sphere, c.off_tenths, near);
    Expected<ModelAlignment> a = measure_model_alignment(sphere, points);
    ASSERT_TRUE(a) << a.error().message;
    EXPECT_EQ(a->in_box, points.size()) << c.off_tenths;
    EXPECT_EQ(a->near, near) << c.off_tenths;
    EXPECT_EQ(a->verdict, c.verdict) << c.off_tenths;
    if (c.off_tenths > 5) {
      // Most points 0.2 (up to the facets' sag, r (1 - cos(pi / 64)) = 0.0012) off.
      EXPECT_NEAR(a->median_distance * diagonal, 0.2, 0.0013) << c.off_tenths;
    }
  }
}

TEST(ModelAlignment, AModelInItsOwnFrameIsMisaligned) {
  // Scaled by 3 and moved 10 along x: no point is in the mesh's box.
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 1, 32, 64);
  const std::vector<Vec3> points = vertices(sphere, 3, {10, 0, 0});
  Expected<ModelAlignment> a = measure_model_alignment(sphere, points);
  ASSERT_TRUE(a) << a.error().message;
  EXPECT_EQ(a->in_box, 0u);
  EXPECT_EQ(a->near, 0u);
  EXPECT_EQ(a->verdict, AlignmentVerdict::kMisaligned);
  EXPECT_NE(alignment_figures(*a).find("0 of 1986 sparse points in the mesh's box"),
            std::string::npos)
      << alignment_figures(*a);
}

TEST(ModelAlignment, TooFewPointsAreNotMeasured) {
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 1, 32, 64);
  std::vector<Vec3> points = vertices(sphere);
  points.resize(kAlignmentMinPoints - 1);
  Expected<ModelAlignment> a = measure_model_alignment(sphere, points);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->verdict, AlignmentVerdict::kNotMeasured);
  EXPECT_EQ(a->points, kAlignmentMinPoints - 1);
  EXPECT_EQ(a->measured, 0u);
}

TEST(ModelAlignment, ThreadCountsGiveTheSameFigures) {
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 1, 32, 64);
  std::size_t near = 0;
  const std::vector<Vec3> points = partly_off(sphere, 6, near);
  Expected<ModelAlignment> one = measure_model_alignment(sphere, points, 1);
  Expected<ModelAlignment> two = measure_model_alignment(sphere, points, 2);
  ASSERT_TRUE(one && two);
  EXPECT_EQ(one->near, two->near);
  EXPECT_EQ(one->median_distance, two->median_distance);
}

TEST(ModelAlignment, AMeshWithoutAreaIsAnError) {
  MeshData flat;
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  std::vector<Vec3> points(30, Vec3{0, 0, 0});
  Expected<ModelAlignment> a = measure_model_alignment(flat, points);
  ASSERT_FALSE(a);
  EXPECT_EQ(a.error().code, ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace texbake
