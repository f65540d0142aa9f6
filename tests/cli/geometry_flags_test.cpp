// The shared geometry flags (bake/cli/geometry_flags.h) as a library: parsing
// into GeometryFlags, the checks, params_from_flags and merge_flags (the
// interface bake, fit and render reuse).
#include "bake/cli/geometry_flags.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace texbake::cli {
namespace {

// Parses `args` (after the program name) into fresh flags.
GeometryFlags parse(std::vector<std::string> args) {
  CLI::App app;
  GeometryFlags flags;
  add_geometry_flags(app, flags);
  std::reverse(args.begin(), args.end());  // CLI11 takes them reversed
  app.parse(args);
  return flags;
}

// The value of the given flag with this parameter key.
template <class T>
T given(const GeometryFlags& flags, const std::string& key) {
  return std::get<T>(flags.values.at(key));
}

TEST(GeometryFlags, ParsesVectorsNumbersCornersAndUp) {
  const GeometryFlags f =
      parse({"--proxy", "quad", "--corners", "0,0,0; 4,0,0 ;4,2,0;0,2,-1e-3", "--up", "-y"});
  ASSERT_TRUE(f.kind.has_value());
  EXPECT_EQ(*f.kind, ProxyKind::kQuad);
  ASSERT_TRUE(f.values.contains("corners"));
  using Corners = std::array<Vec3, 4>;
  EXPECT_EQ(given<Corners>(f, "corners")[1], (Vec3{4, 0, 0}));
  EXPECT_EQ(given<Corners>(f, "corners")[3], (Vec3{0, 2, -1e-3}));
  EXPECT_EQ(up_direction(f), (Vec3{0, -1, 0}));
  const GeometryFlags g = parse({"--center", "+1.5,-2,3e2", "--radius", "0.25"});
  EXPECT_EQ(given<Vec3>(g, "center"), (Vec3{1.5, -2, 300}));
  EXPECT_EQ(given<double>(g, "radius"), 0.25);
  EXPECT_EQ(up_direction(g), (Vec3{0, 0, 1}));
}

TEST(GeometryFlags, RejectsGarbageNamingTheFlag) {
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"--center", "1,2"},
                                             {"--center", "1,2,3,4"},
                                             {"--center", "1,,3"},
                                             {"--center", "1,2,nan"},
                                             {"--center", "1,2,-inf"},
                                             {"--center", "1,2,3x"},
                                             {"--radius", ""},
                                             {"--radius", "1e400"},
                                             {"--corners", "0,0,0;1,0,0;1,1,0"},
                                             {"--up", "up"},
                                             {"--proxy", "Sphere"}}) {
    try {
      parse(args);
      ADD_FAILURE() << args[0] << " " << args[1] << " was accepted";
    } catch (const CLI::ValidationError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(args[0] + ":", 0), 0u) << e.what();
    }
  }
}

TEST(GeometryFlags, ParamsFromFlagsNamesTheFirstMissingFlag) {
  GeometryFlags f = parse({"--proxy", "cylinder", "--radius", "2"});
  EXPECT_EQ(missing_geometry_flags(f, ProxyKind::kCylinder),
            (std::vector<std::string>{"--base", "--height"}));
  Expected<ProxyParams> p = params_from_flags(f, ProxyKind::kCylinder);
  ASSERT_FALSE(p.has_value());
  EXPECT_EQ(p.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(p.error().message.find("missing --base"), std::string::npos) << p.error().message;
}

TEST(GeometryFlags, UpIsTheDefaultAxis) {
  const GeometryFlags f =
      parse({"--proxy", "disk", "--center", "0,0,0", "--radius", "1", "--up", "x"});
  Expected<ProxyParams> p = params_from_flags(f, ProxyKind::kDisk);
  ASSERT_TRUE(p.has_value()) << p.error().message;
  EXPECT_EQ(std::get<DiskParams>(*p).normal, (Vec3{1, 0, 0}));
  EXPECT_FALSE(std::get<DiskParams>(*p).equator.has_value());
  // An explicit --normal wins over --up.
  const GeometryFlags g = parse(
      {"--proxy", "disk", "--center", "0,0,0", "--radius", "1", "--up", "x", "--normal", "0,1,0"});
  EXPECT_EQ(std::get<DiskParams>(*params_from_flags(g, ProxyKind::kDisk)).normal, (Vec3{0, 1, 0}));
}

TEST(GeometryFlags, MergeWritesGivenFlagsOverAFit) {
  const GeometryFlags f = parse({"--proxy", "cone", "--height", "3", "--equator", "0,1,0"});
  const ConeParams fitted{{1, 2, 3}, {0, 0, 1}, std::nullopt, 1.5, 0.5};
  Expected<ProxyParams> merged = merge_flags(f, fitted);
  ASSERT_TRUE(merged.has_value());
  const ConeParams& c = std::get<ConeParams>(*merged);
  EXPECT_EQ(c.apex, (Vec3{1, 2, 3}));  // fitted
  EXPECT_EQ(c.height, 3);              // given
  EXPECT_EQ(c.radius, 0.5);            // fitted
  EXPECT_EQ(*c.equator, (Vec3{0, 1, 0}));
  EXPECT_FALSE(merge_flags(f, SphereParams{}).has_value());  // kind mismatch
}

TEST(GeometryFlags, ChecksTheCombination) {
  EXPECT_TRUE(check_geometry_flags(parse({"--proxy", "sphere", "--center", "0,0,0"}), true));
  const Status foreign =
      check_geometry_flags(parse({"--proxy", "sphere", "--apex", "0,0,0"}), true);
  ASSERT_FALSE(foreign);
  EXPECT_NE(foreign.error().message.find("--apex does not apply to --proxy sphere"),
            std::string::npos);
  const Status with_file =
      check_geometry_flags(parse({"--proxy-file", "p.json", "--radius", "1"}), true);
  ASSERT_FALSE(with_file);
  EXPECT_NE(with_file.error().message.find("--radius"), std::string::npos);
  EXPECT_FALSE(check_geometry_flags(parse({}), true));
  EXPECT_TRUE(check_geometry_flags(parse({}), false));
  EXPECT_FALSE(check_geometry_flags(parse({"--radius", "1"}), false));  // needs --proxy
  EXPECT_THROW(parse({"--proxy", "sphere", "--proxy-file", "p.json"}), CLI::ParseError);
  EXPECT_EQ(
      given_geometry_flags(parse({"--proxy", "plane", "--v-axis", "0,1,0", "--origin", "1,1,1"})),
      (std::vector<std::string>{"--origin", "--v-axis"}));
}

}  // namespace
}  // namespace texbake::cli
