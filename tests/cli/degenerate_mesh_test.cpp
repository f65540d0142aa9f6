// Nothing to bake is an error (issue #10 item 8, issue #12 item 1): a mesh
// with faces but no non-degenerate triangle makes bake (vertex and atlas)
// and render exit 1 with "texbake: error: MESH: all N triangles are
// degenerate" and write nothing; `info` still reads and reports it.
// N counts the triangles of the faces' triangulation by hand: n - 2 for a
// polygon of n >= 3 corners, one for a face of fewer corners.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/cli/run_texbake.h"

namespace {

namespace fs = std::filesystem;
using texbake::testing_cli::run_texbake;
using texbake::testing_cli::shell_quote;

struct DegenerateMesh {
  const char* name;
  const char* off;  // file content ("" = the bad-input corpus' all_degenerate.off)
  int triangles;    // N, by hand
};

const DegenerateMesh kMeshes[] = {
    {"all_degenerate.off", "", 2},  // two triangles, each with a repeated point
    {"collinear.off", "OFF\n4 2 0\n0 0 0\n1 1 1\n2 2 2\n3 3 3\n3 0 1 2\n3 1 2 3\n", 2},
    {"collinear_quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n4 0 1 2 3\n", 2},
    {"two_gons.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n2 1 2\n", 2},
    {"repeated.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 0 0\n3 1 1 1\n", 2},
    {"no_corners.off", "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n0\n0\n0\n", 3},
};

class DegenerateMeshCli : public ::testing::Test {
 protected:
  fs::path dir =
      fs::temp_directory_path() / ("texbake_degenerate_cli_" + std::to_string(::getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::path image;
  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
    image = dir / "tex.ppm";
    std::ofstream t(image, std::ios::binary);
    t << "P6\n2 1\n255\n";
    const unsigned char px[6] = {255, 128, 0, 0, 128, 255};
    t.write(reinterpret_cast<const char*>(px), 6);
  }
  void TearDown() override { fs::remove_all(dir); }

  fs::path mesh_file(const DegenerateMesh& m) {
    if (*m.off == '\0') {
      return fs::path(TEXBAKE_SOURCE_DIR) / "tests" / "data" / "bad" / m.name;
    }
    std::ofstream(dir / m.name) << m.off;
    return dir / m.name;
  }
  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
    return names;
  }
};

TEST_F(DegenerateMeshCli, BakeAndRenderExit1NamingTheMeshAndWriteNothing) {
  for (const DegenerateMesh& m : kMeshes) {
    const fs::path mesh = mesh_file(m);
    const std::string q = shell_quote(mesh.string());
    const std::string tex = " --texture " + shell_quote(image.string());
    const std::string out = shell_quote((dir / "out").string());
    const std::string expected = "texbake: error: " + mesh.string() + ": all " +
                                 std::to_string(m.triangles) + " triangles are degenerate\n";
    const std::vector<std::string> commands = {
        // vertex target, every geometry flag given
        "bake " + q + tex + " --proxy sphere --center 0,0,0 --radius 1 -o " + out + ".ply",
        // vertex target, the proxy to be fitted: the mesh's problem is reported first
        "bake " + q + tex + " --proxy sphere -o " + out + ".ply",
        // atlas target, each UV layout
        "bake " + q + tex + " --proxy sphere --center 0,0,0 --radius 1 --size 16 -o " + out +
            ".obj",
        "bake " + q + tex + " --proxy sphere --center 0,0,0 --radius 1 --uv proxy -o " + out +
            ".glb",
        "bake " + q + tex + " --proxy cylinder --uv generate --size 16 --report " +
            shell_quote((dir / "r.json").string()) + " -o " + out + ".obj",
        "render " + q + " -o " + out + ".png --size 8x8",
        "render " + q + tex + " --proxy sphere -o " + out + ".png --size 8x8",
    };
    for (const std::string& c : commands) {
      const texbake::testing_cli::RunResult r = run_texbake(c);
      EXPECT_EQ(r.exit_code, 1) << c << "\n" << r.err;
      EXPECT_EQ(r.err, expected) << c;
      EXPECT_EQ(r.out, "") << c;
      std::vector<std::string> left = files();
      std::erase_if(left, [](const std::string& n) {
        return n == "tex.ppm" || fs::path(n).extension() == ".off";  // the inputs
      });
      EXPECT_TRUE(left.empty()) << c << ": wrote " << (left.empty() ? "" : left.front());
    }
  }
}

TEST_F(DegenerateMeshCli, InfoStillReadsAndReportsThem) {
  for (const DegenerateMesh& m : kMeshes) {
    const fs::path mesh = mesh_file(m);
    const texbake::testing_cli::RunResult r = run_texbake("info " + shell_quote(mesh.string()));
    EXPECT_EQ(r.exit_code, 0) << m.name << "\n" << r.err;
    EXPECT_NE(r.out.find("\ntriangles: 0\n"), std::string::npos) << m.name << "\n" << r.out;
    EXPECT_NE(r.out.find("\ndegenerate triangles: " + std::to_string(m.triangles) + "\n"),
              std::string::npos)
        << m.name << "\n"
        << r.out;
  }
}

TEST_F(DegenerateMeshCli, AMeshWithOneGoodTriangleStillBakes) {
  // The rule is "nothing to bake", not "something degenerate": one
  // non-degenerate triangle beside a degenerate one is enough.
  const fs::path mesh = dir / "one_good.off";
  std::ofstream(mesh) << "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n";
  const texbake::testing_cli::RunResult r = run_texbake(
      "bake " + shell_quote(mesh.string()) + " --texture " + shell_quote(image.string()) +
      " --proxy sphere --center 0,0,0 --radius 1 -q -o " + shell_quote((dir / "o.ply").string()));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "o.ply"));
}

}  // namespace
