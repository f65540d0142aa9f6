// The proxy parameter tables (mapping/proxy_schema.h): every kind's keys,
// flags, types, roles and required fields written out here by hand from
// SPEC sections 2 and 5, and the conversions between specs and params.
#include "mapping/proxy_schema.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "tests/mapping/expect_same_params.h"

namespace texbake {
namespace {

using T = ParamType;
using R = ParamRole;
using Corners = std::array<Vec3, 4>;

struct FieldByHand {
  const char* key;
  const char* flag;
  ParamType type;
  ParamRole role;
  bool required;
};

// SPEC section 2's keys in its order ({center, radius, pole, equator}, ...),
// section 5's flags; required = what a proxy without a fit needs (directions
// default to --up, the equator to mapping/proxy.h's rule).
std::vector<FieldByHand> spec_table(ProxyKind kind) {
  switch (kind) {
    case ProxyKind::kSphere:
      return {{"center", "--center", T::kVec3, R::kAnchor, true},
              {"radius", "--radius", T::kNumber, R::kExtent, true},
              {"pole", "--pole", T::kVec3, R::kDirection, false},
              {"equator", "--equator", T::kVec3, R::kEquator, false}};
    case ProxyKind::kCylinder:
      return {{"base", "--base", T::kVec3, R::kAnchor, true},
              {"axis", "--axis", T::kVec3, R::kAxis, false},
              {"equator", "--equator", T::kVec3, R::kEquator, false},
              {"radius", "--radius", T::kNumber, R::kExtent, true},
              {"height", "--height", T::kNumber, R::kExtent, true}};
    case ProxyKind::kCone:
      return {{"apex", "--apex", T::kVec3, R::kAnchor, true},
              {"axis", "--axis", T::kVec3, R::kAxis, false},
              {"equator", "--equator", T::kVec3, R::kEquator, false},
              {"height", "--height", T::kNumber, R::kConeHeight, true},
              {"radius", "--radius", T::kNumber, R::kExtent, true}};
    case ProxyKind::kDisk:
      return {{"center", "--center", T::kVec3, R::kAnchor, true},
              {"normal", "--normal", T::kVec3, R::kDirection, false},
              {"equator", "--equator", T::kVec3, R::kEquator, false},
              {"radius", "--radius", T::kNumber, R::kExtent, true}};
    case ProxyKind::kQuad:
      return {{"corners", "--corners", T::kCorners, R::kExtent, true}};
    case ProxyKind::kPlane:
      return {{"origin", "--origin", T::kVec3, R::kAnchor, true},
              {"u_axis", "--u-axis", T::kVec3, R::kExtent, true},
              {"v_axis", "--v-axis", T::kVec3, R::kExtent, true}};
  }
  return {};
}

constexpr ProxyKind kKinds[] = {ProxyKind::kSphere, ProxyKind::kCylinder, ProxyKind::kCone,
                                ProxyKind::kDisk,   ProxyKind::kQuad,     ProxyKind::kPlane};

TEST(ProxySchema, EveryKindsTableIsTheSpecs) {
  for (ProxyKind kind : kKinds) {
    SCOPED_TRACE(to_string(kind));
    const std::vector<FieldByHand> want = spec_table(kind);
    const std::span<const ParamField> got = proxy_fields(kind);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
      SCOPED_TRACE(want[i].key);
      EXPECT_EQ(got[i].key, want[i].key);
      EXPECT_EQ(got[i].flag, want[i].flag);
      EXPECT_EQ(got[i].type, want[i].type);
      EXPECT_EQ(got[i].role, want[i].role);
      EXPECT_EQ(got[i].required, want[i].required);
      EXPECT_FALSE(got[i].help.empty());
      EXPECT_EQ(find_field(kind, want[i].key), &got[i]);
    }
  }
  EXPECT_EQ(find_field(ProxyKind::kSphere, "apex"), nullptr);
  EXPECT_EQ(find_field(ProxyKind::kPlane, "u-axis"), nullptr);  // the flag's spelling
}

TEST(ProxySchema, GeometryParamsAreEveryFlagOnceInTheHelpOrder) {
  // The order `texbake bake --help` lists them in.
  const std::vector<std::string> want = {
      "--center", "--pole",   "--equator", "--axis",   "--apex",   "--base",   "--normal",
      "--origin", "--u-axis", "--v-axis",  "--radius", "--height", "--corners"};
  const std::span<const GeometryParam> params = geometry_params();
  ASSERT_EQ(params.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(params[i].flag, want[i]);
  EXPECT_EQ(params[0].help, "sphere/disk centre");
  EXPECT_EQ(params[11].help, "cylinder height, cone height (apex to base plane)");
  // A field of any kind is its parameter: same key, flag, type and help.
  for (ProxyKind kind : kKinds) {
    for (const ParamField& f : proxy_fields(kind)) {
      int matches = 0;
      for (const GeometryParam& p : params) {
        if (p.key != f.key) continue;
        ++matches;
        EXPECT_EQ(p.flag, f.flag);
        EXPECT_EQ(p.type, f.type);
        EXPECT_EQ(p.help, f.help);
      }
      EXPECT_EQ(matches, 1) << f.key;
    }
  }
}

TEST(ProxySchema, MissingFieldsPerKind) {
  const std::pair<ProxyKind, std::vector<std::string>> want[] = {
      {ProxyKind::kSphere, {"center", "radius"}},
      {ProxyKind::kCylinder, {"base", "radius", "height"}},
      {ProxyKind::kCone, {"apex", "height", "radius"}},
      {ProxyKind::kDisk, {"center", "radius"}},
      {ProxyKind::kQuad, {"corners"}},
      {ProxyKind::kPlane, {"origin", "u_axis", "v_axis"}}};
  for (const auto& [kind, keys] : want) {
    EXPECT_EQ(missing_fields(ProxySpec{kind, {}, std::nullopt}), keys) << to_string(kind);
  }
  // Given values and optional fields do not count; foreign keys are ignored.
  ProxySpec cone{ProxyKind::kCone, {{"height", 2.0}, {"axis", Vec3{0, 0, 1}}}, std::nullopt};
  EXPECT_EQ(missing_fields(cone), (std::vector<std::string>{"apex", "radius"}));
  ProxySpec disk{
      ProxyKind::kDisk, {{"center", Vec3{}}, {"radius", 1.0}, {"apex", Vec3{}}}, std::nullopt};
  EXPECT_TRUE(missing_fields(disk).empty());
}

using testing_params::expect_same_params;

// One params value of every kind, every member distinct (equator set on
// half of them).
std::vector<ProxyParams> samples() {
  return {SphereParams{{1, 2, 3}, 4, {0, 1, 0}, Vec3{1, 0, 0}},
          CylinderParams{{1, 2, 3}, {0, 0, 2}, std::nullopt, 0.5, 7},
          ConeParams{{-1, 0, 5}, {0, 0, 1}, Vec3{0, 1, 0}, 3, 1.5},
          DiskParams{{0, 0, 1}, {1, 1, 0}, std::nullopt, 2},
          QuadParams{{Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 2, 0}, Vec3{0, 2, 0}}},
          PlaneParams{{1, 1, 1}, {2, 0, 0}, {0, 3, 0}}};
}

TEST(ProxySchema, SpecFromParamsGivesEveryFieldByKey) {
  const ProxySpec sphere = spec_from_params(samples()[0]);
  EXPECT_EQ(sphere.kind, ProxyKind::kSphere);
  EXPECT_FALSE(sphere.up.has_value());
  ASSERT_EQ(sphere.values.size(), 4u);
  EXPECT_EQ(std::get<Vec3>(sphere.values.at("center")), (Vec3{1, 2, 3}));
  EXPECT_EQ(std::get<double>(sphere.values.at("radius")), 4);
  EXPECT_EQ(std::get<Vec3>(sphere.values.at("pole")), (Vec3{0, 1, 0}));
  EXPECT_EQ(std::get<Vec3>(sphere.values.at("equator")), (Vec3{1, 0, 0}));
  // An absent equator is not a value.
  const ProxySpec cylinder = spec_from_params(samples()[1]);
  EXPECT_EQ(cylinder.values.size(), 4u);
  EXPECT_FALSE(cylinder.values.contains("equator"));
  EXPECT_EQ(std::get<double>(cylinder.values.at("height")), 7);
  const ProxySpec cone = spec_from_params(samples()[2]);
  EXPECT_EQ(std::get<double>(cone.values.at("height")), 3);
  EXPECT_EQ(std::get<double>(cone.values.at("radius")), 1.5);
  const ProxySpec quad = spec_from_params(samples()[4]);
  EXPECT_EQ(std::get<Corners>(quad.values.at("corners"))[2], (Vec3{4, 2, 0}));
  const ProxySpec plane = spec_from_params(samples()[5]);
  EXPECT_EQ(std::get<Vec3>(plane.values.at("u_axis")), (Vec3{2, 0, 0}));
  EXPECT_EQ(std::get<Vec3>(plane.values.at("v_axis")), (Vec3{0, 3, 0}));
}

TEST(ProxySchema, ParamsFromSpecInvertsSpecFromParams) {
  for (const ProxyParams& p : samples()) {
    SCOPED_TRACE(to_string(kind_of(p)));
    const ProxySpec spec = spec_from_params(p);
    EXPECT_EQ(spec.kind, kind_of(p));
    Expected<ProxyParams> back = params_from_spec(spec);
    ASSERT_TRUE(back) << back.error().message;
    expect_same_params(*back, p);
  }
}

TEST(ProxySchema, DirectionsDefaultToUpAndTheEquatorStaysAbsent) {
  ProxySpec sphere{ProxyKind::kSphere, {{"center", Vec3{}}, {"radius", 1.0}}, std::nullopt};
  Expected<ProxyParams> p = params_from_spec(sphere);
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ(std::get<SphereParams>(*p).pole, (Vec3{0, 0, 1}));  // +Z without up
  EXPECT_FALSE(std::get<SphereParams>(*p).equator.has_value());
  const ProxySpec disk{ProxyKind::kDisk, {{"center", Vec3{}}, {"radius", 1.0}}, Vec3{-1, 0, 0}};
  EXPECT_EQ(std::get<DiskParams>(*params_from_spec(disk)).normal, (Vec3{-1, 0, 0}));
  // A given direction wins over up.
  const ProxySpec cone{
      ProxyKind::kCone,
      {{"apex", Vec3{}}, {"height", 1.0}, {"radius", 1.0}, {"axis", Vec3{0, 2, 0}}},
      Vec3{1, 0, 0}};
  EXPECT_EQ(std::get<ConeParams>(*params_from_spec(cone)).axis, (Vec3{0, 2, 0}));
  // A zero up used as the default is named.
  const ProxySpec zero_up{ProxyKind::kDisk, {{"center", Vec3{}}, {"radius", 1.0}}, Vec3{}};
  Expected<ProxyParams> bad = params_from_spec(zero_up, ParamNaming::kFlag);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "disk: --up is the zero vector");
}

// Expects `s` to fail with kInvalidArgument and exactly this message.
template <class E>
void expect_error(const E& e, const std::string& message) {
  ASSERT_FALSE(e.has_value());
  EXPECT_EQ(e.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(e.error().message, message);
}

TEST(ProxySchema, BadSpecsNameTheKeyOrTheFlag) {
  const ProxySpec partial{ProxyKind::kCylinder, {{"radius", 2.0}}, std::nullopt};
  expect_error(params_from_spec(partial), "cylinder: missing base (needs base, radius, height)");
  expect_error(params_from_spec(partial, ParamNaming::kFlag),
               "cylinder: missing --base (needs --base, --radius, --height)");
  const ProxySpec foreign{ProxyKind::kSphere, {{"apex", Vec3{}}}, std::nullopt};
  expect_error(params_from_spec(foreign),
               "sphere: unknown parameter 'apex' (expected center, radius, pole, equator)");
  expect_error(check_spec_keys(foreign, ParamNaming::kFlag),
               "sphere: unknown parameter --apex (expected --center, --radius, --pole, --equator)");
  const ProxySpec typo{ProxyKind::kDisk, {{"raduis", 1.0}}, std::nullopt};
  expect_error(check_spec_keys(typo),
               "disk: unknown parameter 'raduis' (expected center, normal, equator, radius)");
  const ProxySpec wrong_type{ProxyKind::kQuad, {{"corners", Vec3{}}}, std::nullopt};
  expect_error(params_from_spec(wrong_type), "quad: corners must be four corners x,y,z");
  const ProxySpec number{ProxyKind::kSphere, {{"radius", Vec3{}}}, std::nullopt};
  expect_error(check_spec_keys(number, ParamNaming::kFlag), "sphere: --radius must be a number");
}

TEST(ProxySchema, GivenValuesThatNoFitCanMendAreRejected) {
  const auto spec = [](ProxyKind kind, ParamValues values) {
    return ProxySpec{kind, std::move(values), std::nullopt};
  };
  expect_error(check_given_values(spec(ProxyKind::kCylinder, {{"axis", Vec3{}}})),
               "cylinder: axis is the zero vector");
  expect_error(check_given_values(spec(ProxyKind::kDisk, {{"normal", Vec3{}}}), ParamNaming::kFlag),
               "disk: --normal is the zero vector");
  expect_error(check_given_values(spec(ProxyKind::kSphere, {{"pole", Vec3{}}})),
               "sphere: pole is the zero vector");
  expect_error(check_given_values(spec(ProxyKind::kCone, {{"height", 0.0}}), ParamNaming::kFlag),
               "cone: --height must be a finite number > 0 (got 0)");
  expect_error(check_given_values(spec(ProxyKind::kCylinder, {{"radius", -1.5}})),
               "cylinder: radius must be a finite number > 0 (got -1.5)");
  expect_error(
      check_given_values(spec(ProxyKind::kPlane, {{"v_axis", Vec3{}}}), ParamNaming::kFlag),
      "plane: --v-axis is the zero vector");
  expect_error(check_given_values(spec(ProxyKind::kSphere, {{"equator", Vec3{}}})),
               "sphere: equator is the zero vector");
  const double inf = std::numeric_limits<double>::infinity();
  expect_error(check_given_values(spec(ProxyKind::kSphere, {{"center", Vec3{inf, 0, 0}}})),
               "sphere: center is not finite");
  ProxySpec zero_up = spec(ProxyKind::kCylinder, {});
  zero_up.up = Vec3{};
  expect_error(check_given_values(zero_up), "cylinder: up is the zero vector");
  // Anchors may be anywhere, zero included; a combination is make_proxy's.
  EXPECT_TRUE(check_given_values(spec(ProxyKind::kSphere, {{"center", Vec3{}}})));
  EXPECT_TRUE(check_given_values(
      spec(ProxyKind::kCylinder,
           {{"axis", Vec3{0, 0, 1}}, {"equator", Vec3{0, 0, 1}}, {"height", 2.0}})));
  // The structural checks come first.
  expect_error(check_given_values(spec(ProxyKind::kSphere, {{"height", 0.0}})),
               "sphere: unknown parameter 'height' (expected center, radius, pole, equator)");
}

TEST(ProxySchema, MergeWritesTheGivenValuesOverParams) {
  const ProxySpec given{ProxyKind::kCone, {{"height", 3.0}, {"equator", Vec3{0, 1, 0}}}, Vec3{}};
  const ConeParams fitted{{1, 2, 3}, {0, 0, 1}, std::nullopt, 1.5, 0.5};
  Expected<ProxyParams> merged = merge_spec(given, fitted);
  ASSERT_TRUE(merged) << merged.error().message;
  expect_same_params(*merged,
                     ConeParams{{1, 2, 3}, {0, 0, 1}, Vec3{0, 1, 0}, 3, 0.5});  // up not applied
  expect_error(merge_spec(given, SphereParams{}), "cone: cannot merge into a sphere's values");
}

}  // namespace
}  // namespace texbake
