// Tests of FitOptions::anchor and ::height (bake/fit/fit_proxy.h): values the
// user gives are kept and the rest is re-fitted around them. Expected values
// come from the shapes' construction (points exactly on a known surface, or
// with 1 % noise for the cone's profile) and brute-force maxima computed
// here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "bake/fit/fit_proxy.h"

namespace texbake {
namespace {

constexpr double kPi = std::numbers::pi;

double degrees_between(Vec3 a, Vec3 b) {
  return std::acos(std::clamp(dot(normalize(a), normalize(b)), -1.0, 1.0)) * 180 / kPi;
}

// A frame (e1, e2) perpendicular to unit n.
std::pair<Vec3, Vec3> frame(Vec3 n) {
  const Vec3 helper = std::abs(n.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
  const Vec3 e1 = normalize(cross(helper, n));
  return {e1, cross(n, e1)};
}

Float3 f3(Vec3 p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}
Vec3 v3(Float3 p) {
  return {p.x, p.y, p.z};
}

// Lateral surface of a cylinder on a regular grid (exactly on the surface
// up to float rounding), rings at both ends included.
std::vector<Float3> cylinder_points(Vec3 base, Vec3 axis, double r, double h) {
  const auto [e1, e2] = frame(axis);
  std::vector<Float3> p;
  for (int k = 0; k <= 20; ++k) {
    for (int i = 0; i < 48; ++i) {
      const double a = 2 * kPi * i / 48;
      p.push_back(f3(base + axis * (h * k / 20) + (e1 * std::cos(a) + e2 * std::sin(a)) * r));
    }
  }
  return p;
}

// Lateral surface of a cone (apex, axis from base to apex), area-uniform,
// each point displaced by noise uniform in a ball of radius `noise`.
std::vector<Float3> cone_points(Vec3 apex, Vec3 axis, double radius, double height, double noise,
                                unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> g;
  const auto [e1, e2] = frame(axis);
  std::vector<Float3> p;
  for (int j = 0; j < 120; ++j) {
    for (int i = 0; i < 120; ++i) {
      const double t = height * std::sqrt((j + u01(rng)) / 120);
      const double a = 2 * kPi * (i + u01(rng)) / 120;
      Vec3 d{g(rng), g(rng), g(rng)};
      d = normalize(d) * (noise * std::cbrt(u01(rng)));
      p.push_back(
          f3(apex - axis * t + (e1 * std::cos(a) + e2 * std::sin(a)) * (radius * t / height) + d));
    }
  }
  return p;
}

TEST(FitAnchored, SphereAroundAGivenCentreEnclosesEveryPoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Float3> points;
  for (int i = 0; i < 500; ++i) points.push_back(f3({3 + u(rng), u(rng), 2 * u(rng)}));
  const Vec3 center{1, 0.5, -0.25};
  double want = 0;
  for (const Float3& p : points) want = std::max(want, length(v3(p) - center));
  FitOptions o;
  o.anchor = center;
  auto s = fit_sphere(points, o);
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_EQ(s->center.x, center.x);
  EXPECT_EQ(s->center.y, center.y);
  EXPECT_EQ(s->center.z, center.z);
  EXPECT_NEAR(s->radius, want, 1e-12 * want);
  // The free fit is smaller: the given centre is not the cloud's.
  auto free_fit = fit_sphere(points);
  ASSERT_TRUE(free_fit);
  EXPECT_LT(free_fit->radius, 0.8 * s->radius);

  o.anchor = Vec3{0, 0, 0};
  const std::vector<Float3> at_centre(3, Float3{0, 0, 0});
  EXPECT_FALSE(fit_sphere(at_centre, o));
}

TEST(FitAnchored, CylinderThroughAGivenBaseReachesTheTop) {
  const Vec3 axis = normalize(Vec3{1, 1, 3});
  const Vec3 base{2, -1, 0.5};
  const std::vector<Float3> points = cylinder_points(base, axis, 1.5, 4);
  const Vec3 below = base - axis * 1.0;  // one unit below the points
  for (bool given_axis : {true, false}) {
    SCOPED_TRACE(given_axis ? "given axis" : "fitted axis");
    FitOptions o;
    o.anchor = below;
    if (given_axis) o.axis = axis * 2.0;  // need not be unit
    auto c = fit_cylinder(points, o);
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->base.x, below.x);
    EXPECT_EQ(c->base.z, below.z);
    EXPECT_LT(degrees_between(c->axis, axis), given_axis ? 1e-9 : 0.01);  // base -> top
    EXPECT_NEAR(c->radius, 1.5, 1e-5);
    EXPECT_NEAR(c->height, 5.0, 1e-5);
  }
  // A base above the top without a fixed sign: the axis turns down.
  const Vec3 above = base + axis * 5.0;
  FitOptions o;
  o.anchor = above;
  auto c = fit_cylinder(points, o);
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_LT(degrees_between(c->axis, -axis), 0.01);
  EXPECT_NEAR(c->height, 5.0, 1e-5);
  // ... but a given axis keeps its sign: every point is behind the base.
  o.axis = axis;
  auto bad = fit_cylinder(points, o);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("behind the given base"), std::string::npos)
      << bad.error().message;
}

// Cone: apex (1, 2, 3), axis +Z, radius 2, height 3 (slope 2/3), 1 % noise.
TEST(FitAnchored, ConeThroughAGivenApexFitsTheGeneratorThroughIt) {
  const Vec3 apex{1, 2, 3}, axis{0, 0, 1};
  const std::vector<Float3> points = cone_points(apex, axis, 2, 3, 0.02, 11);
  FitOptions o;
  o.anchor = apex;
  auto c = fit_cone(points, o);
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c->apex.x, 1);
  EXPECT_EQ(c->apex.z, 3);
  EXPECT_LT(degrees_between(c->axis, axis), 1.0);
  EXPECT_NEAR(c->height, 3, 0.03);  // the points' extent below the apex (+ noise)
  EXPECT_NEAR(c->radius / c->height, 2.0 / 3, 0.01);
  // A given height moves the base plane along the generator: radius = slope * height.
  o.height = 6;
  auto tall = fit_cone(points, o);
  ASSERT_TRUE(tall) << tall.error().message;
  EXPECT_EQ(tall->height, 6);
  EXPECT_NEAR(tall->radius, 4, 0.04);
  // The same without a given apex: the fitted apex, radius at 6 below it.
  FitOptions h;
  h.height = 6;
  auto fitted = fit_cone(points, h);
  ASSERT_TRUE(fitted) << fitted.error().message;
  EXPECT_LE(length(fitted->apex - apex), 0.03);
  EXPECT_EQ(fitted->height, 6);
  EXPECT_NEAR(fitted->radius, 4, 0.04);
  // An apex below the base with the axis' sign fixed upwards: the points lie
  // beyond the apex along the axis.
  FitOptions wrong;
  wrong.anchor = Vec3{1, 2, -1};
  wrong.axis = axis;
  auto bad = fit_cone(points, wrong);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("beyond the given apex"), std::string::npos)
      << bad.error().message;
}

TEST(FitAnchored, DiskAroundAGivenCentreReachesTheFarthestPointInItsPlane) {
  const Vec3 n = normalize(Vec3{0, 1, 1});
  const auto [e1, e2] = frame(n);
  const Vec3 center{0, 0, 2};
  std::vector<Float3> points;
  for (int k = 1; k <= 5; ++k) {
    for (int i = 0; i < 40; ++i) {
      const double a = 2 * kPi * i / 40;
      points.push_back(f3(center + (e1 * std::cos(a) + e2 * std::sin(a)) * (0.4 * k)));
    }
  }
  const Vec3 given = center + e1 * 0.5 + n * 0.1;  // off-centre, off-plane
  double want = 0;
  for (const Float3& p : points) {
    const Vec3 w = v3(p) - given;
    want = std::max(want, length(w - n * dot(w, n)));
  }
  EXPECT_NEAR(want, 2.5, 1e-5);  // the rim point opposite e1
  FitOptions o;
  o.anchor = given;
  auto d = fit_disk(points, o);
  ASSERT_TRUE(d) << d.error().message;
  EXPECT_EQ(d->center.y, given.y);
  EXPECT_LT(degrees_between(d->normal, n), 1e-3);
  EXPECT_NEAR(d->radius, want, 1e-9);
}

TEST(FitAnchored, PlaneFromAGivenOriginReachesTheFarthestPoint) {
  // The floor rectangle [0, 4] x [0, 2] at z = 0 (u along +X, v along +Y,
  // fit_proxy.h's floor rule), origin given at (-1, -1, 0).
  std::vector<Float3> points;
  for (int j = 0; j <= 10; ++j) {
    for (int i = 0; i <= 20; ++i) points.push_back({0.2f * i, 0.2f * j, 0});
  }
  FitOptions o;
  o.anchor = Vec3{-1, -1, 0};
  auto p = fit_plane(points, o);
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ(p->origin.x, -1);
  EXPECT_LE(length(p->u_axis - Vec3{5, 0, 0}), 1e-5);
  EXPECT_LE(length(p->v_axis - Vec3{0, 3, 0}), 1e-5);
  // An origin beyond every point in u leaves no length for the u axis.
  o.anchor = Vec3{5, 0, 0};
  auto bad = fit_plane(points, o);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("positive u side"), std::string::npos) << bad.error().message;
}

}  // namespace
}  // namespace texbake
