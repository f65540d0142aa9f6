// complete_proxy of texbake/texbake.h: fields not given are fitted (the
// rules are complete_spec's, tested in tests/bake/fit); here what the API
// adds: the fitted keys and point count, Stats, error categories, naming.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/bake/test_meshes.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

TEST(ApiProxy, NothingGivenFitsEveryFieldOfTheSphere) {
  // A closed UV sphere of radius 0.5 around (1, 2, 3): its vertices lie on
  // that sphere, so the minimum enclosing sphere is that sphere.
  const MeshData m = test::uv_sphere({1, 2, 3}, 0.5, 6, 8);
  Expected<CompletedProxy> done = complete_proxy(ProxySpec{ProxyKind::kSphere, {}, {}}, m);
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_EQ(done->fitted, (std::vector<std::string>{"center", "radius", "pole", "equator"}));
  EXPECT_EQ(done->points, m.vertex_count());  // every vertex is referenced
  const SphereParams p = std::get<SphereParams>(params_of(done->proxy));
  EXPECT_NEAR(p.center.x, 1, 1e-6);
  EXPECT_NEAR(p.center.y, 2, 1e-6);
  EXPECT_NEAR(p.center.z, 3, 1e-6);
  EXPECT_NEAR(p.radius, 0.5, 1e-6);
  EXPECT_GT(done->stats.timings.fit, 0);
  EXPECT_EQ(done->stats.counts.vertices, m.vertex_count());
}

TEST(ApiProxy, ACompleteSpecIsValidatedWithoutTheMesh) {
  ProxySpec spec{ProxyKind::kSphere, {{"center", Vec3{0, 0, 1}}, {"radius", 2.0}}, {}};
  Expected<CompletedProxy> done = complete_proxy(spec, MeshData{});
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_TRUE(done->fitted.empty());
  EXPECT_EQ(done->points, 0u);
  EXPECT_EQ(done->stats.timings.fit, 0);
  EXPECT_EQ(std::get<SphereParams>(params_of(done->proxy)).radius, 2.0);

  spec.values["radius"] = -1.0;
  Expected<CompletedProxy> bad = complete_proxy(spec, MeshData{});
  ASSERT_FALSE(bad);
  EXPECT_EQ(category(bad.error()), ErrorCategory::kUsage);
  EXPECT_NE(bad.error().message.find("radius"), std::string::npos) << bad.error().message;
}

TEST(ApiProxy, ABadValueToFitAroundIsAUsageErrorNamedAsAsked) {
  const MeshData m = test::uv_sphere({0, 0, 0}, 1, 4, 6);
  const ProxySpec spec{ProxyKind::kCylinder, {{"axis", Vec3{0, 0, 0}}}, {}};
  Expected<CompletedProxy> by_key = complete_proxy(spec, m);
  ASSERT_FALSE(by_key);
  EXPECT_EQ(category(by_key.error()), ErrorCategory::kUsage);
  EXPECT_EQ(by_key.error().message.find("--axis"), std::string::npos) << by_key.error().message;
  Expected<CompletedProxy> by_flag = complete_proxy(spec, m, {}, ParamNaming::kFlag);
  ASSERT_FALSE(by_flag);
  EXPECT_NE(by_flag.error().message.find("--axis"), std::string::npos) << by_flag.error().message;
}

TEST(ApiProxy, AMeshThatCannotBeFittedIsAnInputError) {
  MeshData m;  // three coincident points: no sphere to fit
  m.positions = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  m.face_vertices = {0, 1, 2};
  m.face_offsets = {0, 3};
  Expected<CompletedProxy> done = complete_proxy(ProxySpec{ProxyKind::kSphere, {}, {}}, m);
  ASSERT_FALSE(done);
  EXPECT_EQ(category(done.error()), ErrorCategory::kInput);
}

}  // namespace
}  // namespace texbake
