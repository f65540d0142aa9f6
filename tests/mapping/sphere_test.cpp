// Sphere: the worked example of SPEC section 2, the textbook acos form against
// the atan2 form, and the poles.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "mapping/image_view.h"
#include "mapping/proxy.h"

namespace texbake {
namespace {

Sphere unit_sphere() {
  Expected<Proxy> p = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{1, 0, 0}});
  EXPECT_TRUE(p.has_value());
  return std::get<Sphere>(*p);
}

// Circular distance on the u circle: 0.9999999 and 0 are neighbours.
double u_distance(double a, double b) {
  const double d = std::abs(a - b);
  return std::min(d, 1 - d);
}

TEST(SphereWorkedExample, FirstNormalGivesQuarterOfFirstQuadrant) {
  // SPEC section 2: Sp = (0,0,1), Se = (1,0,0), Sn = (1,1,1)/sqrt(3).
  // By hand: phi = acos(-1/sqrt(3)) = 2.186276, v = phi/pi = 0.695913;
  // (Sp x Se) = (0,1,0), so u = atan2(1, 1)/(2 pi) = 1/8.
  const Sphere s = unit_sphere();
  const MapResult r = s.inverse_map(Vec3{1, 1, 1} / std::sqrt(3.0));
  EXPECT_EQ(r.status, MapStatus::kOk);
  EXPECT_NEAR(r.uv.u, 0.125, 1e-6);
  EXPECT_NEAR(r.uv.v, 0.695913, 1e-6);
  EXPECT_NEAR(r.uv.v * std::numbers::pi, 2.186276, 1e-6);
  const UV textbook = s.inverse_map_textbook(Vec3{1, 1, 1} / std::sqrt(3.0));
  EXPECT_NEAR(textbook.u, 0.125, 1e-6);
  EXPECT_NEAR(textbook.v, 0.695913, 1e-6);
}

TEST(SphereWorkedExample, SecondNormalIsTheSlidesValue) {
  // The slides' (0.875, 0.696) belongs to Sn = (1,-1,1)/sqrt(3): their sign slip.
  const Sphere s = unit_sphere();
  const MapResult r = s.inverse_map(Vec3{1, -1, 1} / std::sqrt(3.0));
  EXPECT_NEAR(r.uv.u, 0.875, 1e-6);
  EXPECT_NEAR(r.uv.v, 0.695913, 1e-6);
  const UV textbook = s.inverse_map_textbook(Vec3{1, -1, 1} / std::sqrt(3.0));
  EXPECT_NEAR(textbook.u, 0.875, 1e-6);
  EXPECT_NEAR(textbook.v, 0.695913, 1e-6);
}

TEST(SphereWorkedExample, PixelPositionIn640x480) {
  // SPEC section 1 by hand: x = 0.875*640 - 0.5 = 559.5;
  // y = (1 - 0.6959133)*480 - 0.5 = 145.9616 - 0.5 = 145.46.
  const Sphere s = unit_sphere();
  const MapResult r = s.inverse_map(Vec3{1, -1, 1} / std::sqrt(3.0));
  const PixelPos px = pixel_from_uv(r.uv, 640, 480);
  EXPECT_NEAR(px.x, 559.5, 1e-6);
  EXPECT_NEAR(px.y, 145.46, 0.005);
}

TEST(SphereWorkedExample, WorldPointOffCentreGivesSameUv) {
  // Only the direction from the centre matters, not the distance.
  Expected<Proxy> p = make_proxy(SphereParams{{10, -2, 3}, 5, {0, 0, 7}, Vec3{3, 0, 0}});
  ASSERT_TRUE(p.has_value());
  const MapResult r = inverse_map(*p, Vec3{10, -2, 3} + Vec3{2, 2, 2});
  EXPECT_NEAR(r.uv.u, 0.125, 1e-12);
  EXPECT_NEAR(r.uv.v, 0.695913276, 1e-9);
  EXPECT_NEAR(r.to_projector.x, 1 / std::sqrt(3.0), 1e-12);
}

TEST(Sphere, TextbookAndAtan2FormsAgreeAwayFromThePoles) {
  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> coord(-1, 1);
  Expected<Proxy> p = make_proxy(SphereParams{{1, 2, 3}, 2, {1, 2, 2}, Vec3{0, 1, -1}});
  ASSERT_TRUE(p.has_value());
  const Sphere& s = std::get<Sphere>(*p);
  int compared = 0;
  while (compared < 10000) {
    const Vec3 dir{coord(rng), coord(rng), coord(rng)};
    const double len = length(dir);
    if (len < 0.1 || len > 1) continue;
    // Away from the poles: |cos(phi)| < 0.999.
    if (std::abs(dot(dir / len, s.frame.axis)) > 0.999) continue;
    const Vec3 point = s.center + dir * 3.0;
    const UV a = s.inverse_map(point).uv;
    const UV b = s.inverse_map_textbook(point);
    ASSERT_LT(u_distance(a.u, b.u), 1e-9) << "dir " << dir.x << "," << dir.y << "," << dir.z;
    ASSERT_NEAR(a.v, b.v, 1e-9);
    ++compared;
  }
}

TEST(Sphere, PolesGiveUZeroAndNoNaN) {
  // A pole along no coordinate axis, so Sn at the pole is not exact.
  Expected<Proxy> p = make_proxy(SphereParams{{0.3, -0.7, 1.1}, 2.5, {1, 2, 3}, std::nullopt});
  ASSERT_TRUE(p.has_value());
  const Sphere& s = std::get<Sphere>(*p);
  for (double sign : {1.0, -1.0}) {
    const MapResult r = s.inverse_map(s.center + s.frame.axis * (sign * s.radius));
    EXPECT_EQ(r.uv.u, 0.0);
    EXPECT_NEAR(r.uv.v, sign > 0 ? 1.0 : 0.0, 1e-12);
    EXPECT_EQ(r.status, MapStatus::kOk);
    EXPECT_TRUE(is_finite(r.to_projector));
    // The forward map of any u at the pole is the pole itself.
    for (double u : {0.0, 0.3, 0.9}) {
      const Vec3 q = s.forward_map({u, sign > 0 ? 1.0 : 0.0});
      EXPECT_LT(length(q - (s.center + s.frame.axis * (sign * s.radius))), 1e-12);
    }
  }
  const UV exact_pole = unit_sphere().inverse_map_textbook({0, 0, 1});
  EXPECT_EQ(exact_pole.u, 0.0);
  EXPECT_EQ(exact_pole.v, 1.0);
}

TEST(Sphere, CentreIsUndefinedWithFiniteResult) {
  const Sphere s = unit_sphere();
  const MapResult r = s.inverse_map({0, 0, 0});
  EXPECT_EQ(r.status, MapStatus::kUndefined);
  EXPECT_TRUE(std::isfinite(r.uv.u) && std::isfinite(r.uv.v));
  EXPECT_TRUE(is_finite(r.to_projector));
  const MapResult nan = s.inverse_map({std::nan(""), 0, 0});
  EXPECT_EQ(nan.status, MapStatus::kUndefined);
  EXPECT_TRUE(std::isfinite(nan.uv.u) && std::isfinite(nan.uv.v));
}

TEST(Sphere, VRunsFromSouthPoleToNorthPole) {
  // v = 0 at -pole (bottom image row), 0.5 on the equator, 1 at +pole.
  const Sphere s = unit_sphere();
  EXPECT_NEAR(s.inverse_map({0, 0, -1}).uv.v, 0.0, 1e-15);
  EXPECT_NEAR(s.inverse_map({1, 0, 0}).uv.v, 0.5, 1e-15);
  EXPECT_NEAR(s.inverse_map({0, 0, 1}).uv.v, 1.0, 1e-15);
  EXPECT_NEAR(s.inverse_map({0, 1, 0}).uv.u, 0.25, 1e-15);
  EXPECT_NEAR(s.inverse_map({-1, 0, 0}).uv.u, 0.5, 1e-15);
  EXPECT_NEAR(s.inverse_map({0, -1, 0}).uv.u, 0.75, 1e-15);
}

}  // namespace
}  // namespace texbake
