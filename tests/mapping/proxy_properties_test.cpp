// Properties every proxy must have (issue #2): forward-then-inverse round
// trips on 10,000 seeded random (u, v), seam continuity, handedness, and
// u = 0 on the axis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>
#include <random>
#include <string>

#include "mapping/proxy.h"

namespace texbake {

// Readable parameter names in gtest's failure messages.
void PrintTo(ProxyKind kind, std::ostream* out) {
  *out << to_string(kind);
}

namespace {

constexpr int kRoundTrips = 10000;

double u_distance(double a, double b) {
  const double d = std::abs(a - b);
  return std::min(d, 1 - d);
}

// Random proxies of every kind, in general position (tilted axes, off-origin
// centres, scales from 0.2 to 20), drawn from a seeded generator.
class RandomProxies {
 public:
  explicit RandomProxies(std::uint64_t seed) : rng_(seed) {}

  Vec3 point() { return {sym(10), sym(10), sym(10)}; }
  Vec3 direction() {
    for (;;) {
      const Vec3 d{sym(1), sym(1), sym(1)};
      if (length(d) > 0.2 && length(d) < 1) return d * scale();
    }
  }
  double scale() { return std::exp(uniform(std::log(0.2), std::log(20.0))); }
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }

  Proxy make(ProxyKind kind) {
    for (;;) {
      Expected<Proxy> p = make_proxy(params(kind));
      if (p) return *p;  // rare rejects: an equator drawn nearly parallel
    }
  }

 private:
  double sym(double r) { return uniform(-r, r); }

  ProxyParams params(ProxyKind kind) {
    switch (kind) {
      case ProxyKind::kSphere:
        return SphereParams{point(), scale(), direction(), direction()};
      case ProxyKind::kCylinder:
        return CylinderParams{point(), direction(), direction(), scale(), scale()};
      case ProxyKind::kCone:
        return ConeParams{point(), direction(), direction(), scale(), scale()};
      case ProxyKind::kDisk:
        return DiskParams{point(), direction(), direction(), scale()};
      case ProxyKind::kQuad: {
        // Four points on an ellipse in cyclic order form a convex quad; keep
        // the angular gaps >= 0.4 rad so it is not nearly degenerate.
        const Vec3 a = direction(), b = cross(a, direction());
        const Vec3 c = point();
        for (;;) {
          double t[4];
          for (double& x : t) x = uniform(0, 2 * std::numbers::pi);
          std::sort(t, t + 4);
          bool ok = t[0] + 2 * std::numbers::pi - t[3] > 0.4;
          for (int i = 0; i < 3; ++i) ok = ok && t[i + 1] - t[i] > 0.4;
          if (!ok) continue;
          QuadParams q;
          for (int i = 0; i < 4; ++i) q.corners[i] = c + a * std::cos(t[i]) + b * std::sin(t[i]);
          return q;
        }
      }
      case ProxyKind::kPlane:
        return PlaneParams{point(), direction(), direction()};
    }
    return SphereParams{};
  }

  std::mt19937_64 rng_;
};

const ProxyKind kAllKinds[] = {ProxyKind::kSphere, ProxyKind::kCylinder, ProxyKind::kCone,
                               ProxyKind::kDisk,   ProxyKind::kQuad,     ProxyKind::kPlane};
const ProxyKind kPeriodicKinds[] = {ProxyKind::kSphere, ProxyKind::kCylinder, ProxyKind::kCone,
                                    ProxyKind::kDisk};

class EveryProxy : public testing::TestWithParam<ProxyKind> {};

TEST_P(EveryProxy, ForwardThenInverseRoundTripsTo1e9) {
  RandomProxies random(1234 + static_cast<int>(GetParam()));
  const bool periodic = GetParam() != ProxyKind::kQuad && GetParam() != ProxyKind::kPlane;
  Proxy proxy = random.make(GetParam());
  for (int i = 0; i < kRoundTrips; ++i) {
    // A new proxy every 100 samples: 100 shapes in general position.
    if (i % 100 == 0) proxy = random.make(GetParam());
    const UV uv{random.uniform(0, 1), random.uniform(0, 1)};
    const Vec3 p = forward_map(proxy, uv);
    const MapResult r = inverse_map(proxy, p);
    ASSERT_EQ(r.status, MapStatus::kOk) << "sample " << i << " uv " << uv.u << "," << uv.v;
    const double du = periodic ? u_distance(r.uv.u, uv.u) : std::abs(r.uv.u - uv.u);
    ASSERT_LT(du, 1e-9) << "sample " << i << " uv " << uv.u << "," << uv.v << " -> " << r.uv.u;
    ASSERT_NEAR(r.uv.v, uv.v, 1e-9) << "sample " << i << " uv " << uv.u << "," << uv.v;
    ASSERT_NEAR(length(r.to_projector), 1.0, 1e-12);
  }
}

// Handedness (SPEC section 1): with x = dP/du (image right) and y = dP/dv
// (image up), an unmirrored image seen from the projector's side has
// (x cross y) pointing towards the viewer, i.e. along d(P).
double orientation(const Proxy& proxy, UV uv) {
  const double h = 1e-6;
  const Vec3 du = forward_map(proxy, {uv.u + h, uv.v}) - forward_map(proxy, {uv.u - h, uv.v});
  const Vec3 dv = forward_map(proxy, {uv.u, uv.v + h}) - forward_map(proxy, {uv.u, uv.v - h});
  const Vec3 d = inverse_map(proxy, forward_map(proxy, uv)).to_projector;
  return dot(normalize(cross(du, dv)), d);
}

TEST_P(EveryProxy, ImageSeenFromTheProjectorIsNotMirrored) {
  RandomProxies random(99 + static_cast<int>(GetParam()));
  for (int i = 0; i < 200; ++i) {
    const Proxy proxy = random.make(GetParam());
    const UV uv{random.uniform(0.05, 0.95), random.uniform(0.05, 0.95)};
    const double o = orientation(proxy, uv);
    if (GetParam() == ProxyKind::kDisk) {
      // SPEC section 2 fixes the disk as u counter-clockwise seen from the
      // normal's tip and v = r / radius growing outwards. In (u, v) that is
      // (tangent, radial) = a left-handed pair about the normal: the one proxy
      // whose image reads mirrored from the projector side (reported to the
      // lead as a SPEC contradiction). Pin the behaviour so a change is seen.
      ASSERT_LT(o, -0.999) << "sample " << i;
    } else {
      ASSERT_GT(o, 0.999) << "sample " << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, EveryProxy, testing::ValuesIn(kAllKinds),
                         [](const testing::TestParamInfo<ProxyKind>& info) {
                           return std::string(to_string(info.param));
                         });

class PeriodicProxy : public testing::TestWithParam<ProxyKind> {};

TEST_P(PeriodicProxy, PointsEitherSideOfTheSeamAreNeighbours) {
  RandomProxies random(7 + static_cast<int>(GetParam()));
  for (int i = 0; i < 100; ++i) {
    const Proxy proxy = random.make(GetParam());
    const double v = random.uniform(0.1, 0.9);
    const double eps = 1e-7;
    const Vec3 before = forward_map(proxy, {1 - eps, v});
    const Vec3 after = forward_map(proxy, {eps, v});
    const Vec3 on_seam = forward_map(proxy, {0, v});
    // Neighbouring points in space (a 2 eps turn of a circle of radius <= 40)...
    EXPECT_LT(length(after - before), 2 * eps * 2 * std::numbers::pi * 40);
    EXPECT_LT(length(after - before), 10 * length(after - on_seam));
    // ...map to neighbouring u across the seam, and the seam itself to u in [0, 1).
    const MapResult a = inverse_map(proxy, before), b = inverse_map(proxy, after);
    EXPECT_NEAR(a.uv.u, 1 - eps, 1e-9);
    EXPECT_NEAR(b.uv.u, eps, 1e-9);
    EXPECT_LT(u_distance(a.uv.u, b.uv.u), 2 * eps + 1e-9);
    const double seam_u = inverse_map(proxy, on_seam).uv.u;
    EXPECT_TRUE(seam_u >= 0 && seam_u < 1) << seam_u;
    EXPECT_LT(u_distance(seam_u, 0), 1e-9);
  }
}

TEST_P(PeriodicProxy, UIsPeriodicForTheSampler) {
  RandomProxies random(11);
  EXPECT_EQ(wrap_u(random.make(GetParam())), WrapMode::kRepeat);
}

INSTANTIATE_TEST_SUITE_P(Kinds, PeriodicProxy, testing::ValuesIn(kPeriodicKinds),
                         [](const testing::TestParamInfo<ProxyKind>& info) {
                           return std::string(to_string(info.param));
                         });

TEST(Proxy, QuadAndPlaneClampU) {
  RandomProxies random(5);
  EXPECT_EQ(wrap_u(random.make(ProxyKind::kQuad)), WrapMode::kClamp);
  EXPECT_EQ(wrap_u(random.make(ProxyKind::kPlane)), WrapMode::kClamp);
}

TEST(Cone, ApexGivesUZeroVOneAndNoNaN) {
  Expected<Proxy> p = make_proxy(ConeParams{{1, 2, 3}, {1, 1, 3}, std::nullopt, 2, 0.5});
  ASSERT_TRUE(p.has_value());
  const Cone& c = std::get<Cone>(*p);
  const MapResult r = c.inverse_map(c.apex);
  EXPECT_EQ(r.uv.u, 0.0);
  EXPECT_EQ(r.uv.v, 1.0);
  EXPECT_EQ(r.status, MapStatus::kOk);
  EXPECT_TRUE(is_finite(r.to_projector));
  // The forward map of v = 1 is the apex for every u.
  EXPECT_LT(length(c.forward_map({0.37, 1}) - c.apex), 1e-15);
  // Elsewhere on the axis the closest generator point is a whole circle.
  const MapResult inside = c.inverse_map(c.apex - c.frame.axis * 1.0);
  EXPECT_EQ(inside.status, MapStatus::kUndefined);
  EXPECT_EQ(inside.uv.u, 0.0);
  EXPECT_TRUE(std::isfinite(inside.uv.v) && is_finite(inside.to_projector));
}

TEST(Cone, VIsTheClosestGeneratorPointAndDTheOutwardNormal) {
  // Apex at the origin, axis +z, height 1, base radius 1: the generator in
  // the x-z half-plane runs from (0,0,0) to the rim (1,0,-1). P = (1,0,0):
  // by hand, its closest point on that line is (0.5,0,-0.5), halfway, so
  // v = 0.5; outward normal (1,0,1)/sqrt(2); u = 0 (equator +x).
  Expected<Proxy> p = make_proxy(ConeParams{{0, 0, 0}, {0, 0, 1}, Vec3{1, 0, 0}, 1, 1});
  ASSERT_TRUE(p.has_value());
  const MapResult r = inverse_map(*p, {1, 0, 0});
  EXPECT_NEAR(r.uv.u, 0.0, 1e-15);
  EXPECT_NEAR(r.uv.v, 0.5, 1e-15);
  EXPECT_NEAR(r.to_projector.x, 1 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(r.to_projector.z, 1 / std::sqrt(2.0), 1e-15);
  EXPECT_EQ(r.status, MapStatus::kOk);
  // Below the base rim, further out along the generator: v < 0, outside.
  // P = (2,0,-2): lambda = (2 + 2)/2 = 2, v = -1.
  const MapResult below = inverse_map(*p, {2, 0, -2});
  EXPECT_NEAR(below.uv.v, -1.0, 1e-15);
  EXPECT_EQ(below.status, MapStatus::kOutside);
  // u = 0.25 at +y (counter-clockwise seen from the axis tip).
  EXPECT_NEAR(inverse_map(*p, {0, 1, -0.5}).uv.u, 0.25, 1e-15);
}

TEST(Cylinder, AxisIsUndefinedWithFiniteResultAndHeightOutside) {
  Expected<Proxy> p = make_proxy(CylinderParams{{0, 0, 1}, {0, 0, 2}, Vec3{0, 1, 0}, 2, 4});
  ASSERT_TRUE(p.has_value());
  const MapResult axis = inverse_map(*p, {0, 0, 2});
  EXPECT_EQ(axis.status, MapStatus::kUndefined);
  EXPECT_EQ(axis.uv.u, 0.0);
  EXPECT_NEAR(axis.uv.v, 0.25, 1e-15);
  EXPECT_TRUE(is_finite(axis.to_projector));
  // Equator +y: P = (0,3,3) is at u = 0, v = (3-1)/4 = 0.5, d = +y.
  const MapResult r = inverse_map(*p, {0, 3, 3});
  EXPECT_NEAR(r.uv.u, 0.0, 1e-15);
  EXPECT_NEAR(r.uv.v, 0.5, 1e-15);
  EXPECT_NEAR(r.to_projector.y, 1.0, 1e-15);
  // East = z x y = -x: u = 0.25 there.
  EXPECT_NEAR(inverse_map(*p, {-1, 0, 3}).uv.u, 0.25, 1e-15);
  const MapResult above = inverse_map(*p, {1, 0, 7});
  EXPECT_EQ(above.status, MapStatus::kOutside);
  EXPECT_NEAR(above.uv.v, 1.5, 1e-15);  // unclamped: the caller decides
}

TEST(Disk, CentreGivesUZeroAndOutsideBeyondTheRadius) {
  Expected<Proxy> p = make_proxy(DiskParams{{1, 1, 1}, {1, -2, 0.5}, std::nullopt, 3});
  ASSERT_TRUE(p.has_value());
  const Disk& d = std::get<Disk>(*p);
  const MapResult centre = d.inverse_map(d.center);
  EXPECT_EQ(centre.uv.u, 0.0);
  EXPECT_EQ(centre.uv.v, 0.0);
  EXPECT_EQ(centre.status, MapStatus::kOk);
  // Above the centre, off the plane: projected onto it, still the centre.
  const MapResult above = d.inverse_map(d.center + d.frame.axis * 5.0);
  EXPECT_EQ(above.uv.u, 0.0);
  EXPECT_NEAR(above.uv.v, 0.0, 1e-12);
  EXPECT_NEAR(dot(above.to_projector, d.frame.axis), 1.0, 1e-15);
  const MapResult far = d.inverse_map(d.center + d.frame.equator * 6.0);
  EXPECT_EQ(far.status, MapStatus::kOutside);
  EXPECT_NEAR(far.uv.v, 2.0, 1e-12);
}

TEST(Plane, SpecFormulaForPerpendicularAxesAndExactInverseOtherwise) {
  // SPEC: u = (P - origin) . u_axis / |u_axis|^2. Axes (2,0,0), (0,4,0):
  // P = (1,1,9) gives u = 2/4 = 0.5, v = 4/16 = 0.25 (z is ignored).
  Expected<Proxy> p = make_proxy(PlaneParams{{0, 0, 0}, {2, 0, 0}, {0, 4, 0}});
  ASSERT_TRUE(p.has_value());
  const MapResult r = inverse_map(*p, {1, 1, 9});
  EXPECT_NEAR(r.uv.u, 0.5, 1e-15);
  EXPECT_NEAR(r.uv.v, 0.25, 1e-15);
  EXPECT_NEAR(r.to_projector.z, 1.0, 1e-15);
  EXPECT_EQ(inverse_map(*p, {5, 1, 0}).status, MapStatus::kOutside);
  // Sheared axes (1,0,0), (1,1,0): P = (1.5, 0.5) = 1 u_axis + 0.5 v_axis.
  Expected<Proxy> sheared = make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}});
  ASSERT_TRUE(sheared.has_value());
  const MapResult s = inverse_map(*sheared, {1.5, 0.5, 0});
  EXPECT_NEAR(s.uv.u, 1.0, 1e-15);
  EXPECT_NEAR(s.uv.v, 0.5, 1e-15);
}

}  // namespace
}  // namespace texbake
