// Errors of texbake/texbake.h: categories, meshes with nothing to bake,
// usage errors before input errors, the work's errors as input errors.
#include <gtest/gtest.h>

#include <string>

#include "tests/bake/test_meshes.h"
#include "tests/bake/texbake/api_test_util.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

// Five points, four of them on the x axis, and faces with no area by hand:
// a quad of four collinear points (2 triangles), a 2-gon (1), a triangle
// repeating one vertex (1) and a face without corners (1): 5 in all.
MeshData all_degenerate() {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {0, 1, 0}};
  m.face_vertices = {0, 1, 2, 3, 0, 4, 4, 4, 4};
  m.face_offsets = {0, 4, 6, 9, 9};
  triangulate_faces(m);
  return m;
}

TEST(ApiErrors, CategoryOfEveryCode) {
  EXPECT_EQ(category(make_error(ErrorCode::kInvalidArgument, "")), ErrorCategory::kUsage);
  EXPECT_EQ(category(make_error(ErrorCode::kUnsupported, "")), ErrorCategory::kUsage);
  EXPECT_EQ(category(make_error(ErrorCode::kParse, "")), ErrorCategory::kInput);
  EXPECT_EQ(category(make_error(ErrorCode::kIo, "")), ErrorCategory::kInput);
  EXPECT_EQ(category(make_error(ErrorCode::kInternal, "")), ErrorCategory::kInternal);
  EXPECT_EQ(category(make_error(ErrorCode::kCancelled, "")), ErrorCategory::kCancelled);
}

TEST(ApiErrors, VersionIsTheProjectVersion) {
  EXPECT_STREQ(version(), "0.1.0");
}

TEST(ApiErrors, AllDegenerateMeshCountsEveryTriangleOfItsFaces) {
  const MeshData m = all_degenerate();
  ASSERT_TRUE(m.triangles.empty());
  Status s = check_triangles(m);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kParse);
  EXPECT_EQ(s.error().message, "all 5 triangles are degenerate");

  MeshData none;
  none.positions = {{0, 0, 0}};
  none.face_offsets = {0};
  s = check_triangles(none);
  ASSERT_FALSE(s);
  EXPECT_EQ(category(s.error()), ErrorCategory::kInput);
  EXPECT_EQ(s.error().message, "the mesh has no faces");

  EXPECT_TRUE(check_triangles(test::uv_sphere({0, 0, 0}, 1, 4, 6)));
}

TEST(ApiErrors, BakesAndRenderRefuseAMeshWithNothingToBake) {
  const MeshData m = all_degenerate();
  const Image img = test::constant_image(2, 2, {1, 0, 0, 1});
  const Proxy sphere = test::unit_sphere_proxy();
  const std::string says = "all 5 triangles are degenerate";

  Expected<VertexColors> v = bake_vertex_colors(m, img.view(), sphere);
  ASSERT_FALSE(v);
  EXPECT_EQ(category(v.error()), ErrorCategory::kInput);
  EXPECT_EQ(v.error().message, says);

  for (UvLayout uv : {UvLayout::kAuto, UvLayout::kGenerate, UvLayout::kProxy}) {
    AtlasOptions ao;
    ao.uv = uv;
    ao.bake.size = 16;
    Expected<Atlas> a = bake_atlas_texture(m, img.view(), sphere, ao);
    ASSERT_FALSE(a) << to_string(uv);
    EXPECT_EQ(category(a.error()), ErrorCategory::kInput) << to_string(uv);
    EXPECT_EQ(a.error().message, says) << to_string(uv);
  }

  Expected<Rendered> r = render_mesh(m, GreySource{});
  ASSERT_FALSE(r);
  EXPECT_EQ(category(r.error()), ErrorCategory::kInput);
  EXPECT_EQ(r.error().message, says);
}

TEST(ApiErrors, UsageErrorsComeBeforeTheMeshsProblem) {
  const MeshData m = all_degenerate();
  const Image img = test::constant_image(2, 2, {1, 0, 0, 1});
  AtlasOptions ao;
  ao.bake.size = 0;
  Expected<Atlas> a = bake_atlas_texture(m, img.view(), test::unit_sphere_proxy(), ao);
  ASSERT_FALSE(a);
  EXPECT_EQ(category(a.error()), ErrorCategory::kUsage);
  EXPECT_EQ(a.error().message, "--size 0 is out of range (1 .. 16384)");

  VertexBakeOptions vo;
  vo.samples = 0;
  Expected<VertexColors> v = bake_vertex_colors(m, img.view(), test::unit_sphere_proxy(), vo);
  ASSERT_FALSE(v);
  EXPECT_EQ(category(v.error()), ErrorCategory::kUsage);
  EXPECT_EQ(v.error().message, "--samples 0 is out of range (1 .. 65536)");
}

TEST(ApiErrors, LayersOptionsRefuseTheSingleProjectionRuleAndASharedScene) {
  // The engine's ResultAlpha::kImage and shared scene are the proxy bake's
  // own: a layers job composites by coverage over a scene it builds.
  LayersBakeOptions lo;
  EXPECT_TRUE(validate_options(lo));
  lo.alpha = ResultAlpha::kImage;
  Status s = validate_options(lo);
  ASSERT_FALSE(s);
  EXPECT_EQ(category(s.error()), ErrorCategory::kUsage);
  EXPECT_NE(s.error().message.find("coverage"), std::string::npos) << s.error().message;
}

TEST(ApiErrors, ValidateOptionsNamesTheFlag) {
  VertexBakeOptions vo;
  EXPECT_TRUE(validate_options(vo));
  vo.samples = kMaxVertexSamples + 1;
  EXPECT_FALSE(validate_options(vo));
  vo.filter = VertexFilter::kBilinear;  // samples are not used
  EXPECT_TRUE(validate_options(vo));
  vo.occluded = OccludedMode::kColor;
  vo.occluded_color = {0, 0, 1.5f, 1};
  Status s = validate_options(vo);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("--occluded"), std::string::npos) << s.error().message;

  AtlasOptions ao;
  EXPECT_TRUE(validate_options(ao));
  ao.bake.samples = 257;
  s = validate_options(ao);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().message, "--samples 257 is out of range for an atlas (1 .. 256)");
  ao.bake.samples = 4;
  ao.bake.padding = -3;  // neither a count nor one of the two constants
  s = validate_options(ao);
  ASSERT_FALSE(s);
  EXPECT_EQ(category(s.error()), ErrorCategory::kUsage);
  EXPECT_NE(s.error().message.find("--padding -3"), std::string::npos) << s.error().message;
  ao.bake.padding = kPaddingInfinite;
  EXPECT_TRUE(validate_options(ao));
  ao.bake.shading.outside = OutsideMode::kColor;
  ao.bake.shading.outside_color = {0, -0.5f, 0, 1};
  EXPECT_FALSE(validate_options(ao));
}

TEST(ApiErrors, AnImageWithoutPixelsIsAUsageError) {
  const MeshData m = test::uv_sphere({0, 0, 0}, 0.5, 4, 6);
  const ImageView empty{0, 0, nullptr};
  Expected<VertexColors> v = bake_vertex_colors(m, empty, test::unit_sphere_proxy());
  ASSERT_FALSE(v);
  EXPECT_EQ(category(v.error()), ErrorCategory::kUsage);
  Expected<Atlas> a = bake_atlas_texture(m, empty, test::unit_sphere_proxy());
  ASSERT_FALSE(a);
  EXPECT_EQ(category(a.error()), ErrorCategory::kUsage);
}

TEST(ApiErrors, MeshUvsOnAMeshWithoutUvsIsAUsageError) {
  const MeshData m = test::uv_sphere({0, 0, 0}, 0.5, 4, 6);
  const Image img = test::constant_image(2, 2, {1, 0, 0, 1});
  AtlasOptions ao;
  ao.uv = UvLayout::kMesh;
  ao.bake.size = 16;
  Expected<Atlas> a = bake_atlas_texture(m, img.view(), test::unit_sphere_proxy(), ao);
  ASSERT_FALSE(a);
  EXPECT_EQ(category(a.error()), ErrorCategory::kUsage);
  EXPECT_EQ(a.error().message.rfind("--uv mesh: ", 0), 0u) << a.error().message;
}

TEST(ApiErrors, AnAtlasTheLayoutCannotPackIsAnInputError) {
  // A box has six charts (faces 90 degrees apart, beyond the 70 degree
  // normal cone); 100 texels of gutter cannot fit between them in an 8 x 8
  // atlas. The packer says kUnsupported; after the options were accepted
  // that is the input's fault.
  MeshData box;
  test::append_box(box, {0, 0, 0}, {1, 1, 1});
  test::faces_from_triangles(box);
  const Image img = test::constant_image(2, 2, {1, 0, 0, 1});
  AtlasOptions ao;
  ao.uv = UvLayout::kGenerate;
  ao.bake.size = 8;
  ao.bake.padding = 100;
  Expected<Atlas> a = bake_atlas_texture(box, img.view(), test::unit_sphere_proxy(), ao);
  ASSERT_FALSE(a);
  EXPECT_EQ(a.error().code, ErrorCode::kParse) << a.error().message;
  EXPECT_EQ(category(a.error()), ErrorCategory::kInput);
}

}  // namespace
}  // namespace texbake
