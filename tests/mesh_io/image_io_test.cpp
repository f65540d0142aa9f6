// image_io: images made by hand here (PNG with stored deflate blocks, PGM/PPM,
// PFM), so the expected values are the bytes written, independent of OIIO.
#include "mesh_io/image_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "mapping/sample.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

uint32_t crc32(const std::string& s) {  // PNG's CRC (ISO 3309), bitwise
  uint32_t c = 0xffffffffu;
  for (unsigned char b : s) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

std::string be32(uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
          static_cast<char>(v)};
}

// A PNG of `channels` (1 gray, 2 gray+alpha, 3 RGB, 4 RGBA) at 8 or 16 bits
// from raw big-endian samples, rows top first, zlib "stored" blocks.
std::string make_png(int w, int h, int channels, int bits, const std::string& samples) {
  const int colour_type = channels == 1 ? 0 : channels == 2 ? 4 : channels == 3 ? 2 : 6;
  const std::size_t row = static_cast<std::size_t>(w) * channels * bits / 8;
  std::string raw;
  for (int y = 0; y < h; ++y) raw += '\0' + samples.substr(y * row, row);  // filter type 0
  uint32_t a = 1, b = 0;                                                   // Adler-32
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  std::string z = "\x78\x01";
  z += '\x01';  // final stored block
  const uint16_t len = static_cast<uint16_t>(raw.size()), nlen = static_cast<uint16_t>(~len);
  z += static_cast<char>(len & 0xff);
  z += static_cast<char>(len >> 8);
  z += static_cast<char>(nlen & 0xff);
  z += static_cast<char>(nlen >> 8);
  z += raw + be32((b << 16) | a);
  auto chunk = [](const std::string& type, const std::string& data) {
    return be32(static_cast<uint32_t>(data.size())) + type + data + be32(crc32(type + data));
  };
  std::string ihdr = be32(w) + be32(h);
  ihdr += static_cast<char>(bits);
  ihdr += static_cast<char>(colour_type);
  ihdr += std::string(3, '\0');
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", z) +
         chunk("IEND", "");
}

std::string bytes(std::initializer_list<int> v) {
  std::string s;
  for (int x : v) s += static_cast<char>(x);
  return s;
}

class ImageIo : public ::testing::Test {
 protected:
  fs::path dir = test::fresh_temp_dir("image");
  void TearDown() override { fs::remove_all(dir); }

  Image load(const std::string& name, const std::string& content) {
    Expected<Image> img = read_image(test::write_text(dir / name, content));
    EXPECT_TRUE(img.has_value()) << (img ? "" : img.error().message);
    return img ? *img : Image{};
  }
  static void expect_pixel(const Image& img, int x, int y, Rgba want) {
    const float* p = img.view().pixel(x, y);
    for (int k = 0; k < 4; ++k)
      EXPECT_FLOAT_EQ(p[k], want[k]) << "pixel " << x << "," << y << " channel " << k;
  }
};

TEST_F(ImageIo, GrayPngIsReplicatedWithOpaqueAlpha) {
  Image img = load("g.png", make_png(2, 1, 1, 8, bytes({0, 51})));
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 1);
  expect_pixel(img, 0, 0, {0, 0, 0, 1});
  expect_pixel(img, 1, 0, {0.2f, 0.2f, 0.2f, 1});
}

TEST_F(ImageIo, GrayAlphaPngKeepsStoredValues) {
  // Straight (unassociated) alpha as PNG stores it: gray stays 51/255, not 51*153/255^2.
  Image img = load("ga.png", make_png(1, 1, 2, 8, bytes({51, 153})));
  expect_pixel(img, 0, 0, {0.2f, 0.2f, 0.2f, 0.6f});
}

TEST_F(ImageIo, RgbPngRowsTopFirst) {
  // 1 x 2: top row red, bottom row blue.
  Image img = load("rgb.png", make_png(1, 2, 3, 8, bytes({255, 0, 0, 0, 0, 255})));
  ASSERT_EQ(img.height, 2);
  expect_pixel(img, 0, 0, {1, 0, 0, 1});
  expect_pixel(img, 0, 1, {0, 0, 1, 1});
}

TEST_F(ImageIo, RgbaPngKeepsStraightAlpha) {
  Image img = load("rgba.png", make_png(1, 1, 4, 8, bytes({204, 102, 51, 0})));
  expect_pixel(img, 0, 0, {0.8f, 0.4f, 0.2f, 0});
}

TEST_F(ImageIo, SixteenBitPngScaledBy65535) {
  // RGB samples 65535, 0, 32768 (big-endian).
  Image img = load("16.png", make_png(1, 1, 3, 16, bytes({0xff, 0xff, 0, 0, 0x80, 0x00})));
  expect_pixel(img, 0, 0, {1, 0, 32768.f / 65535.f, 1});
}

TEST_F(ImageIo, PgmAndPpm) {
  Image g = load("g.pgm", "P5\n2 1\n255\n" + bytes({255, 102}));
  expect_pixel(g, 1, 0, {0.4f, 0.4f, 0.4f, 1});
  Image c = load("c.ppm", "P6\n1 1\n255\n" + bytes({64, 255, 1}));
  expect_pixel(c, 0, 0, {64.f / 255.f, 1, 1.f / 255.f, 1});
}

TEST_F(ImageIo, FloatPfmKeepsValuesAndRowOrder) {
  // PFM stores the bottom row first; scale -1 means little-endian floats.
  const float rows[2][3] = {{2.5f, 0.f, 1.f}, {0.25f, -1.f, 4.f}};  // bottom, then top
  std::string s = "PF\n1 2\n-1.0\n";
  s.append(reinterpret_cast<const char*>(rows), sizeof rows);
  Image img = load("f.pfm", s);
  expect_pixel(img, 0, 0, {0.25f, -1.f, 4.f, 1});  // top row
  expect_pixel(img, 0, 1, {2.5f, 0.f, 1.f, 1});
}

Image ramp(int w, int h, bool alpha) {
  Image img;
  img.width = w;
  img.height = h;
  img.pixels.resize(static_cast<std::size_t>(w) * h * 4);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    img.pixels[i] = static_cast<float>(i % 257) / 256.f;
    if (i % 4 == 3 && !alpha) img.pixels[i] = 1;
  }
  return img;
}

TEST_F(ImageIo, WritePng8RoundsToNearest) {
  Image img = ramp(5, 3, true);
  ASSERT_TRUE(write_image(dir / "o.png", img.view()).has_value());
  Expected<Image> back = read_image(dir / "o.png");
  ASSERT_TRUE(back.has_value()) << back.error().message;
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    EXPECT_FLOAT_EQ(back->pixels[i], std::round(img.pixels[i] * 255.f) / 255.f) << i;
  }
}

TEST_F(ImageIo, WritePng16AndExr) {
  Image img = ramp(4, 4, false);
  ImageWriteOptions opt;
  opt.bit_depth = ImageBitDepth::k16;
  ASSERT_TRUE(write_image(dir / "o16.png", img.view(), opt).has_value());
  Expected<Image> b16 = read_image(dir / "o16.png");
  ASSERT_TRUE(b16.has_value());
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    EXPECT_FLOAT_EQ(b16->pixels[i], std::round(img.pixels[i] * 65535.f) / 65535.f) << i;
  }
  img.pixels[0] = 3.75f;  // EXR keeps values outside [0, 1]
  ASSERT_TRUE(write_image(dir / "o.exr", img.view()).has_value());
  Expected<Image> bexr = read_image(dir / "o.exr");
  ASSERT_TRUE(bexr.has_value());
  EXPECT_EQ(bexr->pixels, img.pixels);
  // Only the finished files are left (no temporaries).
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 2u);
}

}  // namespace
}  // namespace texbake
