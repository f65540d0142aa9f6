// The analytic Jacobians of mapping/derivatives.h against central finite
// differences of inverse_map at seeded random points (relative error <= 1e-5
// away from poles, axes and seams), and their documented limits at the u
// seam (the continuous derivative) and on the axis (flags and v_rate).
#include "mapping/derivatives.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "mapping/proxy.h"

namespace texbake {
namespace {

constexpr double kPi = std::numbers::pi;

// u differences across the seam fold into [-0.5, 0.5]: the continuous derivative.
double wrapped(double du) {
  return du - std::round(du);
}

// Central differences of inverse_map along x, y, z with step h; u's
// differences are wrapped when `periodic`.
template <class P>
void finite_differences(const P& proxy, Vec3 p, double h, bool periodic, Vec3& du, Vec3& dv) {
  double gu[3], gv[3];
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 step{axis == 0 ? h : 0, axis == 1 ? h : 0, axis == 2 ? h : 0};
    const UV a = proxy.inverse_map(p + step).uv, b = proxy.inverse_map(p - step).uv;
    const double d_u = periodic ? wrapped(a.u - b.u) : a.u - b.u;
    gu[axis] = d_u / (2 * h);
    gv[axis] = (a.v - b.v) / (2 * h);
  }
  du = {gu[0], gu[1], gu[2]};
  dv = {gv[0], gv[1], gv[2]};
}

double relative_error(Vec3 analytic, Vec3 numeric) {
  return length(analytic - numeric) / std::max(length(numeric), 1e-300);
}

template <class P>
void expect_matches_differences(const P& proxy, Vec3 p, double h, bool periodic) {
  const UvJacobian j = inverse_map_jacobian(proxy, p);
  ASSERT_TRUE(j.u_defined && j.v_defined) << p.x << " " << p.y << " " << p.z;
  Vec3 du, dv;
  finite_differences(proxy, p, h, periodic, du, dv);
  EXPECT_LE(relative_error(j.du, du), 1e-5) << "du at " << p.x << " " << p.y << " " << p.z;
  EXPECT_LE(relative_error(j.dv, dv), 1e-5) << "dv at " << p.x << " " << p.y << " " << p.z;
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return normalize(Vec3{n(rng), n(rng), n(rng)});
}

template <class T>
T make(const ProxyParams& params) {
  Expected<Proxy> p = make_proxy(params);
  EXPECT_TRUE(p.has_value());
  return std::get<T>(*p);
}

// Away from the seam: u of p at least `margin` from 0 and 1.
bool off_seam(double u, double margin) {
  return u > margin && u < 1 - margin;
}

TEST(Derivatives, SphereMatchesFiniteDifferences) {
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 center{uni(rng) * 4 - 2, uni(rng) * 4 - 2, uni(rng) * 4 - 2};
    const double radius = 0.5 + 3 * uni(rng);
    const Sphere s = make<Sphere>(SphereParams{center, radius, random_unit(rng), random_unit(rng)});
    // Off the surface too (inverse_map is radial): 0.3 to 2 radii out.
    const UV uv{uni(rng), 0.05 + 0.9 * uni(rng)};
    const Vec3 p = s.center + (s.forward_map(uv) - s.center) * (0.3 + 1.7 * uni(rng));
    if (!off_seam(uv.u, 1e-3)) continue;
    expect_matches_differences(s, p, 1e-6 * radius, false);
  }
}

TEST(Derivatives, CylinderMatchesFiniteDifferences) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const double radius = 0.2 + 2 * uni(rng), height = 0.5 + 3 * uni(rng);
    const Cylinder c = make<Cylinder>(CylinderParams{
        {uni(rng), uni(rng), uni(rng)}, random_unit(rng), random_unit(rng), radius, height});
    const UV uv{uni(rng), uni(rng) * 1.2 - 0.1};  // also outside the height
    const Vec3 on_axis = c.base + c.frame.axis * (uv.v * height);
    const Vec3 p = on_axis + (c.forward_map(uv) - on_axis) * (0.2 + 1.5 * uni(rng));
    if (!off_seam(uv.u, 1e-3)) continue;
    expect_matches_differences(c, p, 1e-6 * radius, false);
  }
}

TEST(Derivatives, ConeMatchesFiniteDifferences) {
  std::mt19937_64 rng(18);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const double radius = 0.2 + 2 * uni(rng), height = 0.5 + 3 * uni(rng);
    const Cone c = make<Cone>(ConeParams{
        {uni(rng), uni(rng), uni(rng)}, random_unit(rng), random_unit(rng), height, radius});
    const UV uv{uni(rng), 0.05 + 0.9 * uni(rng)};
    // Off the surface along its normal, both ways (the closest-point rule).
    const MapResult on = c.inverse_map(c.forward_map(uv));
    const Vec3 p =
        c.forward_map(uv) + on.to_projector * ((uni(rng) - 0.5) * 0.2 * radius * (1 - uv.v));
    if (!off_seam(uv.u, 1e-3)) continue;
    expect_matches_differences(c, p, 1e-7 * radius, false);
  }
}

TEST(Derivatives, DiskMatchesFiniteDifferences) {
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const double radius = 0.2 + 2 * uni(rng);
    const Disk d = make<Disk>(
        DiskParams{{uni(rng), uni(rng), uni(rng)}, random_unit(rng), random_unit(rng), radius});
    const UV uv{uni(rng), 0.05 + 1.2 * uni(rng)};
    const Vec3 p = d.forward_map(uv) + d.frame.axis * ((uni(rng) - 0.5) * radius);
    if (!off_seam(uv.u, 1e-3)) continue;
    expect_matches_differences(d, p, 1e-6 * radius, false);
  }
}

TEST(Derivatives, QuadMatchesFiniteDifferences) {
  std::mt19937_64 rng(20);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    // A convex quad in a random plane: a square's corners moved by up to 0.25.
    const Vec3 a = random_unit(rng);
    const Vec3 b = normalize(cross(a, random_unit(rng)));
    const Vec3 o{uni(rng), uni(rng), uni(rng)};
    const double size = 0.5 + 2 * uni(rng);
    auto corner = [&](double x, double y) {
      return o + (a * (x + 0.25 * (uni(rng) - 0.5)) + b * (y + 0.25 * (uni(rng) - 0.5))) * size;
    };
    const Quad q = make<Quad>(QuadParams{{corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)}});
    const UV uv{uni(rng), uni(rng)};
    const Vec3 p = q.forward_map(uv) + q.normal * ((uni(rng) - 0.5) * size);
    expect_matches_differences(q, p, 1e-6 * size, false);
  }
}

TEST(Derivatives, PlaneMatchesFiniteDifferences) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int trial = 0; trial < 100; ++trial) {
    // Axes of any length and angle (not perpendicular in general).
    const Plane pl = make<Plane>(PlaneParams{{uni(rng), uni(rng), uni(rng)},
                                             random_unit(rng) * (0.2 + 3 * uni(rng)),
                                             random_unit(rng) * (0.2 + 3 * uni(rng))});
    const Vec3 p = pl.forward_map({uni(rng) * 3 - 1, uni(rng) * 3 - 1}) + pl.normal * uni(rng);
    expect_matches_differences(pl, p, 1e-4, false);
  }
}

// A second method: the Jacobian of the inverse times the forward map's
// tangents dP/du, dP/dv (central differences of forward_map) is the identity.
template <class P>
void expect_inverts_forward_tangents(const P& proxy, UV uv, double h) {
  const Vec3 p = proxy.forward_map(uv);
  const Vec3 pu =
      (proxy.forward_map({uv.u + h, uv.v}) - proxy.forward_map({uv.u - h, uv.v})) / (2 * h);
  const Vec3 pv =
      (proxy.forward_map({uv.u, uv.v + h}) - proxy.forward_map({uv.u, uv.v - h})) / (2 * h);
  const UvJacobian j = inverse_map_jacobian(proxy, p);
  ASSERT_TRUE(j.u_defined && j.v_defined);
  EXPECT_NEAR(dot(j.du, pu), 1, 1e-6) << uv.u << " " << uv.v;
  EXPECT_NEAR(dot(j.du, pv), 0, 1e-6) << uv.u << " " << uv.v;
  EXPECT_NEAR(dot(j.dv, pu), 0, 1e-6) << uv.u << " " << uv.v;
  EXPECT_NEAR(dot(j.dv, pv), 1, 1e-6) << uv.u << " " << uv.v;
}

TEST(Derivatives, InvertTheForwardMapsTangents) {
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> uni(0, 1);
  const Sphere s = make<Sphere>(SphereParams{{0.3, -1, 2}, 1.7, {1, 2, 3}, Vec3{1, 0, 0}});
  const Cylinder c = make<Cylinder>(CylinderParams{{1, 0, 0}, {0, 1, 1}, Vec3{1, 0, 0}, 0.8, 2.5});
  const Cone k = make<Cone>(ConeParams{{0, 0, 1}, {0, 0, 1}, Vec3{0, 1, 0}, 2, 1.5});
  const Disk d = make<Disk>(DiskParams{{0, 1, 0}, {1, 1, 0}, Vec3{0, 0, 1}, 1.2});
  const Quad q = make<Quad>(
      QuadParams{{Vec3{0, 0, 0}, Vec3{2, 0.2, 0}, Vec3{2.3, 1.8, 0}, Vec3{-0.2, 1.5, 0}}});
  const Plane pl = make<Plane>(PlaneParams{{0, 0, 0}, {2, 1, 0}, {-0.5, 1, 0.3}});
  for (int trial = 0; trial < 50; ++trial) {
    const UV uv{0.01 + 0.98 * uni(rng), 0.05 + 0.9 * uni(rng)};
    expect_inverts_forward_tangents(s, uv, 1e-6);
    expect_inverts_forward_tangents(c, uv, 1e-6);
    expect_inverts_forward_tangents(k, uv, 1e-6);
    expect_inverts_forward_tangents(d, uv, 1e-6);
    expect_inverts_forward_tangents(q, uv, 1e-6);
    expect_inverts_forward_tangents(pl, uv, 1e-6);
  }
}

TEST(Derivatives, PlaneByHand) {
  // u_axis (2, 0, 0), v_axis (0, 4, 0): u = x / 2, v = y / 4.
  const Plane pl = make<Plane>(PlaneParams{{1, 1, 1}, {2, 0, 0}, {0, 4, 0}});
  const UvJacobian j = inverse_map_jacobian(pl, {5, -3, 7});
  EXPECT_NEAR(length(j.du - Vec3{0.5, 0, 0}), 0, 1e-15);
  EXPECT_NEAR(length(j.dv - Vec3{0, 0.25, 0}), 0, 1e-15);
}

TEST(Derivatives, SphereByHandOnTheEquator) {
  // Unit sphere, pole +Z, equator +X, at P = (0, 1, 0) (u = 0.25, v = 0.5):
  // moving along -X turns u forward by 1 / (2 pi) per unit, along +Z raises
  // v by 1 / pi per unit.
  const Sphere s = make<Sphere>(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{1, 0, 0}});
  const UvJacobian j = inverse_map_jacobian(s, {0, 1, 0});
  EXPECT_NEAR(length(j.du - Vec3{-1 / (2 * kPi), 0, 0}), 0, 1e-15);
  EXPECT_NEAR(length(j.dv - Vec3{0, 0, 1 / kPi}), 0, 1e-15);
}

// The seam: the derivative at u = 0 is the one just before and just after
// it, and agrees with the wrapped finite difference.
template <class P>
void expect_continuous_at_seam(const P& proxy, Vec3 on_seam, double h) {
  const MapResult m = proxy.inverse_map(on_seam);
  ASSERT_EQ(m.uv.u, 0.0);
  expect_matches_differences(proxy, on_seam, h, /*periodic=*/true);
  const Frame& f = proxy.frame;
  // Rotate on_seam by +-1e-7 turns around the axis (through the proxy's origin point).
  const UvJacobian at = inverse_map_jacobian(proxy, on_seam);
  for (double turn : {1e-7, -1e-7}) {
    const double c = std::cos(2 * kPi * turn), s = std::sin(2 * kPi * turn);
    const Vec3 o = on_seam - f.equator * dot(on_seam, f.equator) - f.east * dot(on_seam, f.east);
    const double x = dot(on_seam, f.equator), y = dot(on_seam, f.east);
    const Vec3 q = o + f.equator * (c * x - s * y) + f.east * (s * x + c * y);
    const double u = proxy.inverse_map(q).uv.u;
    EXPECT_TRUE(turn > 0 ? u < 1e-6 : u > 1 - 1e-6) << u;
    const UvJacobian near = inverse_map_jacobian(proxy, q);
    EXPECT_LE(relative_error(near.du, at.du), 1e-6);
  }
}

TEST(Derivatives, SeamIsTheContinuousDerivative) {
  // Centred at the origin so the rotation about the axis is about the origin.
  expect_continuous_at_seam(make<Sphere>(SphereParams{{0, 0, 0}, 2, {0, 0, 1}, Vec3{1, 0, 0}}),
                            Vec3{1.5, 0, 0.7}, 1e-6);
  expect_continuous_at_seam(
      make<Cylinder>(CylinderParams{{0, 0, 0}, {0, 1, 0}, Vec3{0, 0, 1}, 1, 2}), Vec3{0, 0.5, 0.8},
      1e-6);
  expect_continuous_at_seam(make<Cone>(ConeParams{{0, 0, 0}, {0, 0, 1}, Vec3{1, 0, 0}, 2, 1}),
                            Vec3{0.5, 0, -1}, 1e-7);
  expect_continuous_at_seam(make<Disk>(DiskParams{{0, 0, 0}, {0, 0, 1}, Vec3{1, 0, 0}, 2}),
                            Vec3{1.2, 0, 0.3}, 1e-6);
  // Seam points with a wrapped difference of almost a whole period: without
  // the wrap it would be ~ -1 / (2 h).
  const Sphere s = make<Sphere>(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{1, 0, 0}});
  const UV a = s.inverse_map({1, 1e-6, 0}).uv, b = s.inverse_map({1, -1e-6, 0}).uv;
  EXPECT_GT(std::abs(a.u - b.u), 0.99);
  EXPECT_NEAR(wrapped(a.u - b.u) / 2e-6, inverse_map_jacobian(s, {1, 0, 0}).du.y, 1e-9);
}

TEST(Derivatives, SpherePolesAreFlaggedWithTheirRate) {
  const double r = 2.5;
  const Sphere s = make<Sphere>(SphereParams{{1, 2, 3}, r, {0, 0, 1}, Vec3{1, 0, 0}});
  for (double sign : {1.0, -1.0}) {
    const Vec3 pole = s.center + Vec3{0, 0, sign * r};
    const UvJacobian j = inverse_map_jacobian(s, pole);
    EXPECT_FALSE(j.u_defined);
    EXPECT_FALSE(j.v_defined);
    EXPECT_EQ(j.du, Vec3{});
    EXPECT_EQ(j.dv, Vec3{});
    EXPECT_NEAR(j.v_rate, 1 / (kPi * r), 1e-15);
    // The rate in every direction along the surface: v moves by d / (pi r).
    const double v0 = s.inverse_map(pole).uv.v;
    for (double u : {0.0, 0.3, 0.71}) {
      const double d = 1e-4;  // arc length from the pole
      const double v = sign > 0 ? 1 - d / (kPi * r) : d / (kPi * r);
      const Vec3 q = s.forward_map({u, v});
      EXPECT_NEAR(std::abs(s.inverse_map(q).uv.v - v0) / d, j.v_rate, 1e-9);
    }
    // Near the pole |grad u| = 1 / (2 pi distance from the axis): unbounded.
    const Vec3 near = pole + Vec3{1e-6, 0, 0};
    EXPECT_NEAR(length(inverse_map_jacobian(s, near).du), 1 / (2 * kPi * 1e-6), 1e-3);
  }
  const UvJacobian centre = inverse_map_jacobian(s, s.center);
  EXPECT_FALSE(centre.u_defined || centre.v_defined);
  EXPECT_EQ(centre.v_rate, 0);
}

TEST(Derivatives, AxisLimitsOfCylinderConeDisk) {
  const Cylinder cyl = make<Cylinder>(CylinderParams{{0, 0, 0}, {0, 0, 1}, Vec3{1, 0, 0}, 1, 4});
  const UvJacobian jc = inverse_map_jacobian(cyl, {0, 0, 1});
  EXPECT_FALSE(jc.u_defined);
  EXPECT_TRUE(jc.v_defined);  // v = z / 4 is smooth on the axis
  EXPECT_NEAR(length(jc.dv - Vec3{0, 0, 0.25}), 0, 1e-15);

  // Cone, radius 3, height 4 (slant 5): along the surface v = 1 - d / 5.
  const Cone cone = make<Cone>(ConeParams{{0, 0, 0}, {0, 0, 1}, Vec3{1, 0, 0}, 4, 3});
  const UvJacobian apex = inverse_map_jacobian(cone, {0, 0, 0});
  EXPECT_FALSE(apex.u_defined || apex.v_defined);
  EXPECT_NEAR(apex.v_rate, 0.2, 1e-15);
  const double d = 1e-5;
  EXPECT_NEAR((1 - cone.inverse_map(cone.forward_map({0.4, 1 - d / 5})).uv.v) / d, 0.2, 1e-9);
  const UvJacobian below =
      inverse_map_jacobian(cone, {0, 0, -1});  // axis, not the apex: no mapping
  EXPECT_EQ(cone.inverse_map({0, 0, -1}).status, MapStatus::kUndefined);
  EXPECT_FALSE(below.u_defined || below.v_defined);
  EXPECT_EQ(below.v_rate, 0);

  const Disk disk = make<Disk>(DiskParams{{0, 0, 0}, {0, 0, 1}, Vec3{1, 0, 0}, 2});
  const UvJacobian centre = inverse_map_jacobian(disk, {0, 0, 0.5});
  EXPECT_FALSE(centre.u_defined || centre.v_defined);
  EXPECT_NEAR(centre.v_rate, 0.5, 1e-15);
  EXPECT_NEAR(disk.inverse_map({0, -1e-4, 0}).uv.v / 1e-4, 0.5, 1e-9);
}

TEST(Derivatives, NonFinitePointHasNone) {
  const double nan = std::nan("");
  const Plane pl = make<Plane>(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const UvJacobian j = inverse_map_jacobian(Proxy{pl}, {nan, 0, 0});
  EXPECT_FALSE(j.u_defined || j.v_defined);
}

}  // namespace
}  // namespace texbake
