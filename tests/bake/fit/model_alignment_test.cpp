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
#include <numbers>
#include <vector>

#include "mesh_io/read_mesh.h"
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

// 2 * (rotation by 90 degrees about +z) + (1, 2, 3), row by row.
const std::vector<double> kTwiceQuarterTurn = {0, -2, 0, 1, 2, 0, 0, 2, 0, 0, 2, 3, 0, 0, 0, 1};

TEST(Similarity, FromAMatrixAndItsRefusals) {
  Expected<Similarity> s = similarity_from_matrix(kTwiceQuarterTurn, "--transform");
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_NEAR(s->scale, 2, 1e-15);
  // (1, 0, 0) turns to (0, 1, 0), doubles to (0, 2, 0), moves to (1, 4, 3).
  const Vec3 x = s->apply({1, 0, 0});
  EXPECT_NEAR(x.x, 1, 1e-14);
  EXPECT_NEAR(x.y, 4, 1e-14);
  EXPECT_NEAR(x.z, 3, 1e-14);
  std::vector<double> m = kTwiceQuarterTurn;
  m.pop_back();
  EXPECT_FALSE(similarity_from_matrix(m, "--transform"));  // 15 numbers
  m = kTwiceQuarterTurn;
  m[12] = 1;
  EXPECT_FALSE(similarity_from_matrix(m, "--transform"));  // a projection
  m = kTwiceQuarterTurn;
  m[10] = -2;
  Expected<Similarity> mirror = similarity_from_matrix(m, "--transform");
  ASSERT_FALSE(mirror);
  EXPECT_NE(mirror.error().message.find("no mirroring"), std::string::npos);
  m = kTwiceQuarterTurn;
  m[2] = 0.5;  // a shear
  Expected<Similarity> shear = similarity_from_matrix(m, "--transform");
  ASSERT_FALSE(shear);
  EXPECT_NE(shear.error().message.find("not a scale times a rotation"), std::string::npos);
}

TEST(Similarity, FromPointPairsRecoversTheSimilarity) {
  // The model's points are the corners of a unit tetrahedron and one more;
  // the mesh's are kTwiceQuarterTurn's images, worked out by hand:
  // (x, y, z) -> 2 (-y, x, z) + (1, 2, 3).
  const std::vector<Vec3> model = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  const std::vector<Vec3> mesh = {{1, 2, 3}, {1, 4, 3}, {-1, 2, 3}, {1, 2, 5}, {-1, 4, 5}};
  Expected<PairFit> fit = similarity_from_pairs(model, mesh);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_NEAR(fit->transform.scale, 2, 1e-12);
  const Similarity truth = similarity_from_matrix(kTwiceQuarterTurn, "m").value();
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(fit->transform.r[k], truth.r[k], 1e-12) << k;
  EXPECT_NEAR(fit->transform.t.x, 1, 1e-12);
  EXPECT_NEAR(fit->transform.t.y, 2, 1e-12);
  EXPECT_NEAR(fit->transform.t.z, 3, 1e-12);
  EXPECT_NEAR(fit->rms, 0, 1e-12);
  // One pair mistyped by 1 along z: the largest residual is that pair's.
  std::vector<Vec3> typo = mesh;
  typo[3].z += 1;
  Expected<PairFit> off = similarity_from_pairs(model, typo);
  ASSERT_TRUE(off);
  EXPECT_EQ(off->worst, 3u);
  EXPECT_GT(off->rms, 0.1);
  EXPECT_GE(off->largest, off->rms);
}

TEST(Similarity, PointPairsThatDetermineNoRotationAreRefused) {
  const std::vector<Vec3> two = {{0, 0, 0}, {1, 0, 0}};
  Expected<PairFit> few = similarity_from_pairs(two, two);
  ASSERT_FALSE(few);
  EXPECT_EQ(few.error().message, "2 point pairs: at least 3 are needed");
  const std::vector<Vec3> line = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {-3, -3, -3}};
  const std::vector<Vec3> spread = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Expected<PairFit> collinear = similarity_from_pairs(line, spread);
  ASSERT_FALSE(collinear);
  EXPECT_NE(collinear.error().message.find("the model's points lie on one line"),
            std::string::npos);
  const std::vector<Vec3> one_place(4, Vec3{1, 2, 3});
  Expected<PairFit> same = similarity_from_pairs(spread, one_place);
  ASSERT_FALSE(same);
  EXPECT_NE(same.error().message.find("the mesh's points lie on one line (or at one place)"),
            std::string::npos);
  EXPECT_FALSE(similarity_from_pairs(spread, line));  // the mesh's side on a line
  EXPECT_FALSE(similarity_from_pairs(spread, two));   // not as many
}

TEST(Similarity, AMovedCameraSeesTheMovedWorldAsBefore) {
  // A pinhole at (0, 0, -5) looking down +z; the point (0.3, -0.2, 1).
  Expected<CameraProjector> camera =
      CameraProjector::make({CameraModel::kPinhole,
                             640,
                             480,
                             {500, 500, 320, 240},
                             CameraPose{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 5}}});
  ASSERT_TRUE(camera);
  const Similarity s = similarity_from_matrix(kTwiceQuarterTurn, "m").value();
  Expected<CameraProjector> moved = transform_camera(*camera, s);
  ASSERT_TRUE(moved) << moved.error().message;
  // The centre moves with the world: s(0, 0, -5) = 2 (0, 0, -5) + (1, 2, 3) = (1, 2, -7).
  EXPECT_NEAR(moved->centre().x, 1, 1e-12);
  EXPECT_NEAR(moved->centre().y, 2, 1e-12);
  EXPECT_NEAR(moved->centre().z, -7, 1e-12);
  // Before: (0.3, -0.2, 1) at depth 6 lands on (320 + 500 * 0.05, 240 - 500 / 30).
  const Vec3 p{0.3, -0.2, 1};
  const CameraProjection a = camera->project(p), b = moved->project(s.apply(p));
  ASSERT_TRUE(a.inside && b.inside);
  EXPECT_NEAR(a.pixel.x, 345, 1e-9);
  EXPECT_NEAR(a.pixel.y, 240 - 500.0 / 30, 1e-9);
  EXPECT_NEAR(b.pixel.x, a.pixel.x, 1e-9);
  EXPECT_NEAR(b.pixel.y, a.pixel.y, 1e-9);
}

TEST(ModelFit, ABunnyModelMovedAwayIsBroughtBack) {
  Expected<LoadedMesh> bunny = read_mesh(std::string(TEXBAKE_DATA_DIR) + "/bunny00.off");
  ASSERT_TRUE(bunny) << bunny.error().message;
  const MeshData& mesh = bunny->mesh;
  // The model's frame: scale 0.4, a third of a turn about (1, 1, 1) (which
  // cycles the axes: x -> y -> z -> x), then (5, -2, 1).
  const Similarity away =
      similarity_from_matrix(
          std::vector<double>{0, 0, 0.4, 5, 0.4, 0, 0, -2, 0, 0.4, 0, 1, 0, 0, 0, 1}, "m")
          .value();
  std::vector<Vec3> points, truth;
  for (std::size_t i = 0; i < mesh.positions.size(); i += 3) {
    const Vec3 v{mesh.positions[i].x, mesh.positions[i].y, mesh.positions[i].z};
    truth.push_back(v);
    points.push_back(away.apply(v));
  }
  // 15 % of background points, scattered around the model (a fixed LCG).
  uint64_t state = 12345;
  auto uniform = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  const std::size_t background = points.size() * 15 / 100;
  for (std::size_t i = 0; i < background; ++i) {
    points.push_back(
        away.apply({uniform() * 0.6 - 0.3, uniform() * 0.6 - 0.3, uniform() * 0.6 - 0.3}));
  }
  Expected<ModelFit> fit = fit_model_to_mesh(mesh, points, 2);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_EQ(fit->before.verdict, AlignmentVerdict::kMisaligned);
  EXPECT_EQ(fit->after.verdict, AlignmentVerdict::kAligned) << alignment_figures(fit->after);
  EXPECT_EQ(fit->candidates, 24);
  // The fit is the inverse of `away`: the bunny's own points come back.
  double worst = 0, diagonal = 0;
  Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (const Vec3& v : truth) {
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
    hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  }
  diagonal = length(hi - lo);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    worst = std::max(worst, length(fit->transform.apply(points[i]) - truth[i]));
  }
  EXPECT_LT(worst, 2e-3 * diagonal) << "scale " << fit->transform.scale;
  EXPECT_NEAR(fit->transform.scale, 2.5, 2.5e-3);
}

}  // namespace
}  // namespace texbake
