// glTF inputs on the command line: info, bake, render and fit read .glb /
// .gltf meshes (mesh_io/read_gltf.cpp); a truncated GLB is exit 1 naming the
// file, with no output written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/cli/run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::fresh_test_dir;
using testing_cli::run_texbake;
using testing_cli::shell_quote;
using testing_cli::slurp;

fs::path seed(const std::string& name) {
  return fs::path(TEXBAKE_SOURCE_DIR) / "tests" / "fuzz" / "corpus" / name;
}

class GltfInputCli : public ::testing::Test {
 protected:
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_ = fresh_test_dir("gltf_input");
};

// tests/fuzz/corpus/fuzz_mesh_glb/tri_texture.glb: the triangle (0,0,0),
// (1,0,0), (0,1,0) under a node translated by (1, 2, 3) whose child turns
// 90 degrees about Z and scales by 2: (1,2,3), (1,4,3), (-1,2,3) by hand;
// a 1x1 PNG of 69 bytes in a bufferView; baseColorFactor (1, 0.5, 0.5, 1).
TEST_F(GltfInputCli, InfoListsTransformedBoundsAndEmbeddedTexture) {
  const fs::path glb = seed("fuzz_mesh_glb/tri_texture.glb");
  const auto r = run_texbake("info " + shell_quote(glb.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("vertices: 3\nfaces: 1\ntriangles: 1\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bounds: min -1 2 3  max 1 4 3\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("uv: yes\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("texture: " + glb.string() + ": image 0 (embedded image/png, 69 bytes)\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("base color factor: 1 0.5 0.5 1 (linear)\n"), std::string::npos) << r.out;
}

// A quad baked to a vertex-colour GLB (+Y up: no node matrix) is an input
// for bake, render and fit like any mesh.
TEST_F(GltfInputCli, BakeRenderAndFitReadAGlb) {
  const fs::path off = dir_ / "quad.off";
  std::ofstream(off) << "OFF\n4 1 0\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n4 0 1 2 3\n";
  testing_cli::write_ppm(dir_ / "t.ppm", 2, 1, {255, 0, 0, 0, 0, 255});
  const std::string tex = shell_quote((dir_ / "t.ppm").string());
  const fs::path glb = dir_ / "quad.glb";
  auto r =
      run_texbake("bake " + shell_quote(off.string()) + " --texture " + tex +
                  " --proxy plane --target vertex --up y --quiet -o " + shell_quote(glb.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path ply = dir_ / "again.ply";
  r = run_texbake("bake " + shell_quote(glb.string()) + " --texture " + tex +
                  " --proxy plane --quiet -o " + shell_quote(ply.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("info " + shell_quote(ply.string()));
  EXPECT_NE(r.out.find("vertices: 4\n"), std::string::npos) << r.out;
  // The GLB's own vertex colours as the render's colour source.
  r = run_texbake("render " + shell_quote(glb.string()) + " --size 32x32 --up y -o " +
                  shell_quote((dir_ / "r.png").string()));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "r.png"));
  r = run_texbake("fit " + shell_quote(glb.string()) + " --proxy sphere");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(GltfInputCli, TruncatedGlbIsExitOneNamingTheFileWithoutOutput) {
  const std::string bytes = slurp(seed("fuzz_mesh_glb/tri_colors.glb"));
  const fs::path cut = dir_ / "cut.glb";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  testing_cli::write_ppm(dir_ / "t.ppm", 1, 1, {10, 20, 30});
  const fs::path out = dir_ / "out.ply";
  for (const std::string cmd :
       {"info " + shell_quote(cut.string()),
        "bake " + shell_quote(cut.string()) + " --texture " +
            shell_quote((dir_ / "t.ppm").string()) + " --proxy sphere -o " +
            shell_quote(out.string()),
        "render " + shell_quote(cut.string()) + " -o " + shell_quote(out.string() + ".png")}) {
    SCOPED_TRACE(cmd);
    const auto r = run_texbake(cmd);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.err.rfind("texbake: error: " + cut.string() + ": the GLB header declares ", 0), 0u)
        << r.err;
    EXPECT_NE(r.err.find("(truncated)"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out.string() + ".png"));
}

}  // namespace
}  // namespace texbake
