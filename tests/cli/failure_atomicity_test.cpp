// Failure atomicity of `texbake bake` (SPEC section 8, issue #7 item 4): a
// bake killed with SIGKILL, at any moment, leaves the previous output file
// byte for byte as it was and nothing half-written under the output's name
// (a temporary ".texbake-*" file may remain after SIGKILL: nothing can remove
// it); a bake that fails normally leaves no temporary file at all.
//
// The mesh is a 600 x 600 grid (360k vertices) written as ASCII PLY, so the
// output takes long enough to write (about 11 MB) that the test can see the
// temporary file appear and kill the process while it is being written.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "mesh_io/image_io.h"
#include "run_texbake.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using texbake::testing_cli::slurp;

std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(".texbake-", 0) == 0) out.push_back(name);
  }
  return out;
}

class BakeAtomicity : public ::testing::Test {
 protected:
  fs::path dir, mesh, image, out;

  void SetUp() override {
    std::random_device rd;
    dir = fs::temp_directory_path() / ("texbake-atomic-" + std::to_string(rd()));
    fs::create_directories(dir);
    mesh = dir / "grid.ply";
    const int n = 600;
    std::ofstream ply(mesh, std::ios::binary);
    ply << "ply\nformat binary_little_endian 1.0\nelement vertex " << n * n
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
        << 2 * (n - 1) * (n - 1) << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const float p[3] = {float(i) / (n - 1), float(j) / (n - 1), 0.f};
        ply.write(reinterpret_cast<const char*>(p), sizeof p);
      }
    }
    for (int j = 0; j + 1 < n; ++j) {
      for (int i = 0; i + 1 < n; ++i) {
        const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
        for (const auto& t : {std::array<int, 3>{a, b, c}, std::array<int, 3>{a, c, d}}) {
          const unsigned char three = 3;
          ply.write(reinterpret_cast<const char*>(&three), 1);
          ply.write(reinterpret_cast<const char*>(t.data()), 12);
        }
      }
    }
    ply.close();
    texbake::Image img;
    img.width = img.height = 64;
    img.pixels.resize(64 * 64 * 4);
    for (std::size_t k = 0; k < img.pixels.size(); ++k) img.pixels[k] = float(k % 251) / 250;
    image = dir / "tex.png";
    ASSERT_TRUE(texbake::write_image(image, img.view()).has_value());
    out = dir / "out.ply";
  }
  void TearDown() override { fs::remove_all(dir); }

  std::vector<std::string> args(const fs::path& texture) const {
    return {TEXBAKE_BINARY, "bake",     mesh.string(), "--texture", texture.string(),
            "--proxy",      "plane",    "--origin",    "0,0,0",     "--u-axis",
            "1,0,0",        "--v-axis", "0,1,0",       "--filter",  "bilinear",
            "--visibility", "all",      "--ascii",     "--threads", "1",
            "-q",           "-o",       out.string()};
  }

  pid_t spawn(const std::vector<std::string>& a) const {
    const pid_t pid = ::fork();
    if (pid == 0) {
      std::vector<char*> argv;
      for (const std::string& s : a) argv.push_back(const_cast<char*>(s.c_str()));
      argv.push_back(nullptr);
      std::freopen("/dev/null", "w", stderr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    return pid;
  }
  static int wait_exit(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }
};

TEST_F(BakeAtomicity, SigkillWhileWritingLeavesThePreviousOutputIntact) {
  // The previous output: a complete bake.
  ASSERT_EQ(wait_exit(spawn(args(image))), 0);
  const std::string previous = slurp(out);
  ASSERT_GT(previous.size(), 5'000'000u);
  ASSERT_TRUE(temporaries(dir).empty());

  // Kill as soon as the temporary output appears (mid-write).
  const pid_t pid = spawn(args(image));
  bool seen = false;
  const auto deadline = Clock::now() + std::chrono::seconds(120);
  while (Clock::now() < deadline) {
    if (!temporaries(dir).empty()) {
      seen = true;
      break;
    }
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) break;  // finished unseen
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  ::kill(pid, SIGKILL);
  const int code = wait_exit(pid);
  ASSERT_TRUE(seen) << "the temporary output never appeared (exit " << code << ")";
  EXPECT_EQ(code, -SIGKILL);
  EXPECT_TRUE(slurp(out) == previous) << "the previous output changed";
  // Only the target and (after SIGKILL) at most one temporary remain.
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  EXPECT_EQ(names.size(), 3u + temporaries(dir).size());  // grid.ply, tex.png, out.ply
  EXPECT_LE(temporaries(dir).size(), 1u);
}

TEST_F(BakeAtomicity, SigkillAtAnyMomentLeavesTheOutputWholeOrPrevious) {
  ASSERT_EQ(wait_exit(spawn(args(image))), 0);
  const std::string previous = slurp(out);
  // A complete run's length, then kills spread over it: loading, baking,
  // writing. The output is either the previous file or a complete new one
  // (identical bytes here, the inputs being the same), never partial.
  const auto t0 = Clock::now();
  ASSERT_EQ(wait_exit(spawn(args(image))), 0);
  const auto full = Clock::now() - t0;
  for (int k = 1; k <= 4; ++k) {
    const pid_t pid = spawn(args(image));
    std::this_thread::sleep_for(full * k / 5);
    ::kill(pid, SIGKILL);
    wait_exit(pid);
    EXPECT_TRUE(slurp(out) == previous) << "kill at " << k << "/5 of the run";
    EXPECT_LE(temporaries(dir).size(), static_cast<std::size_t>(k));
  }
}

TEST_F(BakeAtomicity, NormalFailureLeavesNoTemporaryAndKeepsThePreviousOutput) {
  ASSERT_EQ(wait_exit(spawn(args(image))), 0);
  const std::string previous = slurp(out);
  // The texture is not an image: the bake fails (exit 1) after starting.
  const fs::path bad = dir / "bad.png";
  std::ofstream(bad) << "not a png";
  EXPECT_EQ(wait_exit(spawn(args(bad))), 1);
  EXPECT_TRUE(slurp(out) == previous);
  EXPECT_TRUE(temporaries(dir).empty());
  // The output name is a folder: the temporary is written, the rename fails,
  // the temporary is removed.
  const fs::path folder_out = dir / "folder.ply";
  fs::create_directories(folder_out / "inside");
  std::vector<std::string> a = args(image);
  a.back() = folder_out.string();
  EXPECT_EQ(wait_exit(spawn(a)), 1);
  EXPECT_TRUE(fs::is_directory(folder_out / "inside"));
  EXPECT_TRUE(temporaries(dir).empty());
}

}  // namespace
