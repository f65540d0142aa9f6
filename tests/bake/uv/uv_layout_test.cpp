// bake/uv/uv_layout.h: the choice of layout, its checks and warnings, and
// the gutter rule.
#include "bake/uv/uv_layout.h"

#include <gtest/gtest.h>

#include <string>

#include "mesh_io/read_mesh.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

Proxy unit_sphere() {
  return make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, std::nullopt}).value();
}

// One triangle with per-corner UVs; two of its corners lie outside [0, 1].
MeshData triangle_with_uvs() {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.face_vertices = {0, 1, 2};
  m.face_offsets = {0, 3};
  m.uvs = {{0.5f, 0.5f}, {1.5f, 0.5f}, {0.5f, -0.25f}};
  m.corner_uv = {0, 1, 2};
  triangulate_faces(m);
  return m;
}

TEST(UvLayout, Names) {
  EXPECT_STREQ(to_string(UvLayout::kAuto), "auto");
  EXPECT_STREQ(to_string(UvLayout::kMesh), "mesh");
  EXPECT_STREQ(to_string(UvLayout::kGenerate), "generate");
  EXPECT_STREQ(to_string(UvLayout::kProxy), "proxy");
}

TEST(UvLayout, AutoUsesTheMeshsUvsWhenItHasAnyElseGenerates) {
  UvLayoutOptions o;
  o.atlas_size = 64;
  Expected<UvLayoutResult> with = lay_out_uvs(triangle_with_uvs(), unit_sphere(), o);
  ASSERT_TRUE(with) << with.error().message;
  EXPECT_EQ(with->stats.used, UvLayout::kMesh);
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 0.5, 4, 8);
  Expected<UvLayoutResult> without = lay_out_uvs(sphere, unit_sphere(), o);
  ASSERT_TRUE(without) << without.error().message;
  EXPECT_EQ(without->stats.used, UvLayout::kGenerate);
  EXPECT_EQ(without->generated.triangle_uvs.size(), sphere.triangles.size());
}

TEST(UvLayout, MeshUvsAreCheckedWithAWarningPerProblem) {
  UvLayoutOptions o;
  o.uv = UvLayout::kMesh;
  o.atlas_size = 16;
  Expected<UvLayoutResult> r = lay_out_uvs(triangle_with_uvs(), unit_sphere(), o);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->stats.corners_outside, 2u);
  EXPECT_EQ(r->stats.overlap_texels, 0u);  // a single triangle cannot overlap
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_EQ(r->warnings[0], "2 UV corners lie outside [0, 1]; their texels are not baked");
  EXPECT_FALSE(r->repeat_u);
}

TEST(UvLayout, MeshUvsWithoutUvsIsAnInvalidArgument) {
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 0.5, 4, 8);
  EXPECT_TRUE(check_uv_layout(sphere, UvLayout::kGenerate));
  Status s = check_uv_layout(sphere, UvLayout::kMesh);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(s.error().message,
            "--uv mesh: the mesh has no UV coordinates (use --uv generate or --uv proxy)");
  UvLayoutOptions o;
  o.uv = UvLayout::kMesh;
  EXPECT_FALSE(lay_out_uvs(sphere, unit_sphere(), o));
}

TEST(UvLayout, GeneratedChartsKeepAtLeastTheMinimumGutter) {
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 0.5, 6, 12);
  UvLayoutOptions o;
  o.uv = UvLayout::kGenerate;
  o.atlas_size = 128;
  for (const auto& [padding, gutter] : {std::pair{0, 2}, {1, 2}, {2, 2}, {5, 5}}) {
    o.padding = padding;
    Expected<UvLayoutResult> r = lay_out_uvs(sphere, unit_sphere(), o);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->generated.padding, gutter) << "padding " << padding;
    EXPECT_EQ(r->stats.charts, r->generated.chart_count);
  }
}

TEST(UvLayout, ProxyLayoutRepeatsInUOnlyForPeriodicProxies) {
  const MeshData sphere = test::uv_sphere({0, 0, 0}, 0.5, 4, 8);
  UvLayoutOptions o;
  o.uv = UvLayout::kProxy;
  Expected<UvLayoutResult> around = lay_out_uvs(sphere, unit_sphere(), o);
  ASSERT_TRUE(around) << around.error().message;
  EXPECT_TRUE(around->repeat_u);
  EXPECT_TRUE(around->mesh.has_uvs());
  const Proxy plane = make_proxy(PlaneParams{{-1, -1, 0}, {2, 0, 0}, {0, 2, 0}}).value();
  Expected<UvLayoutResult> flat = lay_out_uvs(sphere, plane, o);
  ASSERT_TRUE(flat) << flat.error().message;
  EXPECT_FALSE(flat->repeat_u);
  EXPECT_EQ(flat->stats.cut_triangles, 0u);  // a plane has no seam
}

}  // namespace
}  // namespace texbake
