// Welding by position (mesh_io/weld.h) and the smooth normals that use it
// (issue #28 item 14): copies of a vertex at one point map to its first
// copy (-0 and +0 one point); a mesh without shared positions gets an empty
// table; a flat-shaded mesh (every triangle its own vertices) gets at each
// copy the smooth normal of the welded mesh.
#include "mesh_io/weld.h"

#include <gtest/gtest.h>

#include "mesh_io/vertex_normals.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

TEST(Weld, CopiesMapToTheirFirstVertex) {
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {-0.f, 0, -0.f}, {1, 0, 0}, {1, 0, 1e-7f}, {1, 0, 0}};
  EXPECT_EQ(weld_by_position(mesh), (std::vector<uint32_t>{0, 1, 0, 1, 4, 1}));
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_TRUE(weld_by_position(mesh).empty());
  mesh.positions.clear();
  EXPECT_TRUE(weld_by_position(mesh).empty());
}

TEST(Weld, FlatSplitMeshHasTheWeldedSmoothNormals) {
  MeshData welded = test::uv_sphere({0, 0, 0}, 1, 6, 12);
  ASSERT_TRUE(weld_by_position(welded).empty());
  MeshData split;
  std::vector<uint32_t> source;
  for (const auto& tri : welded.triangles) {
    const auto first = static_cast<uint32_t>(split.positions.size());
    for (uint32_t v : tri) split.positions.push_back(welded.positions[v]), source.push_back(v);
    split.triangles.push_back({first, first + 1, first + 2});
  }
  const std::vector<Float3> expected = smooth_vertex_normals(welded);
  const std::vector<Float3> normals = smooth_vertex_normals(split);
  ASSERT_EQ(normals.size(), source.size());
  for (std::size_t c = 0; c < source.size(); ++c) {
    // The same sums in another order: equal to float rounding.
    EXPECT_NEAR(normals[c].x, expected[source[c]].x, 1e-6) << c;
    EXPECT_NEAR(normals[c].y, expected[source[c]].y, 1e-6) << c;
    EXPECT_NEAR(normals[c].z, expected[source[c]].z, 1e-6) << c;
  }
}

}  // namespace
}  // namespace texbake
