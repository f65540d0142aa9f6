// bake --layers with the atlas target through the executable (SPEC section
// 10, issue #14): one layer over base "none" is the proxy atlas bake in
// linear light on the same generated layout, base "mesh" keeps the mesh's
// own texture where no layer reaches, the coverage is the PNG's alpha (and
// a GLB's alphaMode BLEND), bad flags and files are errors with no output,
// and the result does not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "mesh_io/image_io.h"
#include "tests/cli/run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::run_texbake;

std::string q(const fs::path& p) {
  return testing_cli::shell_quote(p.string());
}

const std::string kData = TEXBAKE_DATA_DIR;
const char* kEarthSphere =
    R"({"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,1,0],"equator":[0,0,1]})";
const char* kSphereFlags = " --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1";

// An 8-bit image's texel (x, y) channel c as a level 0..255.
int level(const Image& image, int x, int y, int c) {
  return static_cast<int>(
      std::lround(image.pixels[4 * (static_cast<std::size_t>(y) * image.width + x) + c] * 255));
}

class LayersAtlasCli : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing_cli::fresh_test_dir("texbake_layers_atlas_cli"); }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const fs::path& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
  }
  Image image(const fs::path& png) {
    Expected<Image> read = read_image(png);
    EXPECT_TRUE(read) << read.error().message;
    if (!read) return {};
    EXPECT_TRUE(read->has_alpha) << png;  // an RGBA PNG
    return std::move(read).value();
  }
  // The white decal of half opacity on a plane over the bunny's front.
  void write_decal() {
    Image white;
    white.width = white.height = 4;
    white.pixels.assign(4 * 4 * 4, 1.0f);
    for (std::size_t i = 3; i < white.pixels.size(); i += 4) white.pixels[i] = 0.5f;
    white.has_alpha = true;
    ASSERT_TRUE(write_image(dir_ / "decal.png", white.view()));
  }
  fs::path dir_;
};

TEST_F(LayersAtlasCli, OneLayerOverNoneIsTheProxyAtlasInLinearLight) {
  const std::string bunny = q(kData + "/bunny00.off");
  write("L.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                      kData + R"(/earth.jpg"}]})");
  testing_cli::RunResult r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") +
                                         " --uv generate --size 512 --padding 0 -q --report " +
                                         q(dir_ / "r.json") + " -o " + q(dir_ / "layers.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --texture " + q(kData + "/earth.jpg") + kSphereFlags +
                  " --filter bilinear --linear --uv generate --size 512 --padding 0 -q -o " +
                  q(dir_ / "direct.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image layers = image(dir_ / "layers.png"), direct = image(dir_ / "direct.png");
  ASSERT_EQ(layers.width, 512);
  ASSERT_EQ(direct.width, 512);
  // Texels all of whose samples the sphere sees (alpha 1) are the proxy
  // atlas's texels within 1 level (measured: 6 of 461,877 values differ by 1); partly seen texels
  // have the coverage as alpha (a multiple of 1/4 with 4 samples: 64, 128, 191; no padding, whose
  // rings would average their neighbours).
  std::size_t seen = 0, partly = 0;
  for (int y = 0; y < 512; ++y) {
    for (int x = 0; x < 512; ++x) {
      const int a = level(layers, x, y, 3);
      if (a == 255) {
        ++seen;
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(level(layers, x, y, c), level(direct, x, y, c), 1)
              << "texel " << x << "," << y;
        }
      } else if (a > 0) {
        ++partly;
        EXPECT_TRUE(a == 64 || a == 128 || a == 191) << a << " at " << x << "," << y;
      }
    }
  }
  EXPECT_GT(seen, 100000u);
  EXPECT_GT(partly, 1000u);
  const std::string report = testing_cli::slurp(dir_ / "r.json");
  EXPECT_NE(report.find("\"target\": \"atlas\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"in_domain\": "), std::string::npos) << report;
  EXPECT_NE(report.find("\"mean_alpha\": "), std::string::npos) << report;
}

TEST_F(LayersAtlasCli, BaseMeshIsTheMeshTextureWhereNoLayerReaches) {
  // The base: the bunny's Earth atlas (OBJ + MTL + PNG, baked by texbake).
  const std::string bunny = q(kData + "/bunny00.off");
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + " --texture " + q(kData + "/earth.jpg") + kSphereFlags +
                  " --uv generate --size 256 -q -o " + q(dir_ / "base.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  write_decal();
  write("L.json", R"({"base":"mesh","layers":[{"proxy":{"kind":"plane","origin":[-0.1,-0.1,0],)"
                  R"("u_axis":[0.2,0,0],"v_axis":[0,0.2,0]},"texture":"decal.png"}]})");
  // --size defaults to the base texture's (256).
  r = run_texbake("bake " + q(dir_ / "base.obj") + " --layers " + q(dir_ / "L.json") +
                  " --uv mesh -q -o " + q(dir_ / "out.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Where the decal reaches: the same decal over base "none" (its alpha).
  write("N.json", R"({"layers":[{"proxy":{"kind":"plane","origin":[-0.1,-0.1,0],)"
                  R"("u_axis":[0.2,0,0],"v_axis":[0,0.2,0]},"texture":"decal.png"}]})");
  r = run_texbake("bake " + q(dir_ / "base.obj") + " --layers " + q(dir_ / "N.json") +
                  " --uv mesh --size 256 -q -o " + q(dir_ / "reach.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image base = image(dir_ / "base.png"), out = image(dir_ / "out.png"),
              reach = image(dir_ / "reach.png");
  ASSERT_EQ(out.width, 256);
  ASSERT_EQ(base.width, 256);
  ASSERT_EQ(reach.width, 256);
  std::size_t kept = 0, lighter = 0;
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 256; ++x) {
      if (level(base, x, y, 3) < 255) continue;              // the base's background
      EXPECT_EQ(level(out, x, y, 3), 255) << x << "," << y;  // an opaque base stays opaque
      const int a = level(reach, x, y, 3);
      for (int c = 0; c < 3; ++c) {
        const int o = level(out, x, y, c), b = level(base, x, y, c);
        if (a == 0) {
          // Not reached: the base texture's texel, within 1 level.
          ASSERT_NEAR(o, b, 1) << "texel " << x << "," << y;
        } else if (a == 128 && b < 250) {
          // Wholly reached (a = 0.5 on every sample): half white over the base.
          ASSERT_GT(o, b + 1) << "texel " << x << "," << y;
        }
      }
      kept += a == 0;
      lighter += a == 128;
    }
  }
  EXPECT_GT(lighter, 50u);
  EXPECT_GT(kept, 20 * lighter);
  // A texture base needs the mesh's own UVs.
  r = run_texbake("bake " + q(dir_ / "base.obj") + " --layers " + q(dir_ / "L.json") +
                  " --uv generate -q -o " + q(dir_ / "gen.obj"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--uv mesh"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "gen.obj"));
  EXPECT_FALSE(fs::exists(dir_ / "gen.png"));
}

TEST_F(LayersAtlasCli, CoverageIsThePngAlphaAndTheGlbAlphaMode) {
  const std::string bunny = q(kData + "/bunny00.off");
  write("half.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                         kData + R"(/earth.jpg","opacity":0.5,"visibility":"all"}]})");
  testing_cli::RunResult r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "half.json") +
                                         " --uv generate --size 128 -q -o " + q(dir_ / "half.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image half = image(dir_ / "half.png");
  // Every sample is seen with a = 0.5: covered texels (and the padding
  // rings, which copy them) have alpha 0.5 = 128 / 255; the background 0.
  std::size_t covered = 0;
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 128; ++x) {
      const int a = level(half, x, y, 3);
      ASSERT_TRUE(a == 0 || a == 128) << a << " at " << x << "," << y;
      covered += a == 128;
    }
  }
  EXPECT_GT(covered, 5000u);
  // The OBJ's MTL names the PNG as map_d too (SPEC section 7, issue #28
  // item 15: without it Blender draws the RGB of uncovered texels opaque).
  EXPECT_EQ(testing_cli::slurp(dir_ / "half.mtl"),
            "# written by texbake\nnewmtl texbake\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\n"
            "map_Kd half.png\nmap_d half.png\n");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "half.json") +
                  " --uv generate --size 128 -q -o " + q(dir_ / "half.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing_cli::slurp(dir_ / "half.glb").find("\"alphaMode\":\"BLEND\""),
            std::string::npos);
  // An opaque result stays OPAQUE (the background's alpha 0 does not count).
  write("full.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                         kData + R"(/earth.jpg","visibility":"all"}]})");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "full.json") +
                  " --uv generate --size 128 -q -o " + q(dir_ / "full.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(testing_cli::slurp(dir_ / "full.glb").find("BLEND"), std::string::npos);
  // ... and its OBJ has no map_d.
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "full.json") +
                  " --uv generate --size 128 -q -o " + q(dir_ / "full.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(testing_cli::slurp(dir_ / "full.mtl").find("map_d"), std::string::npos);
}

// Issue #28 item 15, checked in Blender itself when it is installed
// (Debian's blender 3.4; skipped otherwise): importing a layers OBJ over
// base "none" gives a material that blends (blend_method BLEND) with the
// atlas image's Alpha output linked to the Principled BSDF's Alpha, its
// Color to Base Color; the opaque result's material stays OPAQUE, alpha
// unlinked.
TEST_F(LayersAtlasCli, BlenderImportsTheCoverageAsAlpha) {
  if (std::system("blender --version >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "blender is not installed (apt-get install blender): the MTL is checked by "
                    "CoverageIsThePngAlphaAndTheGlbAlphaMode";
  }
  const std::string bunny = q(kData + "/bunny00.off");
  write("half.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                         kData + R"(/earth.jpg","opacity":0.5,"visibility":"all"}]})");
  write("full.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                         kData + R"(/earth.jpg","visibility":"all"}]})");
  for (const char* name : {"half", "full"}) {
    testing_cli::RunResult r =
        run_texbake("bake " + bunny + " --layers " + q(dir_ / (std::string(name) + ".json")) +
                    " --uv generate --size 64 -q -o " + q(dir_ / (std::string(name) + ".obj")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  write("check.py", R"(import bpy, sys
for name in sys.argv[sys.argv.index("--") + 1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=name)
    for m in bpy.data.materials:
        links = sorted(l.from_node.type + "." + l.from_socket.name + ">" + l.to_socket.name
                       for l in m.node_tree.links if l.from_node.type == "TEX_IMAGE")
        print("RESULT", m.blend_method, ",".join(links))
)");
  const testing_cli::RunResult b =
      testing_cli::run_command("blender -b --factory-startup --python " + q(dir_ / "check.py") +
                               " -- " + q(dir_ / "half.obj") + " " + q(dir_ / "full.obj"));
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto at = b.out.find("RESULT");
  ASSERT_NE(at, std::string::npos) << b.out << b.err;
  std::string results;
  for (std::size_t i = at; (i = b.out.find("RESULT", i)) != std::string::npos; ++i) {
    results += b.out.substr(i, b.out.find('\n', i) - i) + "\n";
  }
  EXPECT_EQ(results,
            "RESULT BLEND TEX_IMAGE.Alpha>Alpha,TEX_IMAGE.Color>Base Color\n"
            "RESULT OPAQUE TEX_IMAGE.Color>Base Color\n");
}

TEST_F(LayersAtlasCli, BadFlagsAndFilesAreErrorsWithNoOutput) {
  const std::string bunny = q(kData + "/bunny00.off");
  write("L.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                      kData + R"(/earth.jpg"}]})");
  const std::string layers = " --layers " + q(dir_ / "L.json");
  const fs::path out = dir_ / "o.obj";
  auto no_output = [&] {
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(dir_ / "o.mtl"));
    EXPECT_FALSE(fs::exists(dir_ / "o.png"));
  };
  struct Case {
    std::string flags, message;
  };
  for (const Case& c : std::vector<Case>{
           {" --uv proxy", "--uv proxy needs a proxy"},
           {" --samples 300", "--samples 300 is out of range for an atlas"},
           {" --size 0", "--size 0"},
           {" --padding x", "--padding 'x'"},
           {" --ascii", "--ascii applies to --target vertex only"},
           {" --texture " + q(kData + "/earth.jpg"), "--texture does not apply to --layers"},
       }) {
    const testing_cli::RunResult r =
        run_texbake("bake " + bunny + layers + " -q " + c.flags + " -o " + q(out));
    EXPECT_EQ(r.exit_code, 2) << c.flags << ": " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.flags << ": " << r.err;
    no_output();
  }
  // A GLB embeds PNG only; --size on the vertex target is a usage error too.
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + layers + " --format exr -q -o " + q(dir_ / "o.glb"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("exr"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "o.glb"));
  r = run_texbake("bake " + bunny + layers + " --size 64 -q -o " + q(dir_ / "o.ply"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--size applies to --target atlas only"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "o.ply"));
  // A layer image that is not there, and base "mesh" on a mesh with neither
  // texture nor colours: the input's fault (exit 1).
  write("missing.json",
        std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":"nowhere.png"}]})");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "missing.json") +
                  " --uv generate --size 64 -q -o " + q(out));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("nowhere.png"), std::string::npos) << r.err;
  no_output();
  write("M.json", std::string(R"({"base":"mesh","layers":[{"proxy":)") + kEarthSphere +
                      R"(,"texture":")" + kData + R"(/earth.jpg"}]})");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "M.json") +
                  " --uv generate --size 64 -q -o " + q(out));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("neither a texture nor vertex colours"), std::string::npos) << r.err;
  no_output();
}

TEST_F(LayersAtlasCli, OneAndTwoThreadsGiveTheSameAtlas) {
  const std::string bunny = q(kData + "/bunny00.off");
  write_decal();
  write("L.json", std::string(R"({"base":[0.2,0.4,0.6,1],"layers":[{"proxy":)") + kEarthSphere +
                      R"(,"texture":")" + kData +
                      R"(/earth.jpg","opacity":0.7,"angle_fade":[40,80]},)"
                      R"({"proxy":{"kind":"plane","origin":[-0.1,-0.1,0],)"
                      R"("u_axis":[0.2,0,0],"v_axis":[0,0.2,0]},"texture":"decal.png",)"
                      R"("mode":"multiply"}]})");
  for (int threads : {1, 2}) {
    const std::string n = std::to_string(threads);
    const testing_cli::RunResult r =
        run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") +
                    " --uv generate --size 256 --samples 9 --threads " + n + " -q --report " +
                    q(dir_ / ("r" + n + ".json")) + " -o " + q(dir_ / ("t" + n + ".obj")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  // Byte for byte (compared as a bool: gtest's diff of two large strings is
  // quadratic). The OBJs differ only in their material's name.
  const std::string png1 = testing_cli::slurp(dir_ / "t1.png");
  EXPECT_GT(png1.size(), 1000u);
  EXPECT_TRUE(png1 == testing_cli::slurp(dir_ / "t2.png"));
  // The reports agree on every count (timings aside): the layers' entries.
  auto layers_part = [&](const std::string& name) {
    const std::string text = testing_cli::slurp(dir_ / name);
    const std::size_t a = text.find("\"layers\": ["), b = text.find("\"timings\"", a);
    return text.substr(a, b - a);
  };
  EXPECT_EQ(layers_part("r1.json"), layers_part("r2.json"));
}

TEST_F(LayersAtlasCli, OverlappingMeshUvsTakeTheSurfaceTheLayerSees) {
  // Two unit squares sharing their UVs, the hidden one (z = 0, behind the
  // other as the plane's rays go towards +z) first in the file: each shared
  // texel takes the visible square's colour, as the proxy atlas gives it,
  // not the lowest-index (hidden) triangle's --occluded colour.
  write("squares.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 5/1 6/2 7/3\nf 5/1 7/3 8/4\n");
  Image green;
  green.width = green.height = 2;
  for (int i = 0; i < 4; ++i) green.pixels.insert(green.pixels.end(), {0.f, 0.6f, 0.f, 1.f});
  ASSERT_TRUE(write_image(dir_ / "green.png", green.view()));
  write("L.json", R"({"layers":[{"proxy":{"kind":"plane","origin":[0,0,0],)"
                  R"("u_axis":[1,0,0],"v_axis":[0,1,0]},"texture":"green.png"}]})");
  testing_cli::RunResult r =
      run_texbake("bake " + q(dir_ / "squares.obj") + " --layers " + q(dir_ / "L.json") +
                  " --uv mesh --size 16 --padding 0 --occluded 1,0,0 -o " + q(dir_ / "out.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Every texel centre but the 16 on the squares' diagonal (an edge, not
  // inside) lies inside two triangles.
  EXPECT_NE(r.err.find("240 atlas texels are covered by overlapping UV triangles"),
            std::string::npos)
      << r.err;
  // Opaque everywhere: written without an alpha channel.
  Expected<Image> out = read_image(dir_ / "out.png");
  ASSERT_TRUE(out) << out.error().message;
  EXPECT_FALSE(out->has_alpha);
  ASSERT_EQ(out->width, 16);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      ASSERT_EQ(level(*out, x, y, 0), 0) << x << "," << y;
      ASSERT_EQ(level(*out, x, y, 1), 153) << x << "," << y;
      ASSERT_EQ(level(*out, x, y, 2), 0) << x << "," << y;
      ASSERT_EQ(level(*out, x, y, 3), 255) << x << "," << y;
    }
  }
}

}  // namespace
}  // namespace texbake
