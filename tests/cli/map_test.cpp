// texbake map, run as a process: output formats, the worked example of SPEC
// section 2, and the exit codes and messages of bad input (2 for flags, 1 for
// files).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "run_texbake.h"

namespace texbake {
namespace {

using testing_cli::run_texbake;
using testing_cli::RunResult;
namespace fs = std::filesystem;

const std::string kUnitSphere =
    "map --proxy sphere --center 0,0,0 --radius 1 --pole 0,0,1 --equator 1,0,0 ";

// Runs `args`, expects success and exactly one JSON object on stdout.
nlohmann::json map_json(const std::string& args) {
  const RunResult r = run_texbake(args + " --json");
  EXPECT_EQ(r.exit_code, 0) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.err, "");
  // One line holding one object, nothing else.
  EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << r.out;
  try {
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j.is_object());
    return j;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not JSON: " << r.out;
    return nlohmann::json::object();
  }
}

// Runs `args`, expects `code` and a "texbake: error:" line containing `words`,
// and nothing on stdout.
void expect_failure(const std::string& args, int code, std::initializer_list<const char*> words) {
  const RunResult r = run_texbake(args);
  EXPECT_EQ(r.exit_code, code) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.out, "") << args;
  EXPECT_EQ(r.err.rfind("texbake: error: ", 0), 0u) << args << "\nstderr: " << r.err;
  for (const char* w : words) {
    EXPECT_NE(r.err.find(w), std::string::npos)
        << args << "\nstderr lacks \"" << w << "\": " << r.err;
  }
}

TEST(MapCommand, WorkedExampleAsJson) {
  // The issue's "done when" command: u = 0.125, v = 0.695913 (by hand in
  // tests/mapping/sphere_test.cpp).
  const nlohmann::json j = map_json(kUnitSphere + "--dir 1,1,1");
  EXPECT_EQ(j.size(), 3u) << j.dump();
  EXPECT_NEAR(j.at("u").get<double>(), 0.125, 1e-12);
  EXPECT_NEAR(j.at("v").get<double>(), 0.695913, 1e-6);
  EXPECT_EQ(j.at("status"), "ok");
}

TEST(MapCommand, SlidesNormalWithPixelPosition) {
  // (0.875, 0.695913) in 640 x 480: x = 559.5, y = 145.46 (SPEC section 2).
  const nlohmann::json j = map_json(kUnitSphere + "--dir 1,-1,1 --image 640x480");
  EXPECT_EQ(j.size(), 5u) << j.dump();
  EXPECT_NEAR(j.at("u").get<double>(), 0.875, 1e-12);
  EXPECT_NEAR(j.at("x").get<double>(), 559.5, 1e-9);
  EXPECT_NEAR(j.at("y").get<double>(), 145.46, 0.005);
}

TEST(MapCommand, HumanReadableOutput) {
  const RunResult r = run_texbake(kUnitSphere + "--dir 1,-1,1 --image 640x480");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("u        0.875\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("v        0.695913276\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("status   ok"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("x 559.5, y 145.461628"), std::string::npos) << r.out;
}

TEST(MapCommand, SpherePointIsAWorldPoint) {
  // Centre (10,-2,3); P = centre + (2,2,2) is the worked example's direction.
  const nlohmann::json j = map_json(
      "map --proxy sphere --center 10,-2,3 --radius 5 --pole 0,0,1 --equator 1,0,0 "
      "--point 12,0,5");
  EXPECT_NEAR(j.at("u").get<double>(), 0.125, 1e-12);
  EXPECT_NEAR(j.at("v").get<double>(), 0.695913276, 1e-9);
}

TEST(MapCommand, UpSetsTheDefaultPoleAndNegativeValuesParse) {
  // --up -z: pole -z, equator +x (default), east = (-z) x x = -y: (0,1,0) is u = 0.75.
  const nlohmann::json j =
      map_json("map --proxy sphere --center -1,0,0 --radius 1 --up -z --point -1,1,0");
  EXPECT_NEAR(j.at("u").get<double>(), 0.75, 1e-12);
  EXPECT_NEAR(j.at("v").get<double>(), 0.5, 1e-12);
}

TEST(MapCommand, EveryProxyKindFromFlags) {
  // Values by hand (see tests/mapping for the formulas).
  // Cylinder, base (0,0,1), axis +z, height 4: (0,3,3) is v = 0.5; equator
  // +x, so +y is u = 0.25.
  nlohmann::json j = map_json(
      "map --proxy cylinder --base 0,0,1 --axis 0,0,2 --radius 2 --height 4 --point 0,3,3");
  EXPECT_NEAR(j.at("u").get<double>(), 0.25, 1e-12);
  EXPECT_NEAR(j.at("v").get<double>(), 0.5, 1e-12);
  // Cone, apex at the origin, height 1, radius 1: (1,0,0) is v = 0.5.
  j = map_json("map --proxy cone --apex 0,0,0 --height 1 --radius 1 --point 1,0,0");
  EXPECT_NEAR(j.at("v").get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(j.at("u").get<double>(), 0.0, 1e-12);
  // Disk radius 2 around (1,1,0): (1,2,0) is r = 1 (v = 0.5) towards +y (u = 0.25).
  j = map_json("map --proxy disk --center 1,1,0 --radius 2 --point 1,2,5");
  EXPECT_NEAR(j.at("u").get<double>(), 0.25, 1e-12);
  EXPECT_NEAR(j.at("v").get<double>(), 0.5, 1e-12);
  // Quad 4 x 2: (1, 0.5) is (0.25, 0.25); (5, 0.5) is outside at u = 1.25.
  j = map_json("map --proxy quad --corners '0,0,0;4,0,0;4,2,0;0,2,0' --point 1,0.5,0");
  EXPECT_NEAR(j.at("u").get<double>(), 0.25, 1e-12);
  EXPECT_NEAR(j.at("v").get<double>(), 0.25, 1e-12);
  j = map_json("map --proxy quad --corners '0,0,0;4,0,0;4,2,0;0,2,0' --point 5,0.5,0");
  EXPECT_EQ(j.at("status"), "outside");
  EXPECT_NEAR(j.at("u").get<double>(), 1.25, 1e-12);
  // Plane with axes (2,0,0), (0,4,0): (1,1,9) is (0.5, 0.25).
  j = map_json("map --proxy plane --origin 0,0,0 --u-axis 2,0,0 --v-axis 0,4,0 --point 1,1,9");
  EXPECT_NEAR(j.at("u").get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(j.at("v").get<double>(), 0.25, 1e-12);
  // The sphere's centre has no mapping.
  j = map_json("map --proxy sphere --center 1,2,3 --radius 1 --point 1,2,3");
  EXPECT_EQ(j.at("status"), "undefined");
}

class MapWithFile : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_map_test_" +
            std::string(testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  fs::path dir_;
};

TEST_F(MapWithFile, ProxyFileGivesTheSameAnswer) {
  const std::string file =
      write("sphere.json",
            R"({"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,1],"equator":[1,0,0]})");
  const nlohmann::json j = map_json("map --proxy-file " + file + " --dir 1,1,1");
  EXPECT_NEAR(j.at("u").get<double>(), 0.125, 1e-12);
  EXPECT_NEAR(j.at("v").get<double>(), 0.695913, 1e-6);
}

TEST_F(MapWithFile, BadFilesExitOneNamingFileAndKey) {
  std::string f =
      write("typo.json", R"({"kind":"sphere","center":[0,0,0],"raduis":1,"pole":[0,0,1]})");
  expect_failure("map --proxy-file " + f + " --point 1,0,0", 1, {f.c_str(), "'raduis'"});
  f = write("missing.json", R"({"kind":"sphere","center":[0,0,0],"pole":[0,0,1]})");
  expect_failure("map --proxy-file " + f + " --point 1,0,0", 1,
                 {f.c_str(), "missing key 'radius'"});
  f = write("inf.json", R"({"kind":"disk","center":[0,0,0],"normal":[0,0,1],"radius":1e999})");
  expect_failure("map --proxy-file " + f + " --point 1,0,0", 1, {f.c_str(), "'radius'"});
  f = write("type.json", R"({"kind":"disk","center":"origin","normal":[0,0,1],"radius":1})");
  expect_failure("map --proxy-file " + f + " --point 1,0,0", 1, {f.c_str(), "'center'"});
  f = write("kind.json", R"({"kind":"torus"})");
  expect_failure("map --proxy-file " + f + " --point 1,0,0", 1, {f.c_str(), "torus"});
  f = write("zero.json", R"({"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,0]})");
  expect_failure("map --proxy-file " + f + " --point 1,0,0", 1, {f.c_str(), "pole", "zero"});
  const std::string absent = (dir_ / "absent.json").string();
  expect_failure("map --proxy-file " + absent + " --point 1,0,0", 1, {absent.c_str()});
}

TEST_F(MapWithFile, GeometryFlagsWithAProxyFileAreAUsageError) {
  const std::string file =
      write("sphere.json", R"({"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,1]})");
  expect_failure("map --proxy-file " + file + " --radius 2 --point 1,0,0", 2,
                 {"--radius", "--proxy-file"});
  expect_failure("map --proxy-file " + file + " --proxy sphere --point 1,0,0", 2,
                 {"--proxy", "--proxy-file"});
}

TEST(MapCommand, BadFlagsExitTwoNamingTheFlag) {
  expect_failure("map --proxy sphere --center 0,0,nan --radius 1 --point 1,0,0", 2,
                 {"--center", "finite"});
  expect_failure("map --proxy sphere --center 0,0,0 --radius inf --point 1,0,0", 2,
                 {"--radius", "finite"});
  expect_failure("map --proxy sphere --center 0,0,0 --radius 1e999 --point 1,0,0", 2, {"--radius"});
  expect_failure("map --proxy sphere --center 0,0,0 --radius 1 --point 1,0,abc", 2,
                 {"--point", "abc"});
  expect_failure("map --proxy sphere --center 0,0 --radius 1 --point 1,0,0", 2,
                 {"--center", "x,y,z"});
  expect_failure("map --proxy sphere --center 0,0,0 --point 1,0,0", 2, {"missing --radius"});
  expect_failure("map --proxy sphere --center 0,0,0 --radius 0 --point 1,0,0", 2,
                 {"--radius", "> 0"});
  expect_failure("map --proxy cylinder --base 0,0,0 --radius 1 --height -2 --point 1,0,0", 2,
                 {"--height"});
  expect_failure("map --proxy sphere --center 0,0,0 --radius 1 --pole 0,0,0 --point 1,0,0", 2,
                 {"--pole", "zero"});
  expect_failure(
      "map --proxy sphere --center 0,0,0 --radius 1 --pole 0,0,1 --equator 0,0,-3 --point 1,0,0", 2,
      {"--equator", "parallel", "--pole"});
  expect_failure("map --proxy disk --center 0,0,0 --radius 1 --normal 0,0,0 --point 1,0,0", 2,
                 {"--normal", "zero"});
  expect_failure("map --proxy plane --origin 0,0,0 --u-axis 1,0,0 --v-axis 2,0,0 --point 1,0,0", 2,
                 {"--v-axis", "parallel"});
  expect_failure("map --proxy quad --corners '0,0,0;1,0,0;0,1,0;1,1,0' --point 1,0,0", 2,
                 {"--corners", "convex"});
  expect_failure("map --proxy quad --corners '0,0,0;1,0,0;1,1,0.1;0,1,0' --point 1,0,0", 2,
                 {"--corners", "planar"});
  expect_failure("map --proxy quad --corners '0,0,0;1,0,0;1,1,0' --point 1,0,0", 2, {"--corners"});
  expect_failure("map --proxy torus --point 1,0,0", 2, {"--proxy", "torus"});
  expect_failure("map --point 1,0,0", 2, {"--proxy"});
  expect_failure("map --proxy sphere --center 0,0,0 --radius 1", 2, {"--point", "--dir"});
  expect_failure("map --proxy cone --apex 0,0,0 --height 1 --radius 1 --dir 1,0,0", 2,
                 {"--dir", "sphere"});
  expect_failure(kUnitSphere + "--dir 0,0,0", 2, {"--dir", "zero"});
  expect_failure("map --proxy cone --apex 0,0,0 --height 1 --radius 1 --center 0,0,0 --point 1,0,0",
                 2, {"--center", "cone"});
  expect_failure(kUnitSphere + "--dir 1,1,1 --image 640", 2, {"--image"});
  expect_failure(kUnitSphere + "--dir 1,1,1 --image 0x480", 2, {"--image"});
  expect_failure(kUnitSphere + "--dir 1,1,1 --up w", 2, {"--up"});
}

}  // namespace
}  // namespace texbake
