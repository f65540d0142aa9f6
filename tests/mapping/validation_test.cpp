// make_proxy's validation (SPEC section 1): bad parameters are errors that
// name the parameter, never silently fixed; absent equators get the default.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "mapping/proxy.h"

namespace texbake {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Expects make_proxy to fail with kInvalidArgument and a message containing
// every one of `words`.
void expect_rejected(const ProxyParams& params, std::initializer_list<const char*> words,
                     ParamNaming naming = ParamNaming::kKey) {
  Expected<Proxy> p = make_proxy(params, naming);
  ASSERT_FALSE(p.has_value());
  EXPECT_EQ(p.error().code, ErrorCode::kInvalidArgument);
  for (const char* w : words) {
    EXPECT_NE(p.error().message.find(w), std::string::npos)
        << "message \"" << p.error().message << "\" lacks \"" << w << "\"";
  }
}

TEST(Validation, ZeroVectors) {
  expect_rejected(SphereParams{{0, 0, 0}, 1, {0, 0, 0}, std::nullopt}, {"sphere", "pole", "zero"});
  expect_rejected(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{0, 0, 0}}, {"equator", "zero"});
  expect_rejected(CylinderParams{{0, 0, 0}, {0, 0, 0}, std::nullopt, 1, 1}, {"cylinder", "axis"});
  expect_rejected(ConeParams{{0, 0, 0}, {0, 0, 0}, std::nullopt, 1, 1}, {"cone", "axis", "zero"});
  expect_rejected(DiskParams{{0, 0, 0}, {0, 0, 0}, std::nullopt, 1}, {"disk", "normal", "zero"});
  expect_rejected(PlaneParams{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}}, {"plane", "u_axis", "zero"});
  expect_rejected(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 0, 0}}, {"--v-axis", "zero"},
                  ParamNaming::kFlag);
}

TEST(Validation, EquatorParallelToPole) {
  expect_rejected(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{0, 0, 5}},
                  {"equator", "parallel", "pole"});
  expect_rejected(SphereParams{{0, 0, 0}, 1, {1, 2, 3}, Vec3{-2, -4, -6}}, {"equator", "parallel"});
  expect_rejected(CylinderParams{{0, 0, 0}, {0, 1, 0}, Vec3{0, -1, 0}, 1, 1},
                  {"--equator", "parallel", "--axis"}, ParamNaming::kFlag);
  expect_rejected(DiskParams{{0, 0, 0}, {1, 0, 0}, Vec3{3, 0, 0}, 1}, {"parallel", "normal"});
  expect_rejected(PlaneParams{{0, 0, 0}, {1, 1, 0}, {2, 2, 0}}, {"v_axis", "parallel", "u_axis"});
}

TEST(Validation, NonPositiveRadiusOrHeight) {
  expect_rejected(SphereParams{{0, 0, 0}, 0, {0, 0, 1}, std::nullopt}, {"radius", "> 0"});
  expect_rejected(SphereParams{{0, 0, 0}, -1, {0, 0, 1}, std::nullopt}, {"radius", "-1"});
  expect_rejected(CylinderParams{{0, 0, 0}, {0, 0, 1}, std::nullopt, 1, 0}, {"height"});
  expect_rejected(CylinderParams{{0, 0, 0}, {0, 0, 1}, std::nullopt, -2, 1}, {"radius"});
  expect_rejected(ConeParams{{0, 0, 0}, {0, 0, 1}, std::nullopt, -1, 1}, {"cone", "height"});
  expect_rejected(ConeParams{{0, 0, 0}, {0, 0, 1}, std::nullopt, 1, 0}, {"cone", "radius"});
  expect_rejected(DiskParams{{0, 0, 0}, {0, 0, 1}, std::nullopt, -0.5}, {"disk", "radius"});
}

TEST(Validation, NaNAndInfinity) {
  expect_rejected(SphereParams{{kNaN, 0, 0}, 1, {0, 0, 1}, std::nullopt}, {"center", "finite"});
  expect_rejected(SphereParams{{0, 0, 0}, kInf, {0, 0, 1}, std::nullopt}, {"radius", "inf"});
  expect_rejected(SphereParams{{0, 0, 0}, kNaN, {0, 0, 1}, std::nullopt}, {"radius", "nan"});
  expect_rejected(SphereParams{{0, 0, 0}, 1, {0, kInf, 1}, std::nullopt}, {"pole", "finite"});
  expect_rejected(CylinderParams{{0, 0, 0}, {0, 0, 1}, Vec3{kNaN, 1, 0}, 1, 1},
                  {"equator", "finite"});
  expect_rejected(ConeParams{{0, -kInf, 0}, {0, 0, 1}, std::nullopt, 1, 1}, {"apex"});
  expect_rejected(DiskParams{{0, 0, 0}, {0, 0, 1}, std::nullopt, kNaN}, {"radius"});
  expect_rejected(PlaneParams{{0, 0, kNaN}, {1, 0, 0}, {0, 1, 0}}, {"origin"});
  expect_rejected(QuadParams{{{{0, 0, 0}, {1, 0, 0}, {1, kInf, 0}, {0, 1, 0}}}},
                  {"corners", "finite"});
}

TEST(Validation, DefaultEquatorIsFirstOfXYZNotParallelMadePerpendicular) {
  const auto frame_of = [](Vec3 pole) {
    Expected<Proxy> p = make_proxy(SphereParams{{0, 0, 0}, 1, pole, std::nullopt});
    EXPECT_TRUE(p.has_value());
    return std::get<Sphere>(*p).frame;
  };
  Frame f = frame_of({0, 0, 3});
  EXPECT_EQ(f.equator, (Vec3{1, 0, 0}));
  EXPECT_EQ(f.east, (Vec3{0, 1, 0}));
  f = frame_of({-2, 0, 0});  // +X is parallel: +Y
  EXPECT_EQ(f.equator, (Vec3{0, 1, 0}));
  // Pole (1,1,0)/sqrt2: X minus its pole component is (0.5,-0.5,0), unit (1,-1,0)/sqrt2.
  f = frame_of({1, 1, 0});
  EXPECT_NEAR(f.equator.x, 1 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(f.equator.y, -1 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(f.equator.z, 0, 1e-15);
}

TEST(Validation, GivenEquatorIsNormalisedAndMadePerpendicular) {
  // Equator (1,0,1) with pole +z: Gram-Schmidt leaves (1,0,0).
  Expected<Proxy> p = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 2}, Vec3{1, 0, 1}});
  ASSERT_TRUE(p.has_value());
  const Frame& f = std::get<Sphere>(*p).frame;
  EXPECT_NEAR(f.equator.x, 1, 1e-15);
  EXPECT_NEAR(f.equator.z, 0, 1e-15);
  EXPECT_NEAR(f.axis.z, 1, 1e-15);
  // Nearly parallel (1e-7 rad) is still a valid, exactly orthonormal frame.
  Expected<Proxy> q = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, Vec3{1e-7, 0, 1}});
  ASSERT_TRUE(q.has_value());
  const Frame& g = std::get<Sphere>(*q).frame;
  EXPECT_NEAR(dot(g.axis, g.equator), 0, 1e-15);
  EXPECT_NEAR(length(g.equator), 1, 1e-15);
  EXPECT_NEAR(g.equator.x, 1, 1e-15);
}

TEST(Validation, HugeAndTinyVectorsNormaliseWithoutOverflow) {
  Expected<Proxy> p =
      make_proxy(CylinderParams{{0, 0, 0}, {0, 0, 1e300}, Vec3{1e-300, 0, 0}, 1, 1});
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(std::get<Cylinder>(*p).frame.axis, (Vec3{0, 0, 1}));
  EXPECT_EQ(std::get<Cylinder>(*p).frame.equator, (Vec3{1, 0, 0}));
}

TEST(Validation, ParamsOfRebuildsTheSameProxy) {
  Expected<Proxy> p = make_proxy(ConeParams{{1, 2, 3}, {0, 0, 2}, std::nullopt, 4, 5});
  ASSERT_TRUE(p.has_value());
  const ConeParams back = std::get<ConeParams>(params_of(*p));
  EXPECT_EQ(back.axis, (Vec3{0, 0, 1}));
  ASSERT_TRUE(back.equator.has_value());
  EXPECT_EQ(*back.equator, (Vec3{1, 0, 0}));
  EXPECT_EQ(back.height, 4);
  EXPECT_EQ(back.radius, 5);
  EXPECT_EQ(kind_of(params_of(*p)), ProxyKind::kCone);
}

TEST(ProxyKindNames, RoundTripAndRejectUnknown) {
  for (ProxyKind k : {ProxyKind::kSphere, ProxyKind::kCylinder, ProxyKind::kCone, ProxyKind::kDisk,
                      ProxyKind::kQuad, ProxyKind::kPlane}) {
    EXPECT_EQ(parse_proxy_kind(to_string(k)), k);
  }
  EXPECT_EQ(std::string(to_string(ProxyKind::kCylinder)), "cylinder");
  EXPECT_FALSE(parse_proxy_kind("torus").has_value());
  EXPECT_FALSE(parse_proxy_kind("Sphere").has_value());
  EXPECT_FALSE(parse_proxy_kind("").has_value());
}

}  // namespace
}  // namespace texbake
