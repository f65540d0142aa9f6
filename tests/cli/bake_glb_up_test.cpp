// texbake bake ... -o F.glb and --up (issue #11 item 5): the node matrix
// turns the mesh's --up axis (default z) to glTF's +Y, the positions are the
// file's; --up is accepted for a .glb where it is no geometry flag
// (--proxy-file, quad) and stays an error for .ply. Matrices worked out by
// hand, column-major: +Z up is -90 degrees about X, (x, y, z) -> (x, z, -y).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/cli/run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::run_texbake;
using testing_cli::RunResult;
using testing_cli::shell_quote;

// An irregular tetrahedron (no coordinate repeats, so a swapped axis shows).
const float kTetra[4][3] = {
    {0.1f, -0.2f, 0.05f}, {1.0f, 0.1f, 0.2f}, {0.2f, 0.9f, -0.1f}, {0.3f, 0.2f, 0.8f}};

class BakeGlbUp : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream off(dir_ / "tetra.off");
    off << "OFF\n4 4 0\n";
    for (const auto& p : kTetra) off << p[0] << " " << p[1] << " " << p[2] << "\n";
    off << "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    off.close();
    testing_cli::write_ppm(dir_ / "tex.ppm", 2, 1, {255, 128, 0, 0, 128, 255});
    std::ofstream(dir_ / "s.json")
        << R"({"kind":"sphere","center":[0.4,0.3,0.2],"radius":2,"pole":[0,0,1],"equator":[1,0,0]})";
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string q(const fs::path& p) const { return shell_quote(p.string()); }
  std::string bake(const std::string& flags, const std::string& out) const {
    return "bake " + q(dir_ / "tetra.off") + " --texture " + q(dir_ / "tex.ppm") + " " + flags +
           " -q -o " + q(dir_ / out);
  }
  // The one node's matrix of a written GLB (empty: none, the identity).
  std::vector<double> matrix(const std::string& name) const {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (dir_ / name).string())) << err;
    EXPECT_EQ(model.nodes.size(), 1u);
    return model.nodes.empty() ? std::vector<double>{} : model.nodes[0].matrix;
  }

  fs::path dir_ = testing_cli::fresh_test_dir("bake_glb_up");
};

const std::string kSphere = "--proxy sphere --center 0.4,0.3,0.2 --radius 2";

TEST_F(BakeGlbUp, DefaultUpIsZTurnedToY) {
  const RunResult r = run_texbake(bake(kSphere + " --target vertex", "v.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(matrix("v.glb"),
            (std::vector<double>{1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1}));
  // The positions are the file's (vertex target: input order).
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (dir_ / "v.glb").string()));
  const tinygltf::Primitive& prim = model.meshes.at(0).primitives.at(0);
  const tinygltf::Accessor& a = model.accessors.at(prim.attributes.at("POSITION"));
  const tinygltf::BufferView& view = model.bufferViews.at(a.bufferView);
  ASSERT_EQ(a.count, 4u);
  float pos[12];
  std::memcpy(pos, model.buffers[0].data.data() + view.byteOffset + a.byteOffset, sizeof pos);
  for (int v = 0; v < 4; ++v) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(pos[v * 3 + k], kTetra[v][k]) << v << "," << k;
  }
  EXPECT_TRUE(prim.attributes.count("NORMAL"));
}

TEST_F(BakeGlbUp, EachAxis) {
  struct Case {
    const char* up;
    std::vector<double> want;  // column-major; empty: no matrix
  };
  const Case cases[] = {
      {"z", {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1}},    // (x, z, -y)
      {"-z", {1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1}},   // (x, -z, y)
      {"x", {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}},    // (-y, x, z)
      {"-x", {0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}},   // (y, -x, z)
      {"-y", {1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1}},  // (x, -y, -z)
      {"y", {}},
  };
  for (const Case& c : cases) {
    const std::string up = std::string(" --up ") + c.up;
    RunResult r = run_texbake(bake(kSphere + up + " --target vertex", "v.glb"));
    ASSERT_EQ(r.exit_code, 0) << c.up << "\n" << r.err;
    EXPECT_EQ(matrix("v.glb"), c.want) << c.up;
    r = run_texbake(bake(kSphere + up + " --uv proxy --size 16", "a.glb"));
    ASSERT_EQ(r.exit_code, 0) << c.up << "\n" << r.err;
    EXPECT_EQ(matrix("a.glb"), c.want) << c.up << " (atlas)";
  }
}

TEST_F(BakeGlbUp, UpWithProxyFileOrQuadOrientsAGlbOnly) {
  const std::string file = "--proxy-file " + q(dir_ / "s.json");
  RunResult r = run_texbake(bake(file + " --up y --target vertex", "f.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(matrix("f.glb"), std::vector<double>{});
  r = run_texbake(bake(file + " --up -x --target vertex", "f.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(matrix("f.glb"),
            (std::vector<double>{0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
  r = run_texbake(bake(file + " --up y", "f.ply"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "texbake: error: --up cannot be combined with --proxy-file (the file holds the "
            "whole proxy)\n");
  EXPECT_FALSE(fs::exists(dir_ / "f.ply"));

  const std::string quad = "--proxy quad --corners '-1,-1,0;2,-1,0;2,2,0;-1,2,0'";
  r = run_texbake(bake(quad + " --up y --target vertex", "q.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(matrix("q.glb"), std::vector<double>{});
  r = run_texbake(bake(quad + " --up y", "q.ply"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("texbake: error: --up does not apply to --proxy quad"), std::string::npos)
      << r.err;
}

TEST_F(BakeGlbUp, HelpSaysWhatUpDoesToAGlb) {
  const RunResult r = run_texbake("bake --help");
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("glTF's +Y"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace texbake
