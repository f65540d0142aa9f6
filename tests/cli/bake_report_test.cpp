// texbake bake --report: the JSON's keys in the order bake/cli/report.h
// documents, for the vertex target and each atlas UV layout, and its counts
// on a mesh whose figures are known by hand.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/cli/run_texbake.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;
using texbake::testing_cli::run_texbake;
using texbake::testing_cli::shell_quote;
using texbake::testing_cli::slurp;

std::vector<std::string> keys(const ordered_json& j) {
  std::vector<std::string> k;
  for (auto it = j.begin(); it != j.end(); ++it) k.push_back(it.key());
  return k;
}

using Keys = std::vector<std::string>;

class BakeReport : public ::testing::Test {
 protected:
  fs::path dir =
      fs::temp_directory_path() / ("texbake_report_cli_" + std::to_string(::getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::path image, off, obj;

  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
    image = dir / "tex.ppm";
    std::ofstream t(image, std::ios::binary);
    t << "P6\n2 2\n255\n";
    const unsigned char px[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    t.write(reinterpret_cast<const char*>(px), 12);
    t.close();
    // The unit square as 2 x 2 cells (9 vertices, 8 triangles), a vertex in
    // no face (9) and a face repeating a vertex (one degenerate triangle).
    off = dir / "square.off";
    std::ofstream o(off);
    o << "OFF\n10 9 0\n";
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) o << i * 0.5 << " " << j * 0.5 << " 0\n";
    }
    o << "0.5 0.5 1\n";
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) {
        const int a = 3 * j + i;
        o << "3 " << a << " " << a + 1 << " " << a + 4 << "\n";
        o << "3 " << a << " " << a + 4 << " " << a + 3 << "\n";
      }
    }
    o << "3 0 0 1\n";
    o.close();
    // The same square as an OBJ with its own UVs (u, v) = (x, y).
    obj = dir / "square.obj";
    std::ofstream b(obj);
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) b << "v " << i * 0.5 << " " << j * 0.5 << " 0\n";
    }
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) b << "vt " << i * 0.5 << " " << j * 0.5 << "\n";
    }
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) {
        const int a = 3 * j + i + 1;
        b << "f " << a << "/" << a << " " << a + 1 << "/" << a + 1 << " " << a + 4 << "/" << a + 4
          << "\n";
        b << "f " << a << "/" << a << " " << a + 4 << "/" << a + 4 << " " << a + 3 << "/" << a + 3
          << "\n";
      }
    }
  }
  void TearDown() override { fs::remove_all(dir); }

  ordered_json bake(const fs::path& mesh, const std::string& flags, const std::string& output) {
    const fs::path report = dir / "r.json";
    const texbake::testing_cli::RunResult r = run_texbake(
        "bake " + shell_quote(mesh.string()) + " --texture " + shell_quote(image.string()) +
        " --proxy plane --origin 0,0,0 --u-axis 1,0,0 --v-axis 0,1,0 -q " + flags + " --report " +
        shell_quote(report.string()) + " -o " + shell_quote((dir / output).string()));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return ordered_json::parse(slurp(report), nullptr, /*allow_exceptions=*/false);
  }
};

TEST_F(BakeReport, VertexKeysInOrderAndCountsByHand) {
  const ordered_json j = bake(off, "", "o.ply");
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(keys(j),
            (Keys{"command", "target", "inputs", "proxy", "proxy_fitted", "counts", "timings"}));
  EXPECT_EQ(j["command"], "bake");
  EXPECT_EQ(j["target"], "vertex");
  EXPECT_EQ(keys(j["inputs"]), (Keys{"mesh", "texture", "output", "image", "options"}));
  EXPECT_EQ(keys(j["inputs"]["options"]), (Keys{"filter", "samples", "visibility", "occluded",
                                                "outside", "wrap", "linear", "threads"}));
  EXPECT_EQ(j["proxy_fitted"], ordered_json::array());
  EXPECT_EQ(keys(j["counts"]),
            (Keys{"vertices", "triangles", "degenerate_skipped", "unreferenced_vertices", "samples",
                  "occluded", "undefined", "outside", "filled", "unfilled"}));
  const ordered_json& c = j["counts"];
  EXPECT_EQ(c["vertices"], 10);
  EXPECT_EQ(c["triangles"], 8);
  EXPECT_EQ(c["degenerate_skipped"], 1);
  EXPECT_EQ(c["unreferenced_vertices"], 1);
  // 16 area samples at each of the 9 square vertices, one at the vertex in
  // no triangle; nothing blocks the rays along the plane's normal.
  EXPECT_EQ(c["samples"], 9 * 16 + 1);
  EXPECT_EQ(c["occluded"], 0);
  EXPECT_EQ(c["undefined"], 0);
  EXPECT_EQ(c["outside"], 0);
  EXPECT_EQ(keys(j["timings"]),
            (Keys{"load", "fit", "scene_build", "bake", "fill", "write", "total"}));
  EXPECT_EQ(j["timings"]["fit"], 0.0);  // nothing was fitted
}

TEST_F(BakeReport, AtlasKeysInOrderForEachUvLayout) {
  const Keys top{"command",      "target", "inputs", "proxy",
                 "proxy_fitted", "counts", "atlas",  "timings"};
  const Keys counts{"vertices", "triangles", "degenerate_skipped", "unreferenced_vertices",
                    "texels",   "samples",   "occluded",           "undefined",
                    "outside",  "padded"};
  const Keys atlas_counts{"texels",    "samples", "border_samples", "occluded",
                          "undefined", "outside", "padded"};
  const Keys atlas_timings{"uv_layout", "rasterize", "scene_build", "sample",
                           "fill",      "pad",       "write"};
  const Keys timings{"load",   "fit",  "uv_layout", "rasterize", "scene_build",
                     "sample", "fill", "pad",       "write",     "total"};
  struct Layout {
    fs::path mesh;
    std::string uv;
    Keys figures;  // the layout's own keys, between "counts" and "timings"
  };
  const std::vector<Layout> layouts = {
      {off, "generate", {"charts", "utilisation", "stretch_l2"}},
      {off, "proxy", {"cut_triangles"}},
      {obj, "mesh", {"uv_check"}},
  };
  for (const Layout& l : layouts) {
    const ordered_json j = bake(l.mesh, "--size 32 --uv " + l.uv, "a.obj");
    ASSERT_TRUE(j.is_object()) << l.uv;
    EXPECT_EQ(keys(j), top) << l.uv;
    EXPECT_EQ(j["target"], "atlas");
    EXPECT_EQ(keys(j["inputs"]["options"]),
              (Keys{"samples", "visibility", "occluded", "outside", "wrap", "linear", "threads"}))
        << l.uv;
    EXPECT_EQ(keys(j["counts"]), counts) << l.uv;
    const ordered_json& a = j["atlas"];
    Keys atlas_keys{"uv", "size", "samples_per_texel", "padding", "counts"};
    atlas_keys.insert(atlas_keys.end(), l.figures.begin(), l.figures.end());
    atlas_keys.push_back("timings");
    EXPECT_EQ(keys(a), atlas_keys) << l.uv;
    EXPECT_EQ(a["uv"], l.uv);
    EXPECT_EQ(a["size"], 32);
    EXPECT_EQ(a["samples_per_texel"], 4);
    EXPECT_EQ(a["padding"], 1);  // 8 texels at 2048, scaled to 32: 0.125, at least 1
    EXPECT_EQ(keys(a["counts"]), atlas_counts) << l.uv;
    EXPECT_EQ(keys(a["timings"]), atlas_timings) << l.uv;
    EXPECT_EQ(keys(j["timings"]), timings) << l.uv;
    // The top-level counts are the atlas's, samples per texel times texels.
    EXPECT_EQ(j["counts"]["texels"], a["counts"]["texels"]) << l.uv;
    EXPECT_EQ(j["counts"]["samples"].get<int>(), 4 * a["counts"]["texels"].get<int>()) << l.uv;
    EXPECT_GT(a["counts"]["texels"].get<int>(), 0) << l.uv;
    EXPECT_EQ(j["timings"]["write"], a["timings"]["write"]) << l.uv;
  }
}

TEST_F(BakeReport, LayoutFiguresByHand) {
  // The OBJ's UVs are its positions in [0, 1]^2: no corner outside, no
  // triangle overlapping another.
  ordered_json j = bake(obj, "--size 32 --uv mesh", "m.obj");
  EXPECT_EQ(j["atlas"]["uv_check"], (ordered_json{{"corners_outside", 0}, {"overlap_texels", 0}}));
  // A plane has no seam: nothing to cut.
  j = bake(off, "--size 32 --uv proxy", "p.obj");
  EXPECT_EQ(j["atlas"]["cut_triangles"], 0);
  // --padding inf is reported as "inf"; an explicit count as given.
  j = bake(off, "--size 32 --padding inf", "i.obj");
  EXPECT_EQ(j["atlas"]["padding"], "inf");
  j = bake(off, "--size 32 --padding 5", "f.obj");
  EXPECT_EQ(j["atlas"]["padding"], 5);
  EXPECT_EQ(j["atlas"]["uv"], "generate");  // --uv auto on a mesh without UVs
}

}  // namespace
