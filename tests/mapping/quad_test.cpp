// Quad: bilinear-patch inversion (general convex, parallelogram, rectangle),
// points outside, and rejected shapes. Expected values are worked out by hand
// from the patch formula of SPEC section 2.
#include <gtest/gtest.h>

#include <cmath>

#include "mapping/proxy.h"

namespace texbake {
namespace {

Proxy quad(Vec3 p00, Vec3 p10, Vec3 p11, Vec3 p01) {
  Expected<Proxy> q = make_proxy(QuadParams{{p00, p10, p11, p01}});
  EXPECT_TRUE(q.has_value()) << q.error().message;
  return *q;
}

TEST(Quad, RectangleIsAffine) {
  // 4 x 2 rectangle in z = 0: P = (1, 0.5) is (1/4, 0.5/2).
  const Proxy q = quad({0, 0, 0}, {4, 0, 0}, {4, 2, 0}, {0, 2, 0});
  const MapResult r = inverse_map(q, {1, 0.5, 0});
  EXPECT_NEAR(r.uv.u, 0.25, 1e-15);
  EXPECT_NEAR(r.uv.v, 0.25, 1e-15);
  EXPECT_EQ(r.status, MapStatus::kOk);
  EXPECT_NEAR(r.to_projector.z, 1.0, 1e-15);  // (p10-p00) x (p01-p00) = +z
  // Off the plane: projected onto it first.
  const MapResult above = inverse_map(q, {1, 0.5, 7});
  EXPECT_NEAR(above.uv.u, 0.25, 1e-15);
  EXPECT_NEAR(above.uv.v, 0.25, 1e-15);
  // Corners map to the unit square's corners.
  EXPECT_NEAR(inverse_map(q, {4, 2, 0}).uv.u, 1.0, 1e-15);
  EXPECT_NEAR(inverse_map(q, {4, 2, 0}).uv.v, 1.0, 1e-15);
}

TEST(Quad, ParallelogramWhereTheQuadraticDegenerates) {
  // e = (2,0), f = (1,1), g = 0: P = u e + v f. P = (1.5, 0.5): v = 0.5,
  // u = (1.5 - 0.5)/2 = 0.5. P = (2, 0.5): u = 0.75.
  const Proxy q = quad({0, 0, 0}, {2, 0, 0}, {3, 1, 0}, {1, 1, 0});
  MapResult r = inverse_map(q, {1.5, 0.5, 0});
  EXPECT_NEAR(r.uv.u, 0.5, 1e-15);
  EXPECT_NEAR(r.uv.v, 0.5, 1e-15);
  r = inverse_map(q, {2, 0.5, 0});
  EXPECT_NEAR(r.uv.u, 0.75, 1e-15);
  EXPECT_NEAR(r.uv.v, 0.5, 1e-15);
  EXPECT_EQ(r.status, MapStatus::kOk);
}

TEST(Quad, TrapezoidWithOneQuadraticRootInside) {
  // p00 (0,0), p10 (4,0), p11 (3,2), p01 (1,2): y = 2v; at v = 0.5 the
  // quad spans x in [0.5, 3.5], so P = (1, 1) is u = 0.5/3 = 1/6.
  const Proxy q = quad({0, 0, 0}, {4, 0, 0}, {3, 2, 0}, {1, 2, 0});
  const MapResult r = inverse_map(q, {1, 1, 0});
  EXPECT_NEAR(r.uv.u, 1.0 / 6, 1e-15);
  EXPECT_NEAR(r.uv.v, 0.5, 1e-15);
}

TEST(Quad, GeneralConvexQuadWithNoParallelSides) {
  // p00 (0,0), p10 (4,0), p11 (5,3), p01 (1,2). By hand at (u,v) = (0.25,0.5):
  // weights 0.375, 0.125, 0.125, 0.375 -> x = 0.5 + 0.625 + 0.375 = 1.5,
  // y = 0.375 + 0.75 = 1.125.
  const Proxy q = quad({0, 0, 0}, {4, 0, 0}, {5, 3, 0}, {1, 2, 0});
  const MapResult r = inverse_map(q, {1.5, 1.125, 0});
  EXPECT_NEAR(r.uv.u, 0.25, 1e-14);
  EXPECT_NEAR(r.uv.v, 0.5, 1e-14);
  EXPECT_EQ(r.status, MapStatus::kOk);
}

TEST(Quad, TiltedQuadInThreeDimensions) {
  // The general quad above, rotated so its plane is x + y + z = const and
  // shifted: (u, v) must not change. Rotation: rows of an orthonormal basis.
  const Vec3 ex = normalize(Vec3{1, -1, 0}), ey = normalize(Vec3{1, 1, -2}),
             ez = normalize(Vec3{1, 1, 1});
  const auto place = [&](double x, double y) { return Vec3{3, -1, 2} + ex * x + ey * y; };
  const Proxy q = quad(place(0, 0), place(4, 0), place(5, 3), place(1, 2));
  const MapResult r = inverse_map(q, place(1.5, 1.125) + ez * 0.3);
  EXPECT_NEAR(r.uv.u, 0.25, 1e-14);
  EXPECT_NEAR(r.uv.v, 0.5, 1e-14);
  EXPECT_NEAR(dot(r.to_projector, ez), 1.0, 1e-14);
}

TEST(Quad, PointsOutsideAreFlaggedWithTheirUnclampedCoordinate) {
  const Proxy rect = quad({0, 0, 0}, {4, 0, 0}, {4, 2, 0}, {0, 2, 0});
  MapResult r = inverse_map(rect, {5, 1, 0});
  EXPECT_EQ(r.status, MapStatus::kOutside);
  EXPECT_NEAR(r.uv.u, 1.25, 1e-15);
  EXPECT_NEAR(r.uv.v, 0.5, 1e-15);
  r = inverse_map(rect, {-1, -1, 0});
  EXPECT_EQ(r.status, MapStatus::kOutside);
  EXPECT_NEAR(r.uv.u, -0.25, 1e-15);
  EXPECT_NEAR(r.uv.v, -0.5, 1e-15);
  // Trapezoid, above the top edge (v = 1.5 by y = 2v): x = 2 is its middle.
  const Proxy trap = quad({0, 0, 0}, {4, 0, 0}, {3, 2, 0}, {1, 2, 0});
  r = inverse_map(trap, {2, 3, 0});
  EXPECT_EQ(r.status, MapStatus::kOutside);
  EXPECT_NEAR(r.uv.v, 1.5, 1e-14);
  EXPECT_NEAR(r.uv.u, 0.5, 1e-14);
  // Points far outside, where the roots may be complex: finite, outside.
  const Proxy general = quad({0, 0, 0}, {4, 0, 0}, {5, 3, 0}, {1, 2, 0});
  for (Vec3 p : {Vec3{100, -50, 0}, Vec3{-30, 80, 0}, Vec3{9, 9, 0}, Vec3{-5, 1, 0}}) {
    r = inverse_map(general, p);
    EXPECT_EQ(r.status, MapStatus::kOutside) << p.x << "," << p.y;
    EXPECT_TRUE(std::isfinite(r.uv.u) && std::isfinite(r.uv.v));
  }
}

TEST(Quad, BowTieAndNonConvexAreRejected) {
  Expected<Proxy> bow = make_proxy(QuadParams{{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}}});
  ASSERT_FALSE(bow.has_value());
  EXPECT_EQ(bow.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(bow.error().message.find("corners"), std::string::npos) << bow.error().message;
  EXPECT_NE(bow.error().message.find("quad"), std::string::npos) << bow.error().message;
  EXPECT_NE(bow.error().message.find("not convex"), std::string::npos) << bow.error().message;
  // A dart: p11 pushed inside the triangle of the other three.
  Expected<Proxy> dart = make_proxy(QuadParams{{{{0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}, {0, 2, 0}}}});
  ASSERT_FALSE(dart.has_value());
  EXPECT_NE(dart.error().message.find("not convex"), std::string::npos) << dart.error().message;
  // Three collinear corners (a triangle) and all-equal corners.
  EXPECT_FALSE(make_proxy(QuadParams{{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}}}}));
  EXPECT_FALSE(make_proxy(QuadParams{{{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}}}}));
  // Clockwise order is a valid convex quad: its normal points the other way.
  Expected<Proxy> cw = make_proxy(QuadParams{{{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}}});
  ASSERT_TRUE(cw.has_value());
  EXPECT_NEAR(std::get<Quad>(*cw).normal.z, -1.0, 1e-15);
}

TEST(Quad, NonPlanarBeyond1e6OfItsSizeIsRejected) {
  // Diagonal length sqrt(2): p11 lifted 0.01 is far beyond 1e-6 * sqrt(2).
  Expected<Proxy> bent = make_proxy(QuadParams{{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0.01}, {0, 1, 0}}}});
  ASSERT_FALSE(bent.has_value());
  EXPECT_NE(bent.error().message.find("not planar"), std::string::npos) << bent.error().message;
  // Lifted 1e-8: 1e-8 off the plane of the other three, within 1e-6 * sqrt(2).
  EXPECT_TRUE(make_proxy(QuadParams{{{{0, 0, 0}, {1, 0, 0}, {1, 1, 1e-8}, {0, 1, 0}}}}));
  // The tolerance scales with size: the same shape 1000 times larger.
  EXPECT_TRUE(
      make_proxy(QuadParams{{{{0, 0, 0}, {1000, 0, 0}, {1000, 1000, 1e-5}, {0, 1000, 0}}}}));
  EXPECT_FALSE(make_proxy(QuadParams{{{{0, 0, 0}, {1, 0, 0}, {1, 1, 1e-5}, {0, 1, 0}}}}));
  // Just either side of the bound: 1.4e-6 passes, 1.42e-6 (> 1e-6 sqrt 2) fails.
  EXPECT_TRUE(make_proxy(QuadParams{{{{0, 0, 0}, {1, 0, 0}, {1, 1, 1.40e-6}, {0, 1, 0}}}}));
  EXPECT_FALSE(make_proxy(QuadParams{{{{0, 0, 0}, {1, 0, 0}, {1, 1, 1.42e-6}, {0, 1, 0}}}}));
}

}  // namespace
}  // namespace texbake
