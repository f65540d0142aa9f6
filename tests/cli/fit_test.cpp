// CLI tests of `texbake fit` (SPEC sections 5 and 6): exit codes, error
// messages, JSON output that parses, round-trips through --proxy-file's
// reader, and atomic -o output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>

#include "mapping/proxy.h"
#include "mesh_io/proxy_json.h"
#include "mesh_io/read_mesh.h"
#include "run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

const fs::path kData = TEXBAKE_DATA_DIR;

using testing_cli::slurp;

// A fresh folder per test, removed afterwards.
class FitCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_fit_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

using testing_cli::RunResult;
RunResult run(const std::string& args_quoted) {
  return testing_cli::run_texbake(args_quoted);
}
std::string quoted(const fs::path& p) {
  return testing_cli::shell_quote(p.string());
}

Vec3 vec(const nlohmann::json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

TEST_F(FitCli, SpherePrintsJsonThatEnclosesTheMesh) {
  const fs::path mesh = kData / "elephant.off";
  const RunResult r = run("fit " + quoted(mesh) + " --proxy sphere");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("kind"), "sphere");
  EXPECT_EQ(vec(j.at("pole")), (Vec3{0, 0, 1}));  // default up
  const Vec3 center = vec(j.at("center"));
  const double radius = j.at("radius").get<double>();
  auto loaded = read_mesh(mesh);
  ASSERT_TRUE(loaded) << loaded.error().message;
  double worst = 0;
  for (const Float3& p : loaded->mesh.positions) {
    worst = std::max(worst, length(Vec3{p.x, p.y, p.z} - center));
  }
  EXPECT_LE(worst, radius * (1 + 1e-12));
  EXPECT_GE(worst, radius * (1 - 1e-9));  // the farthest vertex is on the sphere
}

TEST_F(FitCli, EveryKindRoundTripsThroughAProxyFile) {
  for (const char* kind : {"sphere", "cylinder", "cone", "disk", "quad", "plane"}) {
    SCOPED_TRACE(kind);
    const fs::path file = dir_ / (std::string(kind) + ".json");
    const std::string mesh = quoted(kData / "mushroom.off");
    const RunResult printed = run("fit " + mesh + " --proxy " + kind);
    ASSERT_EQ(printed.exit_code, 0) << printed.err;
    const RunResult written = run("fit " + mesh + " --proxy " + kind + " -o " + quoted(file));
    ASSERT_EQ(written.exit_code, 0) << written.err;
    EXPECT_TRUE(written.out.empty());
    const std::string text = slurp(file);
    EXPECT_EQ(text, printed.out);
    EXPECT_EQ(nlohmann::json::parse(text).at("kind"), kind);
    // What --proxy-file reads back is the same proxy, printed identically.
    auto proxy = read_proxy_file(file);
    ASSERT_TRUE(proxy) << proxy.error().message;
    EXPECT_EQ(to_string(kind_of(*proxy)), std::string(kind));
    EXPECT_EQ(proxy_to_json(*proxy, 2) + "\n", text);
  }
  // Only the outputs are left in the folder: no temporary files.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.path().extension() == ".json";
  EXPECT_EQ(files, 6);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 6);
}

TEST_F(FitCli, UpSetsThePoleAndTheCylinderAxis) {
  const std::string mesh = quoted(kData / "fandisk.off");
  RunResult r = run("fit " + mesh + " --proxy sphere --up -y");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(vec(nlohmann::json::parse(r.out).at("pole")), (Vec3{0, -1, 0}));
  r = run("fit " + mesh + " --proxy cylinder --up x");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(vec(nlohmann::json::parse(r.out).at("axis")), (Vec3{1, 0, 0}));
}

TEST_F(FitCli, GivenFlagsAreKeptAndTheRestFitted) {
  const std::string mesh = quoted(kData / "elephant.off");
  const RunResult free_fit = run("fit " + mesh + " --proxy cylinder --axis 0,2,0");
  ASSERT_EQ(free_fit.exit_code, 0) << free_fit.err;
  const RunResult r = run("fit " + mesh + " --proxy cylinder --axis 0,2,0 --radius 5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json fitted = nlohmann::json::parse(free_fit.out);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(vec(j.at("axis")), (Vec3{0, 1, 0}));  // given, normalised
  EXPECT_EQ(j.at("radius").get<double>(), 5.0);   // given
  EXPECT_NE(fitted.at("radius").get<double>(), 5.0);
  EXPECT_EQ(j.at("base"), fitted.at("base"));  // fitted around the given axis
  EXPECT_EQ(j.at("height"), fitted.at("height"));
}

TEST_F(FitCli, UsageErrorsExitTwo) {
  const std::string mesh = quoted(kData / "elephant.off");
  for (const std::string& args :
       {"fit " + mesh, "fit " + mesh + " --proxy torus", "fit " + mesh + " --proxy sphere --up w",
        std::string("fit --proxy sphere"), "fit " + mesh + " --proxy sphere --apex 0,0,1",
        "fit " + mesh + " --proxy-file " + quoted(kData / "elephant.off")}) {
    SCOPED_TRACE(args);
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("texbake: error: "), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty());
  }
}

TEST_F(FitCli, MissingMeshExitsOneNamingTheFile) {
  const fs::path missing = dir_ / "no_such_mesh.off";
  const RunResult r = run("fit " + quoted(missing) + " --proxy sphere");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("texbake: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no_such_mesh.off"), std::string::npos) << r.err;
}

TEST_F(FitCli, UnwritableOutputExitsOneAndWritesNothing) {
  const fs::path target = dir_ / "missing_folder" / "proxy.json";
  const RunResult r =
      run("fit " + quoted(kData / "elephant.off") + " --proxy sphere -o " + quoted(target));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("texbake: error: "), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(target));
}

TEST_F(FitCli, FlatMeshCannotBeACylinderAndKeepsAnExistingOutput) {
  // Two triangles in the plane z = 0: a quad fits, a cylinder around +Z has
  // no height. The failed run must leave the earlier output untouched.
  const fs::path mesh = dir_ / "square.off";
  std::ofstream(mesh) << "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  const fs::path out = dir_ / "proxy.json";
  RunResult r = run("fit " + quoted(mesh) + " --proxy quad -o " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string before = slurp(out);
  // The unit square seen from +Z, u along +X, v along +Y (fit_proxy.h).
  const nlohmann::json corners = nlohmann::json::parse(before).at("corners");
  const Vec3 want[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (int i = 0; i < 4; ++i) EXPECT_LE(length(vec(corners.at(i)) - want[i]), 1e-6) << i;

  r = run("fit " + quoted(mesh) + " --proxy cylinder --up z -o " + quoted(out));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("square.off"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no extent along the axis"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(out), before);
}

// Issue #12 item 11: a given value the fit would be built around but that
// no fit can mend is a usage error naming the flag (exit 2), found before
// the mesh is read (the mesh here does not exist: reading it would be exit
// 1); it used to be exit 1 blaming the mesh.
TEST_F(FitCli, ABadValueToFitAroundExitsTwoNamingTheFlag) {
  const std::string missing_mesh = quoted(dir_ / "no_such_mesh.off");
  const std::pair<const char*, const char*> cases[] = {
      {" --proxy cylinder --axis 0,0,0", "cylinder: --axis is the zero vector"},
      {" --proxy cone --axis 0,0,0 --apex 0,0,1", "cone: --axis is the zero vector"},
      {" --proxy disk --normal 0,0,0", "disk: --normal is the zero vector"},
      {" --proxy sphere --pole 0,0,0", "sphere: --pole is the zero vector"},
      {" --proxy cone --height 0", "cone: --height must be a finite number > 0 (got 0)"},
      {" --proxy cone --height -1.5", "cone: --height must be a finite number > 0 (got -1.5)"},
      {" --proxy cylinder --radius -2", "cylinder: --radius must be a finite number > 0 (got -2)"},
      {" --proxy plane --u-axis 0,0,0", "plane: --u-axis is the zero vector"},
  };
  for (const auto& [flags, message] : cases) {
    SCOPED_TRACE(flags);
    const RunResult r = run("fit " + missing_mesh + flags);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, "texbake: error: " + std::string(message) + "\n");
    EXPECT_TRUE(r.out.empty());
  }
  // The same with a mesh that can be fitted.
  const RunResult r = run("fit " + quoted(kData / "elephant.off") + " --proxy cone --height 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "texbake: error: cone: --height must be a finite number > 0 (got 0)\n");
}

}  // namespace
}  // namespace texbake
