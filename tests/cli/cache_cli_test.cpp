// --cache-mb through the built binary (issue #16 item 1, SPEC section 13):
// a texture over the budget is read through OpenImageIO's ImageCache and
// the outputs are byte-identical to the in-memory bake, per vertex
// (bilinear, area with --linear, ewa), on the atlas and in a render; the
// report says which path read the image; --filter ewa whose MIP levels do
// not fit the budget is a usage error; a tile lost in the middle of the
// file fails the bake naming the file, with no output.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "run_texbake.h"
#include "tests/mesh_io/tiff_bytes.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::quoted;
using testing_cli::run_texbake;
using testing_cli::slurp;

class CacheCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_cli::fresh_test_dir("cache_cli");
    // 1024 x 512 RGB noise (8 MiB as float RGBA): any texel read
    // differently changes the outputs.
    texture_ = dir_ / "noise.png";
    std::mt19937 rng(11);
    std::vector<unsigned char> rgb(1024 * 512 * 3);
    for (unsigned char& c : rgb) c = static_cast<unsigned char>(rng() & 255);
    auto out = OIIO::ImageOutput::create(texture_.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(texture_.string(), OIIO::ImageSpec(1024, 512, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data()));
    ASSERT_TRUE(out->close());
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string bake(const fs::path& texture, const fs::path& output,
                   const std::string& extra) const {
    return "bake " + quoted(fs::path(TEXBAKE_DATA_DIR) / "bunny00.off") + " --texture " +
           quoted(texture) + " --proxy sphere --center 0,0,0 --radius 1 --up y -q -o " +
           quoted(output) + " " + extra;
  }

  // Bakes with the default budget and with `budget`; expects identical
  // output bytes, the first in memory and the second through the cache.
  void expect_same_both_ways(const std::string& name, const std::string& options,
                             const std::string& budget = "--cache-mb 1") {
    SCOPED_TRACE(name + " " + options);
    // Same names in two folders: an OBJ names its MTL, the MTL its PNG.
    fs::create_directories(dir_ / "memory");
    fs::create_directories(dir_ / "cached");
    const fs::path a = dir_ / "memory" / name, b = dir_ / "cached" / name;
    const fs::path ra = dir_ / (name + "_memory.json"), rb = dir_ / (name + "_cached.json");
    auto r1 = run_texbake(bake(texture_, a, options + " --report " + quoted(ra)));
    ASSERT_EQ(r1.exit_code, 0) << r1.err;
    auto r2 = run_texbake(bake(texture_, b, options + " " + budget + " --report " + quoted(rb)));
    ASSERT_EQ(r2.exit_code, 0) << r2.err;
    const std::string bytes = slurp(a);
    ASSERT_GT(bytes.size(), 1000u);
    EXPECT_TRUE(bytes == slurp(b)) << "outputs differ";
    if (a.extension() == ".obj") {
      EXPECT_TRUE(slurp(a.parent_path() / (a.stem().string() + ".png")) ==
                  slurp(b.parent_path() / (b.stem().string() + ".png")))
          << "atlases differ";
    }
    const auto image_a = nlohmann::json::parse(slurp(ra))["inputs"]["image"];
    const auto image_b = nlohmann::json::parse(slurp(rb))["inputs"]["image"];
    EXPECT_EQ(image_a["cached"], false);
    EXPECT_EQ(image_b["cached"], true);
    EXPECT_EQ(image_b["width"], 1024);
    EXPECT_EQ(image_b["height"], 512);
  }

  fs::path dir_, texture_;
};

TEST_F(CacheCli, VertexBakesAreByteIdenticalThroughTheCache) {
  expect_same_both_ways("bilinear.ply", "--filter bilinear");
  expect_same_both_ways("area.ply", "--filter area --linear");
}

TEST_F(CacheCli, AtlasBakeIsByteIdenticalThroughTheCache) {
  expect_same_both_ways("atlas.obj", "--target atlas --uv proxy --size 256 --samples 4");
}

TEST_F(CacheCli, EwaNeedsItsMipLevelsWithinTheBudget) {
  // The levels above 1024 x 512 hold 2.7 MiB: refused at 1 MiB (exit 2,
  // nothing written), baked at 4 MiB through the cache (10.7 MiB with the
  // image) exactly as in memory.
  const fs::path out = dir_ / "refused.ply";
  auto r = run_texbake(bake(texture_, out, "--filter ewa --cache-mb 1"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("texbake: error: --filter ewa keeps the MIP levels of the 1024 x 512 "
                       "texture in memory (3 MiB), more than --cache-mb 1"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
  expect_same_both_ways("ewa.ply", "--filter ewa", "--cache-mb 4");
}

// Writes the 1024 x 512 noise of `texture` as an 8-bit TIFF, with MIP levels
// 512 x 256 .. 1 x 1 of the constant colour (200, 40, 90) when `levels`
// (as maketx lays a texture out: further directories of a file marked as a
// texture). The levels are deliberately not the noise's average (about
// 127.5 a channel), so an atlas texel tells which pyramid it came from.
void write_tiff(const fs::path& texture, const fs::path& path, bool levels) {
  auto in = OIIO::ImageInput::open(texture.string());
  ASSERT_TRUE(in);
  std::vector<unsigned char> rgb(1024 * 512 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data()));
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  for (int w = 1024, h = 512, l = 0; l == 0 || (levels && (w > 1 || h > 1)); ++l) {
    if (l > 0) {
      w = std::max(1, w / 2);
      h = std::max(1, h / 2);
      rgb.clear();
      for (int i = 0; i < w * h; ++i) rgb.insert(rgb.end(), {200, 40, 90});
    }
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    spec.tile_width = spec.tile_height = 64;
    if (levels) spec.attribute("textureformat", "Plain Texture");
    ASSERT_TRUE(l == 0 ? out->open(path.string(), spec)
                       : out->open(path.string(), spec, OIIO::ImageOutput::AppendSubimage))
        << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data())) << out->geterror();
  }
  ASSERT_TRUE(out->close());
}

// The atlas texels of `png` equal to (200, 40, 90).
int level_colour_texels(const fs::path& png) {
  auto in = OIIO::ImageInput::open(png.string());
  if (!in) return -1;
  const int w = in->spec().width, h = in->spec().height, nc = in->spec().nchannels;
  std::vector<unsigned char> px(static_cast<std::size_t>(w) * h * nc);
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, px.data())) return -1;
  int n = 0;
  for (std::size_t i = 0; i < px.size(); i += nc) {
    n += px[i] == 200 && px[i + 1] == 40 && px[i + 2] == 90;
  }
  return n;
}

TEST_F(CacheCli, EwaReadsAMipMappedFilesOwnLevelsInMemoryAndThroughTheCache) {
  const fs::path mip = dir_ / "mip.tif", plain = dir_ / "plain.tif";
  write_tiff(texture_, mip, true);
  write_tiff(texture_, plain, false);
  // A 32 x 32 atlas: every texel's footprint covers many image texels, so
  // its lookups read levels >= 1 only, all (200, 40, 90).
  const std::string atlas =
      "--target atlas --uv generate --size 32 --samples 1 --visibility all --filter ewa";
  for (const char* sub : {"memory", "cached", "plain", "linear", "plain_linear"}) {
    fs::create_directories(dir_ / sub);
  }
  auto run = [&](const fs::path& texture, const std::string& sub, const std::string& extra) {
    auto r = run_texbake(bake(texture, dir_ / sub / "a.obj", atlas + " " + extra));
    EXPECT_EQ(r.exit_code, 0) << sub << ": " << r.err;
    return slurp(dir_ / sub / "a.png");
  };
  const std::string memory = run(mip, "memory", "--report " + quoted(dir_ / "memory.json"));
  // 512 x 256 .. 1 x 1: ten levels, taken from the file.
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "memory.json"))["inputs"]["image"]["mip_levels"],
            10);
  // Through the cache the levels are read from the file too (no pyramid
  // is built, so even 1 MiB is enough), with the same bytes.
  const std::string cached = run(mip, "cached", "--cache-mb 1");
  EXPECT_TRUE(memory == cached) << "the cache read other levels";
  const int n = level_colour_texels(dir_ / "memory" / "a.png");
  EXPECT_GT(n, 32 * 32 / 4);  // the baked texels and their padding
  // The same texels without the file's levels: the reduced noise, never
  // exactly the levels' colour.
  run(plain, "plain", "");
  EXPECT_EQ(level_colour_texels(dir_ / "plain" / "a.png"), 0);
  // --linear of this sRGB texture needs linear-light levels: the file's
  // (averages of the stored values) are not used, the bake is the plain one.
  EXPECT_TRUE(run(mip, "linear", "--linear --report " + quoted(dir_ / "linear.json")) ==
              run(plain, "plain_linear", "--linear"));
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "linear.json"))["inputs"]["image"]["mip_levels"], 0);
}

TEST_F(CacheCli, RenderOfTheProjectionIsByteIdenticalThroughTheCache) {
  const std::string common = "render " + quoted(fs::path(TEXBAKE_DATA_DIR) / "bunny00.off") +
                             " --texture " + quoted(texture_) +
                             " --proxy sphere --center 0,0,0 --radius 1 --up y --size 160x120";
  auto r1 = run_texbake(common + " -o " + quoted(dir_ / "a.png"));
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  auto r2 = run_texbake(common + " --cache-mb 1 -o " + quoted(dir_ / "b.png"));
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  EXPECT_TRUE(slurp(dir_ / "a.png") == slurp(dir_ / "b.png"));
}

TEST_F(CacheCli, ATileLostInTheMiddleFailsTheBakeNamingTheFile) {
  // 256 x 128 in 64-texel tiles; tile 2 of the top row is not in the file.
  // The sphere reads the whole map, so the bake reaches it.
  const fs::path tif = dir_ / "hole.tif";
  std::ofstream(tif, std::ios::binary) << test::tiled_tiff(
      {256, 128, 64, {2}, false}, [](int x, int y, int c) { return (x + y + 40 * c) & 255; });
  for (const std::string target : {"vertex.ply", "atlas.obj"}) {
    const fs::path out = dir_ / target;
    auto r = run_texbake(bake(tif, out, "--cache-mb 1 --visibility all --filter bilinear"));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("texbake: error: " + tif.string() + ": cannot decode"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST_F(CacheCli, LayersTexturesAndMasksAreReadThroughTheCacheAlike) {
  // An RGBA layer texture of random alpha (premultiplied as its tiles load)
  // and a grey mask, over a colour base; vertex and atlas targets.
  std::mt19937 rng(12);
  auto write = [&](const fs::path& path, int w, int h, int nc) {
    std::vector<unsigned char> v(static_cast<std::size_t>(w) * h * nc);
    for (unsigned char& c : v) c = static_cast<unsigned char>(rng() & 255);
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, nc, OIIO::TypeDesc::UINT8);
    if (nc == 4) spec.alpha_channel = 3;
    ASSERT_TRUE(out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, v.data()));
    ASSERT_TRUE(out->close());
  };
  write(dir_ / "layer.png", 600, 300, 4);
  write(dir_ / "mask.png", 512, 256, 1);  // 2 MiB as float RGBA: cached too
  std::ofstream(dir_ / "layers.json")
      << R"({"base": [0.2, 0.4, 0.6, 1], "layers": [{"proxy": {"kind": "sphere", )"
      << R"("center": [0, 0, 0], "radius": 1, "pole": [0, 1, 0], "equator": [0, 0, 1]}, )"
      << R"("texture": "layer.png", "mask": "mask.png", "visibility": "all"}]})";
  const std::string mesh = quoted(fs::path(TEXBAKE_DATA_DIR) / "bunny00.off");
  for (const std::string name : {"layers.ply", "layers.obj"}) {
    const std::string extra = name == "layers.obj" ? " --size 256 --uv generate" : "";
    fs::create_directories(dir_ / "m");
    fs::create_directories(dir_ / "c");
    auto r1 = run_texbake("bake " + mesh + " --layers " + quoted(dir_ / "layers.json") + extra +
                          " -q -o " + quoted(dir_ / "m" / name));
    ASSERT_EQ(r1.exit_code, 0) << r1.err;
    auto r2 = run_texbake("bake " + mesh + " --layers " + quoted(dir_ / "layers.json") + extra +
                          " --cache-mb 1 -q -o " + quoted(dir_ / "c" / name));
    ASSERT_EQ(r2.exit_code, 0) << r2.err;
    EXPECT_TRUE(slurp(dir_ / "m" / name) == slurp(dir_ / "c" / name)) << name;
    if (name == "layers.obj") {
      EXPECT_TRUE(slurp(dir_ / "m" / "layers.png") == slurp(dir_ / "c" / "layers.png"));
    }
  }
}

TEST_F(CacheCli, PhotosRefuseCacheMb) {
  // Photos are read whole: the flag would do nothing, so it is refused (exit 2).
  auto r =
      run_texbake("bake " + quoted(fs::path(TEXBAKE_DATA_DIR) / "bunny00.off") + " --cameras " +
                  quoted(dir_) + " --cache-mb 64 -q -o " + quoted(dir_ / "p.ply"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--cache-mb does not apply to --cameras"), std::string::npos) << r.err;
}

TEST_F(CacheCli, CacheMbOutOfRangeIsAUsageError) {
  auto r = run_texbake(bake(texture_, dir_ / "x.ply", "--cache-mb 0"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--cache-mb"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace texbake
