// encode_image (PNG into memory, for the GLB atlas) and the PNG compression
// level: the in-memory bytes are exactly the file write_image writes, and
// every level decodes to the same pixels (deflate is lossless).
#include <gtest/gtest.h>

#include <cmath>

#include "mesh_io/image_io.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

// Smooth plus noisy content, so that compression levels give different bytes.
Image pattern(int w, int h, bool alpha) {
  Image img;
  img.width = w;
  img.height = h;
  img.pixels.resize(static_cast<std::size_t>(w) * h * 4);
  uint32_t state = 12345;
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    state = state * 1664525u + 1013904223u;
    const std::size_t px = i / 4;
    img.pixels[i] = static_cast<float>(((px % w) * 3 + (px / w) * 5) % 256) / 255.f +
                    ((state >> 28) & 1u ? 1.f / 255.f : 0.f);
    if (i % 4 == 3) img.pixels[i] = alpha ? static_cast<float>(px % 3) / 2.f : 1.f;
  }
  return img;
}

class ImageEncode : public ::testing::Test {
 protected:
  fs::path dir = test::fresh_temp_dir("encode");
  void TearDown() override { fs::remove_all(dir); }
};

TEST_F(ImageEncode, MemoryBytesEqualTheFileBytes) {
  for (bool alpha : {false, true}) {
    for (ImageBitDepth depth : {ImageBitDepth::k8, ImageBitDepth::k16}) {
      for (int level : {1, 6}) {
        const Image img = pattern(37, 23, alpha);
        ImageWriteOptions o;
        o.bit_depth = depth;
        o.png_compression = level;
        const fs::path file = dir / "a.png";
        ASSERT_TRUE(write_image(file, img.view(), o).has_value());
        Expected<std::vector<unsigned char>> bytes = encode_image(img.view(), ".png", o);
        ASSERT_TRUE(bytes) << bytes.error().message;
        const std::string on_disk = test::read_bytes(file);
        EXPECT_EQ(std::string(bytes->begin(), bytes->end()), on_disk)
            << "alpha " << alpha << " level " << level;
        EXPECT_EQ(on_disk.substr(1, 3), "PNG");
      }
    }
  }
}

TEST_F(ImageEncode, EveryCompressionLevelDecodesToTheSamePixels) {
  const Image img = pattern(64, 40, true);
  std::vector<std::size_t> sizes;
  for (int level : {0, 1, 3, 6, 9}) {
    ImageWriteOptions o;
    o.png_compression = level;
    const fs::path file = dir / ("l" + std::to_string(level) + ".png");
    ASSERT_TRUE(write_image(file, img.view(), o).has_value());
    sizes.push_back(fs::file_size(file));
    Expected<Image> back = read_image(file);
    ASSERT_TRUE(back) << back.error().message;
    for (std::size_t i = 0; i < img.pixels.size(); ++i) {
      // 8-bit: round(v * 255) / 255, v in [0, 1].
      const float v = std::min(1.f, img.pixels[i]);
      ASSERT_FLOAT_EQ(back->pixels[i], std::round(v * 255.f) / 255.f) << "level " << level;
    }
  }
  // Level 0 stores (no deflate): the largest file; 9 is no larger than 1.
  EXPECT_GT(sizes[0], sizes[1]);
  EXPECT_LE(sizes[4], sizes[1]);
}

TEST_F(ImageEncode, FormatsWithoutMemoryOutputAreRefused) {
  const Image img = pattern(4, 4, false);
  Expected<std::vector<unsigned char>> bytes = encode_image(img.view(), ".nosuchformat");
  ASSERT_FALSE(bytes);
  EXPECT_EQ(bytes.error().code, ErrorCode::kUnsupported);
}

}  // namespace
}  // namespace texbake
