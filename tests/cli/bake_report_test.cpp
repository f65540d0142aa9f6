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
  fs::path dir = texbake::testing_cli::fresh_test_dir("report_cli");
  fs::path image = dir / "tex.ppm", off, obj;

  void SetUp() override {
    texbake::testing_cli::write_ppm(image, 2, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255});
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
      {off, "proxy", {"uv_check", "cut_triangles"}},
      {obj, "mesh", {"uv_check"}},
  };
  for (const Layout& l : layouts) {
    const ordered_json j = bake(l.mesh, "--size 32 --uv " + l.uv, "a.obj");
    ASSERT_TRUE(j.is_object()) << l.uv;
    EXPECT_EQ(keys(j), top) << l.uv;
    EXPECT_EQ(j["target"], "atlas");
    EXPECT_EQ(keys(j["inputs"]["options"]), (Keys{"filter", "samples", "visibility", "occluded",
                                                  "outside", "wrap", "linear", "threads"}))
        << l.uv;
    EXPECT_EQ(j["inputs"]["options"]["filter"], "bilinear") << l.uv;
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
  // ... and a flat mesh seen along the plane's normal has no overlap.
  EXPECT_EQ(j["atlas"]["uv_check"], (ordered_json{{"overlap_texels", 0}}));
  // --padding inf is reported as "inf"; an explicit count as given.
  j = bake(off, "--size 32 --padding inf", "i.obj");
  EXPECT_EQ(j["atlas"]["padding"], "inf");
  j = bake(off, "--size 32 --padding 5", "f.obj");
  EXPECT_EQ(j["atlas"]["padding"], 5);
  EXPECT_EQ(j["atlas"]["uv"], "generate");  // --uv auto on a mesh without UVs
}

// --uv proxy on two unit squares one above the other along the plane's
// normal (z = 0 first, then z = 1; each split along its diagonal u = v):
// every texel is shared, except the 32 whose centres lie on the diagonal
// (x + y = 31 in pixels), on an edge of both squares: 32 * 32 - 32 = 992
// overlapping texels, by hand. The warning says so on stderr, the report
// counts them.
TEST_F(BakeReport, ProxyOverlapsAreWarnedAndCounted) {
  const fs::path stacked = dir / "stacked.off";
  {
    std::ofstream o(stacked);
    o << "OFF\n8 4 0\n";
    for (int z = 0; z < 2; ++z)
      o << "0 0 " << z << "\n1 0 " << z << "\n1 1 " << z << "\n0 1 " << z << "\n";
    for (int q = 0; q < 2; ++q) {
      const int a = 4 * q;
      o << "3 " << a << " " << a + 1 << " " << a + 2 << "\n3 " << a << " " << a + 2 << " " << a + 3
        << "\n";
    }
  }
  const fs::path report = dir / "overlap.json";
  const texbake::testing_cli::RunResult r = run_texbake(
      "bake " + shell_quote(stacked.string()) + " --texture " + shell_quote(image.string()) +
      " --proxy plane --origin 0,0,0 --u-axis 1,0,0 --v-axis 0,1,0 -q --uv proxy --size 32"
      " --report " +
      shell_quote(report.string()) + " -o " + shell_quote((dir / "s.obj").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("texbake: warning: 992 atlas texels are covered by overlapping UV "
                       "triangles"),
            std::string::npos)
      << r.err;
  const ordered_json j = ordered_json::parse(slurp(report), nullptr, false);
  EXPECT_EQ(j["atlas"]["uv_check"]["overlap_texels"], 992);
  // The hidden square's samples move to the visible one's triangles.
  EXPECT_EQ(j["atlas"]["counts"]["occluded"], 0);
}

}  // namespace
