// Completion of a proxy spec by fitting (bake/fit/complete_proxy.h): which
// given values the fit keeps, fits around or replaces, what `up` fixes, and
// whose fault an error is. Point sets are small and symmetric, so every
// fitted value is worked out by hand in the comments.
#include "bake/fit/complete_proxy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace texbake {
namespace {

// A point cloud (no faces: the fit uses every vertex).
MeshData cloud(const std::vector<Vec3>& points) {
  MeshData mesh;
  for (const Vec3& p : points) {
    mesh.positions.push_back(
        {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
  }
  return mesh;
}

// The six points at distance 1 from (1, 2, 3) along the axes: their minimum
// enclosing sphere is centred there with radius 1.
MeshData octahedron() {
  return cloud({{2, 2, 3}, {0, 2, 3}, {1, 3, 3}, {1, 1, 3}, {1, 2, 4}, {1, 2, 2}});
}

// Two rings of 8 points, radius 1 around the Z axis, at z = 0 and z = 2.
// Covariance eigenvalues: 1 along Z (z = 0 or 2 about 1), 0.5 across, so the
// principal axis is Z: base (0,0,0), axis +Z, radius 1, height 2.
MeshData tin() {
  std::vector<Vec3> points;
  for (double z : {0.0, 2.0}) {
    for (int k = 0; k < 8; ++k) {
      const double a = k * std::numbers::pi / 4;
      points.push_back({std::cos(a), std::sin(a), z});
    }
  }
  return cloud(points);
}

void expect_near(Vec3 got, Vec3 want, double tolerance = 1e-6) {
  EXPECT_LE(length(got - want), tolerance) << got.x << "," << got.y << "," << got.z;
}

ProxySpec spec(ProxyKind kind, ParamValues values = {}, std::optional<Vec3> up = std::nullopt) {
  return ProxySpec{kind, std::move(values), up};
}

TEST(CompleteSpec, ACompleteSpecIsNotFitted) {
  // An empty mesh: it is never looked at.
  Expected<SpecCompletion> done = complete_spec(
      spec(ProxyKind::kSphere, {{"center", Vec3{1, 2, 3}}, {"radius", 2.0}}, Vec3{0, 1, 0}),
      MeshData{});
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_TRUE(done->fitted.empty());
  EXPECT_EQ(done->points, 0u);
  const Sphere& s = std::get<Sphere>(done->proxy);
  EXPECT_EQ(s.center, (Vec3{1, 2, 3}));
  EXPECT_EQ(s.radius, 2);
  EXPECT_EQ(s.frame.axis, (Vec3{0, 1, 0}));  // the pole defaults to up
  // make_proxy's errors, by key.
  Expected<SpecCompletion> bad =
      complete_spec(spec(ProxyKind::kSphere, {{"center", Vec3{}}, {"radius", -1.0}}), MeshData{});
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(bad.error().message, "sphere: radius must be a finite number > 0 (got -1)");
}

TEST(CompleteSpec, NothingGivenFitsEverything) {
  Expected<SpecCompletion> done = complete_spec(spec(ProxyKind::kSphere), octahedron());
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_EQ(done->fitted, (std::vector<std::string>{"center", "radius", "pole", "equator"}));
  EXPECT_EQ(done->points, 6u);
  const Sphere& s = std::get<Sphere>(done->proxy);
  expect_near(s.center, {1, 2, 3});
  EXPECT_NEAR(s.radius, 1, 1e-6);
  EXPECT_EQ(s.frame.axis, (Vec3{0, 0, 1}));  // up's default
}

TEST(CompleteSpec, AGivenAnchorIsKeptAndTheRestFittedAroundIt) {
  // Around the origin the farthest point is (1, 2, 4): radius sqrt(21).
  Expected<SpecCompletion> done =
      complete_spec(spec(ProxyKind::kSphere, {{"center", Vec3{0, 0, 0}}}), octahedron());
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_EQ(done->fitted, (std::vector<std::string>{"radius", "pole", "equator"}));
  const Sphere& s = std::get<Sphere>(done->proxy);
  EXPECT_EQ(s.center, (Vec3{0, 0, 0}));
  EXPECT_NEAR(s.radius, std::sqrt(21.0), 1e-6);
  // A cylinder's base: the axis line passes through (0, 0, -1); the height
  // reaches the top ring from there (3); the radius stays 1.
  done = complete_spec(spec(ProxyKind::kCylinder, {{"base", Vec3{0, 0, -1}}}), tin());
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_EQ(done->fitted, (std::vector<std::string>{"axis", "equator", "radius", "height"}));
  const Cylinder& c = std::get<Cylinder>(done->proxy);
  EXPECT_EQ(c.base, (Vec3{0, 0, -1}));
  expect_near(c.frame.axis, {0, 0, 1});
  EXPECT_NEAR(c.radius, 1, 1e-6);
  EXPECT_NEAR(c.height, 3, 1e-6);
}

TEST(CompleteSpec, AGivenExtentReplacesTheFittedValue) {
  Expected<SpecCompletion> done =
      complete_spec(spec(ProxyKind::kSphere, {{"radius", 5.0}}), octahedron());
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_EQ(done->fitted, (std::vector<std::string>{"center", "pole", "equator"}));
  const Sphere& s = std::get<Sphere>(done->proxy);
  expect_near(s.center, {1, 2, 3});  // fitted as without the radius
  EXPECT_EQ(s.radius, 5);
}

TEST(CompleteSpec, AGivenDirectionKeepsItsSign) {
  // The ring z = 0 as a disk seen from below: the fit would point the normal
  // up (+Z); the given -Z stays.
  Expected<SpecCompletion> done =
      complete_spec(spec(ProxyKind::kDisk, {{"normal", Vec3{0, 0, -3}}}),
                    cloud({{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}}));
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_EQ(done->fitted, (std::vector<std::string>{"center", "equator", "radius"}));
  const Disk& d = std::get<Disk>(done->proxy);
  EXPECT_EQ(d.frame.axis, (Vec3{0, 0, -1}));
  expect_near(d.center, {0, 0, 0});
  EXPECT_NEAR(d.radius, 1, 1e-6);
}

TEST(CompleteSpec, UpFixesACylindersAxisLine) {
  // Along X instead of the principal Z: the points projected on the YZ plane
  // are (y, 0) and (y, 2) with |y| <= 1, whose enclosing circle has centre
  // (y, z) = (0, 1) and radius sqrt(2) (it passes through (+-1, 0) and
  // (+-1, 2)); the points span x in [-1, 1]: base (-1, 0, 1), height 2.
  Expected<SpecCompletion> done =
      complete_spec(spec(ProxyKind::kCylinder, {}, Vec3{1, 0, 0}), tin());
  ASSERT_TRUE(done) << done.error().message;
  const Cylinder& c = std::get<Cylinder>(done->proxy);
  expect_near(c.frame.axis, {1, 0, 0});
  expect_near(c.base, {-1, 0, 1});
  EXPECT_NEAR(c.radius, std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(c.height, 2, 1e-6);
  // Without up: the principal axis.
  done = complete_spec(spec(ProxyKind::kCylinder), tin());
  ASSERT_TRUE(done) << done.error().message;
  expect_near(std::get<Cylinder>(done->proxy).frame.axis, {0, 0, 1});
  expect_near(std::get<Cylinder>(done->proxy).base, {0, 0, 0});
}

TEST(CompleteSpec, FitOptionsFollowTheRoles) {
  FitOptions o = fit_options(spec(ProxyKind::kCylinder, {}, Vec3{1, 0, 0}));
  EXPECT_EQ(o.up, (Vec3{1, 0, 0}));
  ASSERT_TRUE(o.axis.has_value());
  EXPECT_EQ(*o.axis, (Vec3{1, 0, 0}));
  EXPECT_FALSE(o.keep_axis_sign);  // only the line: the sign is fitted
  EXPECT_FALSE(o.anchor.has_value());
  o = fit_options(
      spec(ProxyKind::kCone,
           {{"axis", Vec3{0, -2, 0}}, {"apex", Vec3{1, 1, 1}}, {"height", 4.0}, {"radius", 9.0}},
           Vec3{1, 0, 0}));
  EXPECT_EQ(*o.axis, (Vec3{0, -2, 0}));
  EXPECT_TRUE(o.keep_axis_sign);
  EXPECT_EQ(*o.anchor, (Vec3{1, 1, 1}));
  EXPECT_EQ(*o.height, 4);
  // Up is a sphere's pole and a disk's hemisphere through FitOptions::up,
  // not a fixed axis.
  o = fit_options(spec(ProxyKind::kSphere, {{"center", Vec3{0, 0, 5}}}, Vec3{0, -1, 0}));
  EXPECT_FALSE(o.axis.has_value());
  EXPECT_EQ(o.up, (Vec3{0, -1, 0}));
  EXPECT_EQ(*o.anchor, (Vec3{0, 0, 5}));
  o = fit_options(spec(ProxyKind::kDisk, {}, Vec3{0, -1, 0}));
  EXPECT_FALSE(o.axis.has_value());
  o = fit_options(spec(ProxyKind::kPlane, {{"origin", Vec3{1, 2, 3}}, {"u_axis", Vec3{1, 0, 0}}}));
  EXPECT_EQ(*o.anchor, (Vec3{1, 2, 3}));
  EXPECT_FALSE(o.axis.has_value());
  EXPECT_EQ(o.up, (Vec3{0, 0, 1}));
  // A cylinder's height is an extent, not passed to the fit.
  o = fit_options(spec(ProxyKind::kCylinder, {{"height", 4.0}}));
  EXPECT_FALSE(o.height.has_value());
}

TEST(CompleteSpec, BadGivenValuesAreTheCallersFaultBeforeTheMesh) {
  // An empty mesh: a fit would fail (kParse); the value is checked first.
  const std::pair<ProxySpec, const char*> cases[] = {
      {spec(ProxyKind::kCylinder, {{"axis", Vec3{}}}), "cylinder: axis is the zero vector"},
      {spec(ProxyKind::kDisk, {{"normal", Vec3{}}}), "disk: normal is the zero vector"},
      {spec(ProxyKind::kCone, {{"height", 0.0}}),
       "cone: height must be a finite number > 0 (got 0)"},
      {spec(ProxyKind::kSphere, {{"radius", -2.0}}),
       "sphere: radius must be a finite number > 0 (got -2)"},
      {spec(ProxyKind::kCone, {{"center", Vec3{}}}),
       "cone: unknown parameter 'center' (expected apex, axis, equator, height, radius)"},
  };
  for (const auto& [s, message] : cases) {
    Expected<SpecCompletion> done = complete_spec(s, MeshData{});
    ASSERT_FALSE(done) << message;
    EXPECT_EQ(done.error().code, ErrorCode::kInvalidArgument);
    EXPECT_EQ(done.error().message, message);
  }
  // Flags when asked.
  Expected<SpecCompletion> flag =
      complete_spec(spec(ProxyKind::kCone, {{"axis", Vec3{}}}), MeshData{}, ParamNaming::kFlag);
  ASSERT_FALSE(flag);
  EXPECT_EQ(flag.error().message, "cone: --axis is the zero vector");
}

TEST(CompleteSpec, AMeshThatCannotBeFittedIsAParseError) {
  // The flat square has no extent along +Z.
  Expected<SpecCompletion> done =
      complete_spec(spec(ProxyKind::kCylinder, {}, Vec3{0, 0, 1}),
                    cloud({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
  ASSERT_FALSE(done);
  EXPECT_EQ(done.error().code, ErrorCode::kParse);
  EXPECT_NE(done.error().message.find("no extent along the axis"), std::string::npos)
      << done.error().message;
  done = complete_spec(spec(ProxyKind::kSphere), MeshData{});
  ASSERT_FALSE(done);
  EXPECT_EQ(done.error().code, ErrorCode::kParse);
}

TEST(CompleteSpec, AGivenValueThatContradictsTheFitIsNamed) {
  // The equator along the fitted axis (+Z).
  Expected<SpecCompletion> done =
      complete_spec(spec(ProxyKind::kCylinder, {{"equator", Vec3{0, 0, 2}}}), tin());
  ASSERT_FALSE(done);
  EXPECT_EQ(done.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(done.error().message,
            "the fitted cylinder with the given values is invalid: cylinder: equator is parallel "
            "to axis");
}

}  // namespace
}  // namespace texbake
