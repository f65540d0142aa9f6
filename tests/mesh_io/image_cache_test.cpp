// read_image with a memory budget (issue #16 item 1, SPEC section 13): past
// the budget the image is read through OpenImageIO's ImageCache, and every
// texel has the same bits as the whole decode, for tiled and scanline TIFF,
// PNG, JPEG and EXR, 8/16-bit, half and float, 1 to 4 channels; below it
// the image is decoded as before; an image past 16384 x 16384 pixels is
// refused without a budget and read with one; a file that loses tiles is
// an error naming it (at open for the first or last tile, after the pass
// for one in between).
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "mapping/sample.h"
#include "mesh_io/image_io.h"
#include "tests/mesh_io/test_files.h"
#include "tests/mesh_io/tiff_bytes.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

class ImageCacheFiles : public ::testing::Test {
 protected:
  void SetUp() override { dir = test::fresh_temp_dir("image-cache"); }
  void TearDown() override { fs::remove_all(dir); }
  fs::path dir;
};

// Writes w x h x nc random values in [0, 1] (one NaN when `nan`) as `type`,
// tiled with `tile` (0: scanlines), through OpenImageIO.
void write_random(const fs::path& path, int w, int h, int nc, OIIO::TypeDesc type, int tile,
                  unsigned seed, bool nan = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  std::vector<float> values(static_cast<std::size_t>(w) * h * nc);
  for (float& v : values) v = unit(rng);
  if (nan) values[values.size() / 2] = std::nanf("");
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out) << path;
  OIIO::ImageSpec spec(w, h, nc, type);
  if (tile > 0) spec.tile_width = spec.tile_height = tile;
  if (nc == 2) spec.alpha_channel = 1;
  ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, values.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

ImageReadOptions forced_cache() {
  ImageReadOptions o;
  o.cache_mb = 1;
  o.memory_copies = 1e6;  // every image is over the budget
  return o;
}

bool same_bits(const Rgba& a, const Rgba& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST_F(ImageCacheFiles, EveryLayoutReadsTheSameBitsThroughTheCache) {
  struct Case {
    const char* name;
    int nc;
    OIIO::TypeDesc type;
    int tile;
    bool nan;
  };
  const Case cases[] = {
      {"tiled8.tif", 3, OIIO::TypeDesc::UINT8, 64, false},
      {"tiled16_rgba.tif", 4, OIIO::TypeDesc::UINT16, 32, false},  // tiles unlike the cache's
      {"scan16_grey.tif", 1, OIIO::TypeDesc::UINT16, 0, false},
      {"float_grey.tif", 1, OIIO::TypeDesc::FLOAT, 0, true},  // NaN read as 0
      {"grey_alpha.png", 2, OIIO::TypeDesc::UINT8, 0, false},
      {"rgba.png", 4, OIIO::TypeDesc::UINT8, 0, false},  // unassociated alpha kept
      {"photo.jpg", 3, OIIO::TypeDesc::UINT8, 0, false},
      {"half.exr", 3, OIIO::TypeDesc::HALF, 0, false},
      {"tiled_half.exr", 4, OIIO::TypeDesc::HALF, 64, false},
  };
  unsigned seed = 1;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path path = dir / c.name;
    const int w = 333, h = 190;  // partial tiles on the right and bottom
    write_random(path, w, h, c.nc, c.type, c.tile, seed++, c.nan);
    Expected<Image> whole = read_image(path);
    ASSERT_TRUE(whole.has_value()) << whole.error().message;
    Expected<Image> cached = read_image(path, forced_cache());
    ASSERT_TRUE(cached.has_value()) << cached.error().message;
    ASSERT_TRUE(cached->tiles);
    EXPECT_TRUE(cached->pixels.empty());
    EXPECT_FALSE(whole->tiles);
    EXPECT_EQ(cached->width, w);
    EXPECT_EQ(cached->height, h);
    EXPECT_EQ(cached->color_space, whole->color_space);
    EXPECT_EQ(cached->has_alpha, whole->has_alpha);
    const ImageView a = whole->view(), b = cached->view();
    EXPECT_EQ(b.data, nullptr);
    int differing = 0;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) differing += !same_bits(a.texel(x, y), b.texel(x, y));
    }
    EXPECT_EQ(differing, 0);
    EXPECT_TRUE(check_texels_read(b).has_value());
  }
}

TEST_F(ImageCacheFiles, TheBudgetDecidesAndNoBudgetAlwaysDecodes) {
  const fs::path path = dir / "rgb.png";
  write_random(path, 512, 512, 3, OIIO::TypeDesc::UINT8, 0, 7);  // 4 MiB as float RGBA
  ImageReadOptions o;
  o.cache_mb = 8;
  Expected<Image> fits = read_image(path, o);
  ASSERT_TRUE(fits.has_value());
  EXPECT_FALSE(fits->tiles);
  EXPECT_EQ(fits->pixels.size(), 512u * 512 * 4);
  o.memory_copies = 2;  // 8 MiB: still within
  EXPECT_FALSE(read_image(path, o)->tiles);
  o.memory_copies = 2.1;  // past it
  EXPECT_TRUE(read_image(path, o)->tiles);
  o.cache_mb = 0;  // no budget
  EXPECT_FALSE(read_image(path, o)->tiles);
}

TEST_F(ImageCacheFiles, AnImagePastTheSizeLimitIsReadThroughTheCacheOnly) {
  // 20480 x 13200 = 270 million pixels, more than 16384 x 16384; one grey
  // level per 256-texel tile, (tx + 7 ty) mod 251, deflate-compressed.
  const int w = 20480, h = 13200, t = 256;
  const fs::path path = dir / "huge.tif";
  {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, 1, OIIO::TypeDesc::UINT8);
    spec.tile_width = spec.tile_height = t;
    spec.attribute("compression", "zip");
    ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
    std::vector<unsigned char> tile(t * t);
    for (int y = 0; y < h; y += t) {
      for (int x = 0; x < w; x += t) {
        std::fill(tile.begin(), tile.end(),
                  static_cast<unsigned char>((x / t + 7 * (y / t)) % 251));
        ASSERT_TRUE(out->write_tile(x, y, 0, OIIO::TypeDesc::UINT8, tile.data()));
      }
    }
    ASSERT_TRUE(out->close());
  }
  Expected<Image> refused = read_image(path);
  ASSERT_FALSE(refused.has_value());
  EXPECT_NE(refused.error().message.find("20480 x 13200 pixels is larger than texbake reads"),
            std::string::npos)
      << refused.error().message;
  ImageReadOptions o;
  o.cache_mb = 64;
  Expected<Image> cached = read_image(path, o);
  ASSERT_TRUE(cached.has_value()) << cached.error().message;
  ASSERT_TRUE(cached->tiles);
  EXPECT_EQ(cached->width, w);
  EXPECT_EQ(cached->height, h);
  const ImageView v = cached->view();
  for (auto [x, y] :
       {std::pair{0, 0}, std::pair{20479, 13199}, std::pair{5000, 9000}, std::pair{12345, 100}}) {
    const float level = static_cast<float>((x / t + 7 * (y / t)) % 251) / 255.f;
    const Rgba texel = v.texel(x, y);
    EXPECT_NEAR(texel[0], level, 1e-7) << x << "," << y;
    EXPECT_EQ(texel[0], texel[1]);
    EXPECT_EQ(texel[0], texel[2]);
    EXPECT_EQ(texel[3], 1.f);
    // A bilinear lookup at a texel centre inside a tile is that texel.
    const UV uv{(x + 0.5) / w, 1 - (y + 0.5) / h};
    EXPECT_EQ(sample_bilinear(v, uv, WrapMode::kRepeat, WrapMode::kClamp)[0], texel[0]);
  }
  EXPECT_TRUE(check_texels_read(v).has_value());
}

auto gradient = [](int x, int y, int c) { return (x * 3 + y * 5 + c * 70) & 255; };

TEST_F(ImageCacheFiles, HandWrittenTiffReadsAsItsPixels) {
  // The hand-written file of the two tests below, whole: the reader takes it.
  const fs::path path =
      test::write_text(dir / "ok.tif", test::tiled_tiff({200, 150, 64, {}, false}, gradient));
  Expected<Image> whole = read_image(path);
  ASSERT_TRUE(whole.has_value()) << whole.error().message;
  Expected<Image> cached = read_image(path, forced_cache());
  ASSERT_TRUE(cached.has_value()) << cached.error().message;
  for (auto [x, y] : {std::pair{0, 0}, std::pair{199, 149}, std::pair{70, 80}}) {
    EXPECT_FLOAT_EQ(whole->view().texel(x, y)[1], gradient(x, y, 1) / 255.f);
    EXPECT_TRUE(same_bits(whole->view().texel(x, y), cached->view().texel(x, y)));
  }
}

TEST_F(ImageCacheFiles, ATruncatedFileIsAnErrorNamingItWhenOpened) {
  // The last of 4 x 3 tiles is gone: the probe of the last texel fails.
  const fs::path path = test::write_text(dir / "truncated.tif",
                                         test::tiled_tiff({200, 150, 64, {11}, false}, gradient));
  Expected<Image> cached = read_image(path, forced_cache());
  ASSERT_FALSE(cached.has_value());
  EXPECT_EQ(cached.error().code, ErrorCode::kParse);
  EXPECT_EQ(cached.error().message.rfind(path.string() + ": cannot decode", 0), 0u)
      << cached.error().message;
}

TEST_F(ImageCacheFiles, ALostTileInBetweenIsAnErrorNamingTheFileAfterThePass) {
  // Tile (1, 1) of 4 x 3 is gone: the file opens (first and last tiles are
  // there); reading there gives zeros and the file's error.
  const fs::path path =
      test::write_text(dir / "hole.tif", test::tiled_tiff({200, 150, 64, {5}, false}, gradient));
  Expected<Image> cached = read_image(path, forced_cache());
  ASSERT_TRUE(cached.has_value()) << cached.error().message;
  const ImageView v = cached->view();
  EXPECT_FLOAT_EQ(v.texel(10, 10)[0], gradient(10, 10, 0) / 255.f);
  EXPECT_TRUE(check_texels_read(v).has_value());
  EXPECT_TRUE(same_bits(v.texel(70, 70), Rgba{0, 0, 0, 0}));
  const Status s = check_texels_read(v);
  ASSERT_FALSE(s.has_value());
  EXPECT_EQ(s.error().message.rfind(path.string() + ": cannot decode", 0), 0u) << s.error().message;
}

}  // namespace
}  // namespace texbake

namespace texbake {
namespace {

// Writes a MIP-mapped 8-bit RGB TIFF (tiled 16, as maketx writes textures)
// of the given level sizes; texel (x, y) of level l is ((x + 3 y + 50 l)
// mod 256, l, 7) / 255.
void write_mip_tiff(const fs::path& path, const std::vector<std::pair<int, int>>& sizes) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out) << path;
  for (std::size_t l = 0; l < sizes.size(); ++l) {
    const auto [w, h] = sizes[l];
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    spec.tile_width = spec.tile_height = 16;
    std::vector<unsigned char> rgb;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        rgb.insert(rgb.end(), {static_cast<unsigned char>((x + 3 * y + 50 * l) % 256),
                               static_cast<unsigned char>(l), 7});
      }
    }
    // As maketx writes a MIP-mapped TIFF: the levels as further
    // directories of a file marked as a texture, which readers take as
    // MIP levels (OIIO's TIFF writer has no AppendMIPLevel).
    spec.attribute("textureformat", "Plain Texture");
    ASSERT_TRUE(l == 0 ? out->open(path.string(), spec)
                       : out->open(path.string(), spec, OIIO::ImageOutput::AppendSubimage))
        << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data())) << out->geterror();
  }
  ASSERT_TRUE(out->close());
}

TEST_F(ImageCacheFiles, MipLevelsOfAMipMappedFileAreReadInMemoryAndThroughTheCache) {
  // 45 x 20: levels 22 x 10, 11 x 5, 5 x 2, 2 x 1, 1 x 1 (floor halving).
  const std::vector<std::pair<int, int>> sizes = {{45, 20}, {22, 10}, {11, 5},
                                                  {5, 2},   {2, 1},   {1, 1}};
  const fs::path path = dir / "mip.tif";
  write_mip_tiff(path, sizes);
  ImageReadOptions memory;
  memory.mip_levels = true;
  ImageReadOptions cached = forced_cache();
  cached.mip_levels = true;
  Expected<Image> a = read_image(path, memory);
  Expected<Image> b = read_image(path, cached);
  ASSERT_TRUE(a) << a.error().message;
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_FALSE(a->tiles);
  EXPECT_TRUE(b->tiles);
  for (const Image* img : {&*a, &*b}) {
    ASSERT_TRUE(img->mip);
    ASSERT_EQ(img->mip->levels.size(), sizes.size() - 1);
    const ImageView v = img->view();
    ASSERT_EQ(v.mip_level_count, static_cast<int>(sizes.size()) - 1);
    for (std::size_t l = 1; l < sizes.size(); ++l) {
      const ImageView& level = v.mip_levels[l - 1];
      ASSERT_EQ(level.width, sizes[l].first);
      ASSERT_EQ(level.height, sizes[l].second);
      EXPECT_EQ(level.color_space, ColorSpace::kSrgb);
      for (int y = 0; y < level.height; ++y) {
        for (int x = 0; x < level.width; ++x) {
          const Rgba t = level.texel(x, y);
          ASSERT_FLOAT_EQ(t[0], static_cast<float>((x + 3 * y + 50 * l) % 256) / 255) << l;
          ASSERT_FLOAT_EQ(t[1], static_cast<float>(l) / 255);
          ASSERT_FLOAT_EQ(t[2], 7.f / 255);
          ASSERT_EQ(t[3], 1.f);
        }
      }
    }
  }
  // Every level's texels are the same bits both ways.
  for (std::size_t l = 0; l + 1 < sizes.size(); ++l) {
    const ImageView& la = a->view().mip_levels[l];
    const ImageView& lb = b->view().mip_levels[l];
    for (int y = 0; y < la.height; ++y) {
      for (int x = 0; x < la.width; ++x) ASSERT_TRUE(same_bits(la.texel(x, y), lb.texel(x, y)));
    }
  }
  // Without mip_levels (every filter but ewa) the levels are not read.
  Expected<Image> plain = read_image(path);
  ASSERT_TRUE(plain);
  EXPECT_FALSE(plain->mip);
  EXPECT_EQ(plain->view().mip_level_count, 0);
  // Working in linear light (--linear), an 8-bit (sRGB) file's levels are
  // not read either, both ways; a file read as linear keeps them.
  for (ImageReadOptions o : {memory, cached}) {
    o.linear_working = true;
    Expected<Image> srgb = read_image(path, o);
    ASSERT_TRUE(srgb) << srgb.error().message;
    EXPECT_EQ(srgb->color_space, ColorSpace::kSrgb);
    EXPECT_FALSE(srgb->mip);
    o.color_space = TextureColorSpace::kLinear;
    Expected<Image> linear = read_image(path, o);
    ASSERT_TRUE(linear) << linear.error().message;
    ASSERT_TRUE(linear->mip);
    EXPECT_EQ(linear->mip->levels.size(), sizes.size() - 1);
    EXPECT_EQ(linear->mip->levels[0].color_space, ColorSpace::kLinear);
  }
}

TEST_F(ImageCacheFiles, MipLevelsThatAreNotTheHalvingChainAreNotUsed) {
  ImageReadOptions o;
  o.mip_levels = true;
  // Level 1 rounded up (23 x 10, not 22 x 10), and a chain stopping at 4 x 2.
  for (const auto& sizes : {std::vector<std::pair<int, int>>{{45, 20}, {23, 10}, {11, 5}},
                            std::vector<std::pair<int, int>>{{16, 8}, {8, 4}, {4, 2}}}) {
    const fs::path path = dir / ("odd_" + std::to_string(sizes[1].first) + ".tif");
    write_mip_tiff(path, sizes);
    for (const ImageReadOptions& options : {o, [&] {
                                              ImageReadOptions c = forced_cache();
                                              c.mip_levels = true;
                                              return c;
                                            }()}) {
      Expected<Image> img = read_image(path, options);
      ASSERT_TRUE(img) << img.error().message;
      EXPECT_FALSE(img->mip) << path;
      EXPECT_EQ(img->width, sizes[0].first);
      // Level 0 is read as ever.
      EXPECT_FLOAT_EQ(img->view().texel(2, 1)[0], 5.f / 255);
    }
  }
}

}  // namespace
}  // namespace texbake
