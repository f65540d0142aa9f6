// --uv proxy: the proxy's own (u, v), cut at the seam, poles fixed; and the
// --uv mesh checks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bake/uv/uv_proxy.h"
#include "tests/bake/atlas/atlas_test_util.h"
#include "tests/bake/uv/uv_sphere.h"

namespace texbake {
namespace {

Proxy unit_sphere_proxy() {
  SphereParams p;
  p.center = {0, 0, 0};
  p.radius = 1;
  p.pole = {0, 0, 1};
  p.equator = Vec3{1, 0, 0};
  return make_proxy(p).value();
}

double signed_uv_area(const MeshData& m, std::size_t t) {
  const Float2 a = m.uvs[m.corner_uv[m.triangle_corners[t][0]]];
  const Float2 b = m.uvs[m.corner_uv[m.triangle_corners[t][1]]];
  const Float2 c = m.uvs[m.corner_uv[m.triangle_corners[t][2]]];
  return 0.5 *
         ((double(b.u) - a.u) * (double(c.v) - a.v) - (double(b.v) - a.v) * (double(c.u) - a.u));
}

// UV sphere with R latitude bands and S segments whose vertices sit at
// azimuth (j + 0.5) / S, so the seam u = 0 passes through the middle of a
// column of triangles and every band has triangles to cut.
TEST(AtlasUvProxy, UvSphereIsCutAtTheSeamAndPolesAreFixed) {
  const int rings = 12, segments = 24;
  const MeshData mesh = test::make_uv_sphere(rings, segments, 0.5);
  auto layout = proxy_uv_layout(mesh, unit_sphere_proxy());
  ASSERT_TRUE(layout) << layout.error().message;
  const MeshData& m = layout->mesh;
  const ProxyUvStats& st = layout->stats;

  // Counted by hand: each of the R - 2 bands has 2 seam triangles, each fan 1;
  // the cut edges are the R - 1 ring edges and R - 2 band diagonals crossing
  // the seam; every pole corner (2 S of them) is singular.
  EXPECT_EQ(st.cut_triangles, std::size_t(2 * (rings - 2) + 2));
  EXPECT_EQ(st.added_vertices, std::size_t(2 * rings - 3));
  EXPECT_EQ(st.singular_corners, std::size_t(2 * segments));
  EXPECT_EQ(st.wide_triangles, 0u);
  EXPECT_FALSE(st.rescaled);
  // A band triangle is cut into 3 pieces, a fan triangle (pole corner on the
  // cut line) into 2.
  EXPECT_EQ(m.triangles.size(), mesh.triangles.size() + 4 * (rings - 2) + 2);
  EXPECT_EQ(m.vertex_count(), mesh.vertex_count() + st.added_vertices);

  // Added vertices: on ring edges (z of a ring) exactly on the seam
  // half-plane y = 0, x > 0; on band diagonals within half a segment of it
  // (the UV midpoint of a chord is not at the proxy's u = 0).
  for (std::size_t v = mesh.vertex_count(); v < m.vertex_count(); ++v) {
    const Float3 p = m.positions[v];
    EXPECT_GT(p.x, 0);
    EXPECT_LE(std::abs(std::atan2(p.y, p.x)), std::numbers::pi / segments);
    bool on_ring = false;
    for (int i = 1; i < rings; ++i)
      on_ring |= std::abs(p.z - std::cos(std::numbers::pi * i / rings)) < 1e-6;
    if (on_ring) {
      EXPECT_NEAR(p.y, 0, 1e-6);
    }
  }

  double area = 0;
  int positive = 0, negative = 0;
  const Proxy proxy = unit_sphere_proxy();
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    double umin = 2, umax = -1;
    Vec3 centroid;
    double cu = 0, cv = 0;
    for (int k = 0; k < 3; ++k) {
      const Float2 q = m.uvs[m.corner_uv[m.triangle_corners[t][k]]];
      EXPECT_GE(q.u, 0);
      EXPECT_LE(q.u, 1);
      EXPECT_GE(q.v, 0);
      EXPECT_LE(q.v, 1);
      umin = std::min<double>(umin, q.u);
      umax = std::max<double>(umax, q.u);
      cu += q.u / 3.0;
      cv += q.v / 3.0;
      const Float3 p = m.positions[m.triangles[t][k]];
      centroid += Vec3{p.x, p.y, p.z} / 3.0;
    }
    // No triangle spans more than half the u range; here at most one segment.
    EXPECT_LE(umax - umin, 1.0 / segments + 1e-6) << "triangle " << t;
    // The layout agrees with the proxy at the triangle's centroid: within a
    // segment in u (circularly) and a band in v.
    const MapResult r = inverse_map(proxy, centroid);
    double du = std::abs(r.uv.u - cu);
    du = std::min(du, 1 - du);
    EXPECT_LE(du, 1.0 / segments) << "triangle " << t;
    EXPECT_LE(std::abs(r.uv.v - cv), 1.0 / rings) << "triangle " << t;
    const double a = signed_uv_area(m, t);
    area += std::abs(a);
    (a > 0 ? positive : negative) += 1;
  }
  // No folds: one orientation throughout.
  EXPECT_TRUE(positive == 0 || negative == 0) << positive << " vs " << negative;
  // Hand-computed: every band fills its strip of [0,1]^2, the two pole fans
  // fill half of theirs (triangles with their apex at the pole row):
  // 1 - 1/R.
  EXPECT_NEAR(area, 1.0 - 1.0 / rings, 1e-5);

  // Faces are the triangles, written with v/vt: the OBJ writer's input.
  EXPECT_EQ(m.face_count(), m.triangles.size());
  EXPECT_EQ(m.corner_uv.size(), m.face_vertices.size());
}

// Vertices at azimuth j / S (one column on u = 0): no cut is needed, seam
// triangles are only shifted to end at u = 1.
TEST(AtlasUvProxy, SeamThroughVerticesNeedsNoCut) {
  const MeshData mesh = test::make_uv_sphere(8, 16, 0.0);
  auto layout = proxy_uv_layout(mesh, unit_sphere_proxy());
  ASSERT_TRUE(layout);
  EXPECT_EQ(layout->stats.cut_triangles, 0u);
  EXPECT_EQ(layout->stats.added_vertices, 0u);
  EXPECT_EQ(layout->mesh.triangles.size(), mesh.triangles.size());
  double area = 0;
  for (std::size_t t = 0; t < layout->mesh.triangles.size(); ++t)
    area += std::abs(signed_uv_area(layout->mesh, t));
  EXPECT_NEAR(area, 1.0 - 1.0 / 8, 1e-5);
}

// A tube z in [-0.5, 1.5] around a cylinder of height 1 at z = 0: v runs
// -0.5 .. 1.5, so the layout is rescaled: v' = (v + 0.5) / 2 = (z + 0.5) / 2.
TEST(AtlasUvProxy, LayoutBeyondTheDomainIsRescaled) {
  const int segments = 16;
  std::vector<Float3> pos;
  std::vector<Float2> uv;
  for (int j = 0; j < segments; ++j) {
    const double a0 = 2 * std::numbers::pi * (j + 0.5) / segments,
                 a1 = 2 * std::numbers::pi * (j + 1.5) / segments;
    const Float3 p00{float(std::cos(a0)), float(std::sin(a0)), -0.5f},
        p10{float(std::cos(a1)), float(std::sin(a1)), -0.5f},
        p01{float(std::cos(a0)), float(std::sin(a0)), 1.5f},
        p11{float(std::cos(a1)), float(std::sin(a1)), 1.5f};
    for (const Float3& p : {p00, p10, p11, p00, p11, p01}) pos.push_back(p), uv.push_back({});
  }
  const MeshData mesh = test::make_triangle_soup(pos, uv);
  CylinderParams c;
  c.base = {0, 0, 0};
  c.axis = {0, 0, 1};
  c.equator = Vec3{1, 0, 0};
  c.radius = 1;
  c.height = 1;
  auto layout = proxy_uv_layout(mesh, make_proxy(c).value());
  ASSERT_TRUE(layout);
  EXPECT_TRUE(layout->stats.rescaled);
  EXPECT_EQ(layout->stats.cut_triangles, 2u);
  const MeshData& m = layout->mesh;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Float2 q = m.uvs[m.corner_uv[m.triangle_corners[t][k]]];
      const float z = m.positions[m.triangles[t][k]].z;
      EXPECT_NEAR(q.v, (z + 0.5) / 2, 1e-6);
      EXPECT_GE(q.u, 0);
      EXPECT_LE(q.u, 1);
    }
  }
}

// Quad proxy over a flat grid: (u, v) = (x / 2, y), no cut, no rescale.
TEST(AtlasUvProxy, QuadProxyGivesPlanarCoordinates) {
  std::vector<Float2> xy = {{0, 0}, {2, 0},        {2, 1},        {0, 0},    {2, 1},
                            {0, 1}, {0.5f, 0.25f}, {1.5f, 0.25f}, {1, 0.75f}};
  std::vector<Float3> pos;
  for (const Float2& q : xy) pos.push_back({q.u, q.v, 0});
  const MeshData mesh = test::make_triangle_soup(pos, std::vector<Float2>(xy.size()));
  QuadParams q;
  q.corners = {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{2, 1, 0}, Vec3{0, 1, 0}};
  auto layout = proxy_uv_layout(mesh, make_proxy(q).value());
  ASSERT_TRUE(layout);
  EXPECT_EQ(layout->stats.cut_triangles, 0u);
  EXPECT_FALSE(layout->stats.rescaled);
  const MeshData& m = layout->mesh;
  ASSERT_EQ(m.triangles.size(), 3u);
  for (std::size_t t = 0; t < 3; ++t) {
    for (int k = 0; k < 3; ++k) {
      const Float2 uvq = m.uvs[m.corner_uv[m.triangle_corners[t][k]]];
      const Float3 p = m.positions[m.triangles[t][k]];
      EXPECT_NEAR(uvq.u, p.x / 2, 1e-6);
      EXPECT_NEAR(uvq.v, p.y, 1e-6);
    }
  }
}

// 8 x 8 raster. Triangle A = uv (0,0), (1,0), (0,1) holds the texel centres
// with x < y strictly (28 of them); B is A again (28 overlaps); C, the other
// half (x > y, 28), shares only the diagonal, whose centres are on the edge:
// no overlap. D lies outside [0, 1]: 3 corners outside, no texels.
TEST(AtlasUvProxy, MeshUvCheckCountsOverlapsAndOutsideCorners) {
  const MeshData mesh = test::make_flat_uv_soup({{0, 0},
                                                 {1, 0},
                                                 {0, 1},
                                                 {0, 0},
                                                 {1, 0},
                                                 {0, 1},
                                                 {1, 0},
                                                 {1, 1},
                                                 {0, 1},
                                                 {1.2f, 0},
                                                 {1.5f, 0},
                                                 {1.2f, 0.3f}});
  const MeshUvCheck check = check_mesh_uvs(mesh, 8);
  EXPECT_EQ(check.corners_outside, 3u);
  EXPECT_EQ(check.covered_texels, 56u);
  EXPECT_EQ(check.overlap_texels, 28u);
}

}  // namespace
}  // namespace texbake
