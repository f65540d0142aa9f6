// Resource limits (SPEC section 8, issues #7 and #12): a header declaring an
// image that cannot fit, or that its file cannot hold, is rejected before
// pixels are allocated; non-finite texels never reach a bake.
// (The mesh readers' limits are in fuzz_regressions_test.cpp and
// bad_input_test.cpp.)
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <functional>
#include <limits>
#include <vector>

#include "mesh_io/image_io.h"
#include "tests/mesh_io/test_files.h"
#include "tests/mesh_io/tiff_bytes.h"

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

// Runs `fn` in a forked child whose address space may grow by at most
// `extra_mb` beyond what it has mapped now; returns the child's exit code
// (fn's result), or -signal if it died. Checks that a call fails cleanly
// without allocating for a lying header (issue #12 item 3).
int run_with_memory_cap(long extra_mb, const std::function<int()>& fn) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    long pages = 0;
    std::ifstream("/proc/self/statm") >> pages;
    const rlim_t cap = static_cast<rlim_t>(pages) * ::sysconf(_SC_PAGESIZE) +
                       (static_cast<rlim_t>(extra_mb) << 20);
    const struct rlimit limit { cap, cap };
    ::setrlimit(RLIMIT_AS, &limit);
    ::_exit(fn());
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// 0 when read_image fails with kParse and a message containing `says`.
int expect_parse_error(const fs::path& path, const std::string& says) {
  Expected<Image> img = read_image(path);
  if (img.has_value()) return 10;
  if (img.error().code != ErrorCode::kParse) return 11;
  return img.error().message.find(says) != std::string::npos ? 0 : 12;
}

std::string png_chunk(const std::string& type, const std::string& data) {
  return be32(static_cast<uint32_t>(data.size())) + type + data + be32(crc32(type + data));
}

TEST_F(ImageLimitFiles, SmallPngDeclaring16384SquaredIsRejectedWithoutAllocating) {
  // 16384 x 16384 RGB is within the size cap (3.2 GB as float RGBA, 0.8 GB
  // of 8-bit data), but 64 bytes of PNG cannot hold it: deflate stores at
  // most 1032 decoded bytes per byte.
  std::string ihdr = be32(16384) + be32(16384);
  ihdr += '\x08';
  ihdr += '\x02';  // RGB
  ihdr += std::string(3, '\0');
  const std::string bytes = std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) +
                            png_chunk("IDAT", std::string("\x78\x01\x01\x00\x00\xff\xff", 7)) +
                            png_chunk("IEND", "");
  const fs::path path = test::write_text(dir / "lying.png", bytes);
  ASSERT_EQ(fs::file_size(path), 64u);
  const std::string says =
      path.string() + ": declares 16384 x 16384 pixels, more than a 64-byte png file can hold";
  EXPECT_EQ(expect_parse_error(path, says), 0);
  // And without allocating: 200 MB more address space is enough to fail.
  EXPECT_EQ(run_with_memory_cap(200, [&] { return expect_parse_error(path, says); }), 0);
}

TEST_F(ImageLimitFiles, SmallJpegDeclaring16384SquaredIsRejectedWithoutAllocating) {
  // A real 16 x 16 JPEG whose frame header (SOF0) is patched to 16384 x 16384.
  std::vector<float> pixels(16 * 16 * 4, 0.5f);
  const fs::path path = dir / "lying.jpg";
  ASSERT_TRUE(write_image(path, ImageView{16, 16, pixels.data()}));
  std::string bytes = test::read_bytes(path);
  const std::size_t sof = bytes.find("\xff\xc0");
  ASSERT_NE(sof, std::string::npos);
  // FF C0, length (2), precision (1), height (2), width (2).
  bytes.replace(sof + 5, 4, std::string("\x40\x00\x40\x00", 4));
  test::write_text(path, bytes);
  const std::string says = "declares 16384 x 16384 pixels, more than a";
  EXPECT_EQ(expect_parse_error(path, says), 0);
  EXPECT_EQ(run_with_memory_cap(200, [&] { return expect_parse_error(path, says); }), 0);
}

TEST_F(ImageLimitFiles, TruncatedUncompressedImageFailsOnItsFirstBandWithoutAllocating) {
  // PGM is not compressed, so no ratio applies: 16384 x 16384 gray declared,
  // 2 bytes of pixels. The first band of rows cannot be decoded, and the
  // 4 GB result is never allocated.
  const fs::path path = test::write_text(dir / "short.pgm", "P5\n16384 16384\n255\n\x01\x02");
  EXPECT_EQ(run_with_memory_cap(200, [&] { return expect_parse_error(path, "cannot decode"); }), 0);
}

TEST_F(ImageLimitFiles, NonFiniteTexelsAreReadAsZeroAndCounted) {
  // A float EXR with NaN and infinities (issue #12 item 4): they would make
  // every interpolation touching them NaN.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> pixels = {nan, 0.5f, inf, 1.f, 0.25f, -inf, 0.75f, nan};
  const fs::path path = dir / "holes.exr";
  ImageWriteOptions o;
  o.bit_depth = ImageBitDepth::kFloat;
  ASSERT_TRUE(write_image(path, ImageView{2, 1, pixels.data()}, o));
  Expected<Image> img = read_image(path);
  ASSERT_TRUE(img.has_value()) << img.error().message;
  EXPECT_EQ(img->nonfinite_values, 4u);
  const std::vector<float> expected = {0.f, 0.5f, 0.f, 1.f, 0.25f, 0.f, 0.75f, 0.f};
  EXPECT_EQ(img->pixels, expected);
}

TEST_F(ImageLimitFiles, LyingTiffHeaderFailsThroughTheCacheWithoutAllocatingForItsSize) {
  // A 2-kB tiled TIFF declaring 100000 x 100000 RGB (30 GB of 8-bit data,
  // 160 GB as float RGBA) in 4096-texel tiles, none of which is in the
  // file. Without a budget the size limit refuses it; with one (issue #16:
  // any size is read through the cache) its first tile cannot be read,
  // an error naming the file, and the cache allocates one tile at most.
  const fs::path path = test::write_text(
      dir / "lying.tif",
      test::tiled_tiff({100000, 100000, 4096, {}, true}, [](int, int, int) { return 0; }));
  ASSERT_LT(fs::file_size(path), 8000u);
  EXPECT_EQ(expect_parse_error(path, "100000 x 100000 pixels is larger than texbake reads"), 0);
  auto cached_error = [&] {
    ImageReadOptions o;
    o.cache_mb = 1024;
    Expected<Image> img = read_image(path, o);
    if (img.has_value()) return 10;
    if (img.error().code != ErrorCode::kParse) return 11;
    return img.error().message.rfind(path.string() + ": cannot decode", 0) == 0 ? 0 : 12;
  };
  EXPECT_EQ(cached_error(), 0);
  EXPECT_EQ(run_with_memory_cap(400, cached_error), 0);
}

}  // namespace
}  // namespace texbake
