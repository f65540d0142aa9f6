// texbake bake --filter ewa through the built binary (issue #16 item 2): a
// constant image bakes to that constant on both targets; a fine
// checkerboard (4096 x 2048, 4-texel squares) onto the bunny through a
// sphere at a coarse atlas (256) gives nearly its mean where the bilinear
// bake aliases; the report names the filter; --filter area is the vertex
// target's only.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::run_texbake;

std::string q(const fs::path& p) {
  return testing_cli::shell_quote(p.string());
}

class BakeEwaCli : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing_cli::fresh_test_dir("ewa_cli"); }
  void TearDown() override { fs::remove_all(dir_); }

  std::string bunny_sphere(const fs::path& texture) const {
    return "bake " + q(fs::path(TEXBAKE_DATA_DIR) / "bunny00.off") + " --texture " + q(texture) +
           " --proxy sphere --center 0,0,0 --radius 1 --up y --visibility all -q";
  }

  fs::path dir_;
};

struct Stats {
  std::size_t count = 0;
  double mean = 0, rms = 0;  // red channel; rms about 0.5
};

// Red over the atlas's opaque (baked) texels.
Stats opaque_red(const fs::path& png) {
  Stats s;
  Expected<Image> img = read_image(png);
  EXPECT_TRUE(img.has_value()) << png;
  if (!img) return s;
  double sum = 0, sq = 0;
  for (std::size_t t = 0; t < img->pixels.size() / 4; ++t) {
    if (img->pixels[t * 4 + 3] != 1) continue;
    const double r = img->pixels[t * 4];
    sum += r;
    sq += (r - 0.5) * (r - 0.5);
    ++s.count;
  }
  s.mean = sum / s.count;
  s.rms = std::sqrt(sq / s.count);
  return s;
}

TEST_F(BakeEwaCli, ConstantImageIsThatConstantOnBothTargets) {
  // 77, 153, 230 / 255.
  std::vector<unsigned char> rgb;
  for (int i = 0; i < 64 * 32; ++i) rgb.insert(rgb.end(), {77, 153, 230});
  testing_cli::write_ppm(dir_ / "c.ppm", 64, 32, rgb);
  const testing_cli::RunResult a = run_texbake(bunny_sphere(dir_ / "c.ppm") +
                                               " --filter ewa --target atlas --size 128 "
                                               "--uv proxy --padding 0 -o " +
                                               q(dir_ / "a.obj"));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  // The 8-bit values as read_image scales them (the same for the PPM and the PNG).
  Expected<Image> input = read_image(dir_ / "c.ppm");
  ASSERT_TRUE(input.has_value());
  const float* c = input->pixels.data();
  Expected<Image> atlas = read_image(dir_ / "a.png");
  ASSERT_TRUE(atlas.has_value());
  std::size_t opaque = 0;
  for (std::size_t t = 0; t < atlas->pixels.size() / 4; ++t) {
    if (atlas->pixels[t * 4 + 3] != 1) continue;
    ++opaque;
    ASSERT_EQ(atlas->pixels[t * 4 + 0], c[0]) << t;
    ASSERT_EQ(atlas->pixels[t * 4 + 1], c[1]) << t;
    ASSERT_EQ(atlas->pixels[t * 4 + 2], c[2]) << t;
  }
  EXPECT_GT(opaque, 5000u);

  const testing_cli::RunResult v =
      run_texbake(bunny_sphere(dir_ / "c.ppm") + " --filter ewa -o " + q(dir_ / "v.ply"));
  ASSERT_EQ(v.exit_code, 0) << v.err;
  Expected<LoadedMesh> mesh = read_mesh(dir_ / "v.ply");
  ASSERT_TRUE(mesh.has_value());
  ASSERT_EQ(mesh->mesh.vertex_colors.size(), 37706u);
  for (const auto& vc : mesh->mesh.vertex_colors) {
    // The PLY's 8-bit colours (read_mesh scales them its own way).
    ASSERT_EQ(std::lround(vc[0] * 255), 77);
    ASSERT_EQ(std::lround(vc[1] * 255), 153);
    ASSERT_EQ(std::lround(vc[2] * 255), 230);
  }
}

TEST_F(BakeEwaCli, FineCheckerboardOnACoarseAtlasIsItsMeanWhereBilinearAliases) {
  // 4096 x 2048, 4-texel squares: 1024 x 512 squares, mean 0.5. The bunny's
  // 256 x 256 proxy layout puts about 16 x 8 image texels under an atlas
  // texel near the equator.
  const int w = 4096, h = 2048;
  std::vector<unsigned char> rgb(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const unsigned char c = ((x / 4 + y / 4) % 2) ? 255 : 0;
      for (int k = 0; k < 3; ++k) rgb[(static_cast<std::size_t>(y) * w + x) * 3 + k] = c;
    }
  }
  testing_cli::write_ppm(dir_ / "checker.ppm", w, h, rgb);
  const std::string common =
      bunny_sphere(dir_ / "checker.ppm") + " --target atlas --size 256 --uv proxy --padding 0 ";
  const testing_cli::RunResult b =
      run_texbake(common + "--filter bilinear -o " + q(dir_ / "b.obj"));
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const testing_cli::RunResult e = run_texbake(common + "--filter ewa --report " +
                                               q(dir_ / "e.json") + " -o " + q(dir_ / "e.obj"));
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const Stats sb = opaque_red(dir_ / "b.png"), se = opaque_red(dir_ / "e.png");
  ASSERT_EQ(sb.count, se.count);
  // Measured, rms about the mean over the 62954 baked texels (4 supersamples
  // per texel, the default): bilinear 0.105 (0.222 at --samples 1, 0.027 at
  // 16), ewa 0.0043 (0.0029 at --samples 1).
  EXPECT_GT(sb.rms, 0.08);
  EXPECT_LT(se.rms, 0.01);
  EXPECT_NEAR(se.mean, 0.5, 0.005);
  const nlohmann::json j = nlohmann::json::parse(testing_cli::slurp(dir_ / "e.json"));
  EXPECT_EQ(j["inputs"]["options"]["filter"], "ewa");
}

TEST_F(BakeEwaCli, ResultsDoNotDependOnTheThreadCount) {
  std::vector<unsigned char> rgb;
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 512; ++x) {
      const unsigned char c = ((x / 3 + y / 3) % 2) ? 230 : 20;
      rgb.insert(rgb.end(), {c, static_cast<unsigned char>(x / 2), static_cast<unsigned char>(y)});
    }
  }
  testing_cli::write_ppm(dir_ / "t.ppm", 512, 256, rgb);
  for (const std::string target : {"v.ply", "a.obj"}) {
    std::string files[2];
    for (int threads : {1, 2}) {
      const fs::path out = dir_ / (std::to_string(threads) + target);
      const std::string atlas = target == "a.obj" ? " --size 128 --uv proxy" : "";
      const testing_cli::RunResult r =
          run_texbake(bunny_sphere(dir_ / "t.ppm") + " --filter ewa" + atlas + " --threads " +
                      std::to_string(threads) + " -o " + q(out));
      ASSERT_EQ(r.exit_code, 0) << r.err;
      fs::path written = out;
      if (target == "a.obj") written.replace_extension(".png");
      files[threads - 1] = testing_cli::slurp(written);
    }
    EXPECT_FALSE(files[0].empty());
    EXPECT_EQ(files[0], files[1]) << target;
  }
}

TEST_F(BakeEwaCli, AreaFilterIsTheVertexTargetsOnly) {
  std::vector<unsigned char> rgb(8 * 4 * 3, 128);
  testing_cli::write_ppm(dir_ / "g.ppm", 8, 4, rgb);
  const testing_cli::RunResult r = run_texbake(
      bunny_sphere(dir_ / "g.ppm") + " --filter area --target atlas -o " + q(dir_ / "a.obj"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("texbake: error: --filter area applies to --target vertex only"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "a.obj"));
  EXPECT_FALSE(fs::exists(dir_ / "a.png"));
}

}  // namespace
}  // namespace texbake
