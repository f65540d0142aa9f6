// Resource limits (SPEC section 8, issue #7): a header declaring an image
// that cannot fit is rejected on the header, before pixels are allocated.
// (The mesh readers' limits are in fuzz_regressions_test.cpp and
// bad_input_test.cpp.)
#include <gtest/gtest.h>

#include "mesh_io/image_io.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

TEST(ImageLimits, CheckImageSizeBounds) {
  EXPECT_TRUE(check_image_size(16384, 16384, 4).has_value());
  EXPECT_TRUE(check_image_size(1, 1, 1).has_value());
  EXPECT_TRUE(check_image_size(8192, 8192, 16).has_value());  // 2^26 x 16 = 2^30 values
  const Status pixels = check_image_size(16385, 16384, 1);
  ASSERT_FALSE(pixels.has_value());
  EXPECT_NE(pixels.error().message.find("16385 x 16384 pixels is larger than texbake reads"),
            std::string::npos)
      << pixels.error().message;
  const Status values = check_image_size(16384, 16384, 5);
  ASSERT_FALSE(values.has_value());
  EXPECT_NE(values.error().message.find("of 5 channels is more than texbake decodes"),
            std::string::npos)
      << values.error().message;
  EXPECT_FALSE(check_image_size(8192, 8193, 16).has_value());
  // No overflow in the products: (2^31 - 1)^2 x 2^31 values.
  EXPECT_FALSE(check_image_size(2147483647, 2147483647, 2147483647).has_value());
  EXPECT_FALSE(check_image_size(0, 5, 3).has_value());
  EXPECT_FALSE(check_image_size(5, 5, 0).has_value());
}

class ImageLimitFiles : public ::testing::Test {
 protected:
  fs::path dir = test::fresh_temp_dir("limits");
  void TearDown() override { fs::remove_all(dir); }
};

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

TEST_F(ImageLimitFiles, PngHeaderOf100000SquaredPixelsRejectedBeforeDecoding) {
  // A valid IHDR for 100000 x 100000 RGBA 8-bit (160 GB as float RGBA) and a
  // few bytes of IDAT: only the header is read.
  std::string ihdr = be32(100000) + be32(100000);
  ihdr += '\x08';  // bit depth
  ihdr += '\x06';  // RGBA
  ihdr += std::string(3, '\0');
  auto chunk = [](const std::string& type, const std::string& data) {
    return be32(static_cast<uint32_t>(data.size())) + type + data + be32(crc32(type + data));
  };
  const fs::path path = test::write_text(
      dir / "huge.png", std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) +
                            chunk("IDAT", std::string("\x78\x01\x01\x00\x00\xff\xff", 7)) +
                            chunk("IEND", ""));
  Expected<Image> img = read_image(path);
  ASSERT_FALSE(img.has_value());
  EXPECT_EQ(img.error().code, ErrorCode::kParse);
  EXPECT_NE(img.error().message.find(path.string() +
                                     ": 100000 x 100000 pixels is larger than texbake reads"),
            std::string::npos)
      << img.error().message;
}

TEST_F(ImageLimitFiles, PgmHeaderJustAboveTheLimitRejected) {
  // 16385 x 16384 gray: one column above 2^28 pixels, 18 bytes of file.
  const fs::path path = test::write_text(dir / "wide.pgm", "P5\n16385 16384\n255\n\x01\x02");
  Expected<Image> img = read_image(path);
  ASSERT_FALSE(img.has_value());
  EXPECT_NE(img.error().message.find("16385 x 16384 pixels is larger than texbake reads"),
            std::string::npos)
      << img.error().message;
}

}  // namespace
}  // namespace texbake
