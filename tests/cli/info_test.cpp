// texbake info: runs the built binary (TEXBAKE_BINARY) on small meshes whose
// counts, bounds and problems are worked out by hand, and on bad files.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>

namespace {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

CliRun run_texbake(const std::string& args, const fs::path& dir) {
  const fs::path err_file = dir / "stderr.txt";
  const std::string cmd = std::string(TEXBAKE_BINARY) + " " + args + " 2>" + err_file.string();
  CliRun r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  for (std::size_t n; (n = fread(buf.data(), 1, buf.size(), p)) > 0;) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err_file);
  r.err.assign(std::istreambuf_iterator<char>(e), {});
  return r;
}

class InfoCli : public ::testing::Test {
 protected:
  fs::path dir;
  void SetUp() override {
    std::random_device rd;
    dir = fs::temp_directory_path() / ("texbake-info-" + std::to_string(rd()));
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
};

// A quad (2 triangles), a book of three triangles on edge 0-1 (one
// non-manifold edge), one zero-area triangle, one unreferenced vertex.
const char* kMesh =
    "OFF\n8 5 0\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 -1 0\n-2 3 -4\n2 0 0\n1 1 0\n"
    "3 0 1 2\n3 1 0 3\n3 0 1 4\n3 0 1 6\n4 0 1 7 2\n";

TEST_F(InfoCli, TextReportsCountsBoundsAndProblems) {
  const fs::path mesh = write("m.off", kMesh);
  CliRun r = run_texbake("info " + mesh.string(), dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("vertices: 8\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("faces: 5\n"), std::string::npos) << r.out;
  // 1 + 1 + 1 + 0 (0,1,6 are collinear) + 2 (the quad).
  EXPECT_NE(r.out.find("triangles: 5\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bounds: min -2 -1 -4  max 2 3 1\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("uv: no\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("vertex colors: no\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("degenerate triangles: 1\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("unreferenced vertices: 1\n"), std::string::npos) << r.out;
  // Edge 0-1 is in faces 0, 1, 2, 3 and the quad: one non-manifold edge.
  EXPECT_NE(r.out.find("non-manifold edges: 1\n"), std::string::npos) << r.out;
}

TEST_F(InfoCli, JsonHasTheSameValues) {
  const fs::path mesh = write("m.off", kMesh);
  CliRun r = run_texbake("info --json " + mesh.string(), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["vertices"], 8);
  EXPECT_EQ(j["faces"], 5);
  EXPECT_EQ(j["triangles"], 5);
  EXPECT_EQ(j["bounds"]["min"], nlohmann::json::parse("[-2, -1, -4]"));
  EXPECT_EQ(j["bounds"]["max"], nlohmann::json::parse("[2, 3, 1]"));
  EXPECT_EQ(j["problems"]["degenerate_triangles"], 1);
  EXPECT_EQ(j["problems"]["unreferenced_vertices"], 1);
  EXPECT_EQ(j["problems"]["non_manifold_edges"], 1);
  EXPECT_EQ(j["attributes"]["uv"], false);
  EXPECT_TRUE(j["attributes"]["texture"].is_null());
}

TEST_F(InfoCli, ObjAttributesAreListed) {
  write("m.mtl", "newmtl a\nmap_Kd wood.png\n");
  const fs::path mesh = write("m.obj",
                              "mtllib m.mtl\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\n"
                              "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nusemtl a\nf 1/1/1 2/2/1 3/3/1\n");
  CliRun r = run_texbake("info " + mesh.string(), dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("uv: yes\nnormals: yes\nvertex colors: yes\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("texture: " + (dir / "wood.png").string() + "\n"), std::string::npos)
      << r.out;
}

TEST_F(InfoCli, BadFilesExitOneNamingTheFile) {
  const fs::path bad = fs::path(TEXBAKE_SOURCE_DIR) / "tests" / "data" / "bad";
  for (const fs::path& f : {bad / "nan.off", bad / "truncated_binary.ply", dir / "missing.obj",
                            bad / "out_of_range.obj"}) {
    CliRun r = run_texbake("info " + f.string(), dir);
    EXPECT_EQ(r.exit_code, 1) << f;
    EXPECT_EQ(r.err.rfind("texbake: error: " + f.string() + ": ", 0), 0u) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

TEST_F(InfoCli, MissingArgumentIsUsageError) {
  CliRun r = run_texbake("info", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("texbake: error:"), std::string::npos) << r.err;
}

}  // namespace
