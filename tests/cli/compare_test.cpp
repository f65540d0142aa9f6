// texbake compare: PSNR and max difference of image files, exit codes.
// Inputs are tiny binary PPM files written here byte by byte (OpenImageIO
// reads PNM), so the expected figures follow from the bytes by hand:
// PSNR = 20 log10(1 / RMS), RMS over all pixels and the 3 channels.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

class CompareCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_compare_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A w x h RGB PPM, black except for the given (x, y, r, g, b) pixels.
  struct Px {
    int x, y;
    unsigned char r, g, b;
  };
  fs::path write_ppm(const std::string& name, int w, int h, const std::vector<Px>& pixels) {
    std::vector<unsigned char> data(static_cast<std::size_t>(w) * h * 3, 0);
    for (const Px& p : pixels) {
      unsigned char* d = &data[(static_cast<std::size_t>(p.y) * w + p.x) * 3];
      d[0] = p.r;
      d[1] = p.g;
      d[2] = p.b;
    }
    const fs::path path = dir_ / name;
    std::ofstream out(path, std::ios::binary);
    out << "P6\n" << w << " " << h << "\n255\n";
    out.write(reinterpret_cast<const char*>(data.data()),
              static_cast<std::streamsize>(data.size()));
    return path;
  }

  RunResult run(const std::string& args) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = std::string("\"") + TEXBAKE_BINARY + "\" compare " + args + " >\"" +
                            out.string() + "\" 2>\"" + err.string() + "\"";
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }

  static std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  static double psnr_of(const std::string& out) {
    std::smatch m;
    if (!std::regex_search(out, m, std::regex("PSNR: ([0-9.]+|inf) dB"))) return NAN;
    return m[1] == "inf" ? INFINITY : std::stod(m[1]);
  }

  std::string q(const fs::path& p) { return "\"" + p.string() + "\""; }

  fs::path dir_;
};

TEST_F(CompareCli, IdenticalImagesHaveInfinitePsnrAndZeroDifference) {
  const fs::path a = write_ppm("a.ppm", 4, 4, {{1, 2, 10, 200, 30}, {3, 3, 255, 255, 255}});
  const RunResult r = run(q(a) + " " + q(a) + " --min-psnr 100");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::isinf(psnr_of(r.out))) << r.out;
  EXPECT_NE(r.out.find("max difference: 0 "), std::string::npos) << r.out;
}

TEST_F(CompareCli, OnePixelFullDifferenceGivesHandComputedPsnr) {
  // One channel of one pixel differs by 1.0: MSE = 1 / (16 * 3),
  // PSNR = 10 log10(48) = 16.8124 dB; max difference 1 at (2, 1), channel 0.
  const fs::path a = write_ppm("a.ppm", 4, 4, {});
  const fs::path b = write_ppm("b.ppm", 4, 4, {{2, 1, 255, 0, 0}});
  const RunResult r = run(q(a) + " " + q(b));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(psnr_of(r.out), 10 * std::log10(48.0), 1e-3) << r.out;
  EXPECT_NE(r.out.find("max difference: 1 at pixel (2, 1) channel 0"), std::string::npos) << r.out;
}

TEST_F(CompareCli, OnePixelPartialDifferenceGivesHandComputedPsnr) {
  // 51/255 = 0.2 on all three channels of pixel (0, 3): MSE = 3 * 0.04 / 48
  // = 0.0025, RMS = 0.05, PSNR = 20 log10(20) = 26.0206 dB.
  const fs::path a = write_ppm("a.ppm", 4, 4, {{0, 3, 102, 102, 102}});
  const fs::path b = write_ppm("b.ppm", 4, 4, {{0, 3, 153, 153, 153}});
  const RunResult r = run(q(a) + " " + q(b));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(psnr_of(r.out), 20 * std::log10(20.0), 1e-3) << r.out;
  EXPECT_NE(r.out.find("max difference: 0.2 at pixel (0, 3)"), std::string::npos) << r.out;
}

TEST_F(CompareCli, MaskBackgroundCountsOnlyForegroundPixels) {
  // Background = black (--background 0,0,0; PPM has no alpha). Foreground:
  // (1, 1) in both (0.4 vs 0.6) and (3, 3) white in both: 2 pixels.
  // MSE = 3 * 0.04 / (2 * 3) = 0.02, PSNR = 10 log10(50) = 16.9897 dB.
  const fs::path a = write_ppm("a.ppm", 4, 4, {{1, 1, 102, 102, 102}, {3, 3, 255, 255, 255}});
  const fs::path b = write_ppm("b.ppm", 4, 4, {{1, 1, 153, 153, 153}, {3, 3, 255, 255, 255}});
  const RunResult masked = run(q(a) + " " + q(b) + " --mask-background --background 0,0,0");
  EXPECT_EQ(masked.exit_code, 0) << masked.err;
  EXPECT_NEAR(psnr_of(masked.out), 10 * std::log10(50.0), 1e-3) << masked.out;
  EXPECT_NE(masked.out.find("compared pixels: 2 of 16"), std::string::npos) << masked.out;
  // Unmasked, the same difference is spread over 16 pixels: 20 log10(20).
  const RunResult plain = run(q(a) + " " + q(b));
  EXPECT_NEAR(psnr_of(plain.out), 20 * std::log10(20.0), 1e-3) << plain.out;
}

TEST_F(CompareCli, MinPsnrNotReachedExitsOne) {
  const fs::path a = write_ppm("a.ppm", 4, 4, {});
  const fs::path b = write_ppm("b.ppm", 4, 4, {{2, 1, 255, 0, 0}});
  const RunResult fail = run(q(a) + " " + q(b) + " --min-psnr 17");
  EXPECT_EQ(fail.exit_code, 1);
  EXPECT_NE(fail.err.find("texbake: error: PSNR 16.812 dB is below --min-psnr"), std::string::npos)
      << fail.err;
  const RunResult pass = run(q(a) + " " + q(b) + " --min-psnr 16.8");
  EXPECT_EQ(pass.exit_code, 0) << pass.err;
}

TEST_F(CompareCli, SizeMismatchExitsOneNamingBothFiles) {
  const fs::path a = write_ppm("a.ppm", 4, 4, {});
  const fs::path b = write_ppm("b.ppm", 5, 4, {});
  const RunResult r = run(q(a) + " " + q(b));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("texbake: error: image sizes differ"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("4x4 and 5x4"), std::string::npos) << r.err;
}

TEST_F(CompareCli, UnreadableImagesExitOneNamingTheFile) {
  const fs::path a = write_ppm("a.ppm", 4, 4, {});
  const RunResult missing = run(q(a) + " " + q(dir_ / "missing.png"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("missing.png"), std::string::npos) << missing.err;

  const fs::path junk = dir_ / "junk.png";
  std::ofstream(junk) << "this is not a PNG";
  const RunResult bad = run(q(junk) + " " + q(a));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("junk.png"), std::string::npos) << bad.err;
}

TEST_F(CompareCli, UsageErrorsExitTwo) {
  const fs::path a = write_ppm("a.ppm", 4, 4, {});
  EXPECT_EQ(run(q(a)).exit_code, 2);                                       // B missing
  EXPECT_EQ(run(q(a) + " " + q(a) + " --min-psnr abc").exit_code, 2);      // not a number
  EXPECT_EQ(run(q(a) + " " + q(a) + " --background 2,0,0").exit_code, 2);  // out of range
}

}  // namespace
