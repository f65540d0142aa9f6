// Proxy JSON (SPEC section 2): round trips of every kind, and errors that
// name the source and the key.
#include "mesh_io/proxy_json.h"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "tests/mapping/expect_same_params.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

// Expects parsing `text` to fail with kParse and a message containing every
// one of `words`.
void expect_error(const std::string& text, std::initializer_list<const char*> words) {
  Expected<Proxy> p = proxy_from_json(text, "test.json");
  ASSERT_FALSE(p.has_value()) << text;
  EXPECT_EQ(p.error().code, ErrorCode::kParse) << p.error().message;
  EXPECT_EQ(p.error().message.rfind("test.json: ", 0), 0u) << p.error().message;
  for (const char* w : words) {
    EXPECT_NE(p.error().message.find(w), std::string::npos)
        << "message \"" << p.error().message << "\" lacks \"" << w << "\"";
  }
}

TEST(ProxyJson, SpecExampleParses) {
  Expected<Proxy> p = proxy_from_json(
      R"({"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,1],"equator":[1,0,0]})");
  ASSERT_TRUE(p.has_value()) << p.error().message;
  const Sphere& s = std::get<Sphere>(*p);
  EXPECT_EQ(s.radius, 1);
  EXPECT_EQ(s.frame.axis, (Vec3{0, 0, 1}));
  EXPECT_EQ(s.frame.equator, (Vec3{1, 0, 0}));
  // And it maps the worked example (SPEC section 2).
  EXPECT_NEAR(inverse_map(*p, {1, 1, 1}).uv.u, 0.125, 1e-12);
}

TEST(ProxyJson, EveryKindRoundTripsExactly) {
  const char* texts[] = {
      R"({"kind":"sphere","center":[0.1,-2,3e5],"radius":0.3,"pole":[1,2,3],"equator":[0,1,0]})",
      R"({"kind":"cylinder","base":[1,2,3],"axis":[0,0,2],"radius":1.5,"height":4})",
      R"({"kind":"cone","apex":[0,0,5],"axis":[0,1,1],"equator":[1,0,0],"height":2,"radius":0.7})",
      R"({"kind":"disk","center":[1,1,1],"normal":[0,0,-1],"radius":2})",
      R"({"kind":"quad","corners":[[0,0,0],[4,0,0],[5,3,0],[1,2,0]]})",
      R"({"kind":"plane","origin":[1,2,3],"u_axis":[2,0,0],"v_axis":[0,0.1,0]})",
  };
  for (const char* text : texts) {
    Expected<Proxy> a = proxy_from_json(text);
    ASSERT_TRUE(a.has_value()) << a.error().message;
    const std::string written = proxy_to_json(*a);
    Expected<Proxy> b = proxy_from_json(written);
    ASSERT_TRUE(b.has_value()) << written << ": " << b.error().message;
    EXPECT_EQ(kind_of(*a), kind_of(*b));
    // Numbers are written to round-trip, but reading re-normalises the
    // (already unit) pole and equator, which may move them by an ulp: the
    // mapping agrees to rounding.
    for (Vec3 p : {Vec3{0.3, 0.2, 0.1}, Vec3{-1, 2, 5}, Vec3{4, 4, -4}}) {
      const MapResult ra = inverse_map(*a, p), rb = inverse_map(*b, p);
      EXPECT_NEAR(ra.uv.u, rb.uv.u, 1e-14) << written;
      EXPECT_NEAR(ra.uv.v, rb.uv.v, 1e-14) << written;
      EXPECT_EQ(ra.status, rb.status);
    }
  }
}

TEST(ProxyJson, WrittenSphereHasTheSpecKeys) {
  Expected<Proxy> p = make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, std::nullopt});
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(
      proxy_to_json(*p),
      R"({"center":[0.0,0.0,0.0],"equator":[1.0,0.0,0.0],"kind":"sphere","pole":[0.0,0.0,1.0],"radius":1.0})");
}

// Every kind through the writer and the reader of params (no make_proxy):
// the text is written out by hand (SPEC section 2's keys; nlohmann prints
// keys sorted), and reading it gives back every member exactly.
TEST(ProxyJson, EveryKindsParamsRoundTripThroughTheirKeys) {
  using Corners = std::array<Vec3, 4>;
  const std::pair<ProxyParams, const char*> cases[] = {
      {SphereParams{{1, 2, 3}, 4, {0, 2, 0}, Vec3{1, 0, 0}},
       R"({"center":[1.0,2.0,3.0],"equator":[1.0,0.0,0.0],"kind":"sphere","pole":[0.0,2.0,0.0],"radius":4.0})"},
      {CylinderParams{{1, 2, 3}, {0, 0, 2}, std::nullopt, 0.5, 7},
       R"({"axis":[0.0,0.0,2.0],"base":[1.0,2.0,3.0],"height":7.0,"kind":"cylinder","radius":0.5})"},
      {ConeParams{{-1, 0, 5}, {0, 0, 1}, Vec3{0, 1, 0}, 3, 1.5},
       R"({"apex":[-1.0,0.0,5.0],"axis":[0.0,0.0,1.0],"equator":[0.0,1.0,0.0],"height":3.0,"kind":"cone","radius":1.5})"},
      {DiskParams{{0, 0, 1}, {1, 1, 0}, std::nullopt, 2},
       R"({"center":[0.0,0.0,1.0],"kind":"disk","normal":[1.0,1.0,0.0],"radius":2.0})"},
      {QuadParams{Corners{Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 2, 0}, Vec3{0, 2, 0}}},
       R"({"corners":[[0.0,0.0,0.0],[4.0,0.0,0.0],[4.0,2.0,0.0],[0.0,2.0,0.0]],"kind":"quad"})"},
      {PlaneParams{{1, 1, 1}, {2, 0, 0}, {0, 0.5, 0}},
       R"({"kind":"plane","origin":[1.0,1.0,1.0],"u_axis":[2.0,0.0,0.0],"v_axis":[0.0,0.5,0.0]})"},
  };
  for (const auto& [params, text] : cases) {
    SCOPED_TRACE(text);
    EXPECT_EQ(proxy_params_to_json(params), text);
    Expected<ProxyParams> back = proxy_params_from_json(text);
    ASSERT_TRUE(back.has_value()) << back.error().message;
    testing_params::expect_same_params(*back, params);
  }
}

TEST(ProxyJson, EquatorIsOptional) {
  Expected<Proxy> p =
      proxy_from_json(R"({"kind":"disk","center":[0,0,0],"normal":[1,0,0],"radius":1})");
  ASSERT_TRUE(p.has_value()) << p.error().message;
  EXPECT_EQ(std::get<Disk>(*p).frame.equator, (Vec3{0, 1, 0}));
}

TEST(ProxyJson, UnknownMissingAndMistypedKeysAreNamed) {
  expect_error(R"({"kind":"sphere","center":[0,0,0],"raduis":1,"pole":[0,0,1]})",
               {"unknown key 'raduis'", "sphere"});
  expect_error(R"({"kind":"sphere","center":[0,0,0],"pole":[0,0,1]})", {"missing key 'radius'"});
  expect_error(R"({"center":[0,0,0],"radius":1,"pole":[0,0,1]})", {"missing key 'kind'"});
  expect_error(R"({"kind":3})", {"'kind'", "string"});
  expect_error(R"({"kind":"torus"})", {"unknown proxy kind 'torus'"});
  expect_error(R"({"kind":"sphere","center":[0,0],"radius":1,"pole":[0,0,1]})",
               {"'center'", "3 numbers"});
  expect_error(R"({"kind":"sphere","center":[0,0,"1"],"radius":1,"pole":[0,0,1]})",
               {"'center'[2]", "number", "string"});
  expect_error(R"({"kind":"sphere","center":[0,0,0],"radius":"1","pole":[0,0,1]})",
               {"'radius'", "must be a number"});
  expect_error(R"({"kind":"sphere","center":[0,0,0],"radius":true,"pole":[0,0,1]})",
               {"'radius'", "boolean"});
  expect_error(R"({"kind":"quad","corners":[[0,0,0],[1,0,0],[1,1,0]]})", {"'corners'", "4"});
  expect_error(R"({"kind":"quad","corners":[[0,0,0],[1,0,0],[1,1,0],[0,1]]})", {"'corners'[3]"});
  expect_error(R"({"kind":"plane","origin":[0,0,0],"u_axis":[1,0,0]})", {"missing key 'v_axis'"});
  expect_error(
      R"({"kind":"cone","apex":[0,0,0],"axis":[0,0,1],"height":1,"radius":1,"center":[0,0,0]})",
      {"unknown key 'center'", "cone"});
}

TEST(ProxyJson, NonFiniteNumbersAreRejected) {
  // JSON has no NaN or inf literals; 1e999 would be infinity.
  expect_error(R"({"kind":"sphere","center":[0,0,0],"radius":1e999,"pole":[0,0,1]})",
               {"'radius'", "not finite"});
  expect_error(R"({"kind":"sphere","center":[0,-1e400,0],"radius":1,"pole":[0,0,1]})",
               {"'center'", "not finite"});
  expect_error(R"({"kind":"sphere","center":[0,0,0],"radius":NaN,"pole":[0,0,1]})",
               {"not valid JSON"});
}

TEST(ProxyJson, DeepNestingIsRefusedNamingTheKey) {
  // 100,000 levels overflowed the stack when the value was converted; the
  // shared parse (mesh_io/json_strict.h) stops at 128 levels. `{"kind":
  // "sphere","center":` is 26 characters, the root is level 1: the 128th '['
  // is level 129, column 26 + 128.
  expect_error(R"({"kind":"sphere","center":)" + std::string(100000, '['),
               {"key 'center' nests deeper than 128 levels (line 1, column 154)"});
}

TEST(ProxyJson, GeometryErrorsNameTheKey) {
  expect_error(R"({"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,0]})", {"pole", "zero"});
  expect_error(R"({"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,1],"equator":[0,0,2]})",
               {"equator", "parallel"});
  expect_error(R"({"kind":"cylinder","base":[0,0,0],"axis":[0,0,1],"radius":1,"height":-1})",
               {"height"});
  expect_error(R"({"kind":"quad","corners":[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]})",
               {"corners", "convex"});
  expect_error(R"({"kind":"plane","origin":[0,0,0],"u_axis":[1,0,0],"v_axis":[0,0,0]})",
               {"v_axis"});
}

TEST(ProxyJson, MalformedTextAndWrongShapes) {
  expect_error(R"({"kind":"sphere",)", {"not valid JSON", "line 1"});
  expect_error("", {"not valid JSON"});
  expect_error("[1,2,3]", {"expected a JSON object", "array"});
  expect_error(R"({"kind":"sphere","kind":"disk"})", {"duplicate key 'kind'"});
}

class ProxyFile : public testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() /
        ("texbake_proxy_json_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ProxyFile, WriteThenReadGivesTheSameProxy) {
  Expected<Proxy> p = make_proxy(ConeParams{{1, 2, 3}, {0, 1, 1}, std::nullopt, 2, 0.5});
  ASSERT_TRUE(p.has_value());
  const fs::path file = dir_ / "cone.json";
  ASSERT_TRUE(write_proxy_file(file, *p).has_value());
  Expected<Proxy> back = read_proxy_file(file);
  ASSERT_TRUE(back.has_value()) << back.error().message;
  EXPECT_EQ(kind_of(*back), ProxyKind::kCone);
  EXPECT_EQ(std::get<Cone>(*back).apex, (Vec3{1, 2, 3}));
  EXPECT_EQ(std::get<Cone>(*back).height, 2);
  EXPECT_NEAR(dot(std::get<Cone>(*back).frame.axis, std::get<Cone>(*p).frame.axis), 1, 1e-15);
  // Only the target is left in the folder (no temporary file).
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST_F(ProxyFile, ErrorsNameTheFile) {
  const fs::path missing = dir_ / "missing.json";
  Expected<Proxy> p = read_proxy_file(missing);
  ASSERT_FALSE(p.has_value());
  EXPECT_EQ(p.error().code, ErrorCode::kIo);
  EXPECT_NE(p.error().message.find(missing.string()), std::string::npos) << p.error().message;

  const fs::path bad = dir_ / "bad.json";
  std::ofstream(bad) << R"({"kind":"disk","center":[0,0,0],"normal":[0,0,1],"radius":1,"extra":2})";
  p = read_proxy_file(bad);
  ASSERT_FALSE(p.has_value());
  EXPECT_EQ(p.error().code, ErrorCode::kParse);
  EXPECT_NE(p.error().message.find(bad.string() + ": unknown key 'extra'"), std::string::npos)
      << p.error().message;

  p = read_proxy_file(dir_);
  ASSERT_FALSE(p.has_value());
  EXPECT_EQ(p.error().code, ErrorCode::kIo);
  // A number beyond double's range and a value nested too deep: the file,
  // the key and the line (the value starts on line 2).
  std::ofstream(bad)
      << "{\"kind\":\"sphere\",\n\"radius\":1e999,\"center\":[0,0,0],\"pole\":[0,0,1]}";
  p = read_proxy_file(bad);
  ASSERT_FALSE(p.has_value());
  EXPECT_EQ(p.error().code, ErrorCode::kParse);
  EXPECT_EQ(p.error().message,
            bad.string() +
                ": key 'radius' holds a number that is not finite (1e999 at line 2, "
                "column 10)");
  std::ofstream(bad) << "{\"kind\":\"sphere\",\n\"pole\":" << std::string(90000, '[');
  p = read_proxy_file(bad);
  ASSERT_FALSE(p.has_value());
  EXPECT_EQ(p.error().message,
            bad.string() + ": key 'pole' nests deeper than 128 levels (line 2, column 135)");
}

}  // namespace
}  // namespace texbake
