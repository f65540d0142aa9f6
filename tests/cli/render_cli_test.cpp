// texbake render from the command line: output sizes, thread independence,
// direct projection, exit codes, no partial output on failure.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "mesh_io/image_compare.h"

namespace {

namespace fs = std::filesystem;

class RenderCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_render_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // An octahedron: small, closed, every view sees it.
    mesh_ = dir_ / "octa.off";
    std::ofstream(mesh_) << "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
                            "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n"
                            "3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";
    // A 2x1 texture for direct projection (binary PPM).
    texture_ = dir_ / "tex.ppm";
    std::ofstream t(texture_, std::ios::binary);
    t << "P6\n2 1\n255\n";
    const unsigned char px[6] = {255, 128, 0, 0, 128, 255};
    t.write(reinterpret_cast<const char*>(px), 6);
  }
  void TearDown() override { fs::remove_all(dir_); }

  int run(const std::string& args, std::string* err = nullptr) {
    const fs::path err_file = dir_ / "stderr.txt";
    const std::string cmd = std::string("\"") + TEXBAKE_BINARY + "\" render " + args +
                            " >/dev/null 2>\"" + err_file.string() + "\"";
    const int status = std::system(cmd.c_str());
    if (err) {
      std::ifstream in(err_file);
      std::stringstream ss;
      ss << in.rdbuf();
      *err = ss.str();
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::string q(const fs::path& p) const { return "\"" + p.string() + "\""; }

  fs::path dir_, mesh_, texture_;
};

TEST_F(RenderCli, WritesTheRequestedSizeAndContactSheet) {
  const fs::path one = dir_ / "one.png", sheet = dir_ / "sheet.png";
  ASSERT_EQ(run(q(mesh_) + " -o " + q(one) + " --size 40x30"), 0);
  ASSERT_EQ(run(q(mesh_) + " -o " + q(sheet) + " --size 40x30 --views 5"), 0);
  // 5 views: 3 columns, 2 rows of 40x30.
  auto a = texbake::compare_image_files(one, one, {});
  ASSERT_TRUE(a.has_value()) << a.error().message;
  EXPECT_EQ(a->width, 40);
  EXPECT_EQ(a->height, 30);
  EXPECT_EQ(a->channels, 4);  // alpha: the background is transparent
  auto s = texbake::compare_image_files(sheet, sheet, {});
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->width, 120);
  EXPECT_EQ(s->height, 60);
}

TEST_F(RenderCli, ThreadCountDoesNotChangeTheImage) {
  const fs::path a = dir_ / "a.png", b = dir_ / "b.png";
  const std::string common = q(mesh_) + " --size 64x48 --samples 4 --shadows --views 2 ";
  ASSERT_EQ(run(common + "--threads 1 -o " + q(a)), 0);
  ASSERT_EQ(run(common + "--threads 2 -o " + q(b)), 0);
  auto r = texbake::compare_image_files(a, b, {});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_TRUE(std::isinf(r->psnr));
  EXPECT_EQ(r->max_difference, 0.0);
}

TEST_F(RenderCli, DirectProjectionDiffersFromGrey) {
  const fs::path grey = dir_ / "grey.png", proj = dir_ / "proj.png";
  ASSERT_EQ(run(q(mesh_) + " --size 32x32 -o " + q(grey)), 0);
  std::string err;
  ASSERT_EQ(run(q(mesh_) + " --size 32x32 -o " + q(proj) + " --texture " + q(texture_) +
                    " --proxy sphere --center 0,0,0 --radius 1",
                &err),
            0)
      << err;
  auto r = texbake::compare_image_files(grey, proj, {});
  ASSERT_TRUE(r.has_value());
  EXPECT_LT(r->psnr, 30);  // orange/blue against grey: far apart
}

// --wrap repeat tiles the plane's texture: moving the origin by one tile
// (the u axis) gives the same image, which the clamped plane does not.
TEST_F(RenderCli, WrapRepeatTilesThePlane) {
  const fs::path square = dir_ / "square.off";
  std::ofstream(square) << "OFF\n4 2 0\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n3 0 1 2\n3 0 2 3\n";
  const std::string common = q(square) + " --size 48x48 --view 0,90 --texture " + q(texture_) +
                             " --proxy plane --u-axis 1,0,0 --v-axis 0,1,0";
  auto render = [&](const std::string& name, const std::string& flags) {
    const fs::path out = dir_ / name;
    std::string err;
    EXPECT_EQ(run(common + " " + flags + " -o " + q(out), &err), 0) << err;
    return out;
  };
  const fs::path repeat0 = render("r0.png", "--origin 0,0,0 --wrap repeat");
  const fs::path repeat1 = render("r1.png", "--origin -1,0,0 --wrap repeat");
  const fs::path clamp0 = render("c0.png", "--origin 0,0,0 --wrap clamp");
  const fs::path clamp1 = render("c1.png", "--origin -1,0,0 --wrap clamp");
  const fs::path plain1 = render("p1.png", "--origin -1,0,0");
  auto max_diff = [](const fs::path& a, const fs::path& b) {
    auto r = texbake::compare_image_files(a, b, {});
    EXPECT_TRUE(r.has_value()) << r.error().message;
    return r ? r->max_difference : -1.0;
  };
  EXPECT_LE(max_diff(repeat0, repeat1), 1.0 / 255);  // one tile apart: the same image
  EXPECT_GT(max_diff(clamp0, clamp1), 0.2);          // clamped: orange/blue move
  EXPECT_GT(max_diff(repeat1, clamp1), 0.2);
  EXPECT_EQ(max_diff(clamp1, plain1), 0.0);  // clamp is the default
}

TEST_F(RenderCli, WrapNeedsAPlaneProjection) {
  const std::string out = " -o " + q(dir_ / "x.png");
  std::string err;
  EXPECT_EQ(run(q(mesh_) + out + " --wrap repeat", &err), 2);
  EXPECT_NE(err.find("texbake: error: --wrap needs --texture and --proxy plane"), std::string::npos)
      << err;
  EXPECT_EQ(run(q(mesh_) + out + " --texture " + q(texture_) +
                    " --proxy sphere --center 0,0,0 --radius 1 --wrap repeat",
                &err),
            2);
  EXPECT_NE(err.find("--wrap applies to the plane proxy only"), std::string::npos) << err;
  EXPECT_EQ(run(q(mesh_) + out + " --texture " + q(texture_) +
                    " --proxy plane --origin 0,0,0 --u-axis 1,0,0 --v-axis 0,1,0 --wrap tile",
                &err),
            2);
  EXPECT_NE(err.find("unknown value 'tile' (expected clamp or repeat)"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

TEST_F(RenderCli, UsageErrorsExitTwo) {
  const std::string out = " -o " + q(dir_ / "x.png");
  std::string err;
  EXPECT_EQ(run(q(mesh_) + out + " --size 0x10", &err), 2);
  EXPECT_NE(err.find("texbake: error: --size"), std::string::npos) << err;
  EXPECT_EQ(run(q(mesh_) + out + " --view 10,95", &err), 2);
  EXPECT_NE(err.find("--view"), std::string::npos) << err;
  EXPECT_EQ(run(q(mesh_) + out + " --samples 0"), 2);
  EXPECT_EQ(run(q(mesh_) + out + " --texture " + q(texture_), &err), 2);
  EXPECT_NE(err.find("--proxy"), std::string::npos) << err;
  EXPECT_EQ(run(q(mesh_) + out + " --colors vertex", &err), 2);
  EXPECT_NE(err.find("no vertex colours"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

TEST_F(RenderCli, BadFilesExitOneWithoutOutput) {
  std::string err;
  const fs::path out = dir_ / "x.png";
  EXPECT_EQ(run(q(dir_ / "missing.off") + " -o " + q(out), &err), 1);
  EXPECT_NE(err.find("missing.off"), std::string::npos) << err;
  const fs::path bad = dir_ / "bad.off";
  std::ofstream(bad) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";  // index 7 out of range
  EXPECT_EQ(run(q(bad) + " -o " + q(out), &err), 1);
  EXPECT_NE(err.find("bad.off"), std::string::npos) << err;
  EXPECT_EQ(run(q(mesh_) + " -o " + q(dir_ / "no_such_folder" / "x.png"), &err), 1);
  EXPECT_FALSE(fs::exists(out));
  // Only the inputs and stderr remain: no temporary files left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.is_regular_file();
  EXPECT_EQ(files, 4);  // octa.off, tex.ppm, bad.off, stderr.txt
}

}  // namespace
