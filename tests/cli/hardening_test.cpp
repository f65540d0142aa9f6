// Hardening of the command line, second round (issue #12): self-overwrites,
// read-only and special outputs, a full stdout, and interrupted writes. Each
// case asserts the exit code, the message and the folder's exact contents
// afterwards (SPEC section 8: nothing lost, nothing left behind).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "run_texbake.h"

namespace {

namespace fs = std::filesystem;
using texbake::testing_cli::run_texbake;
using texbake::testing_cli::RunResult;
using texbake::testing_cli::shell_quote;
using texbake::testing_cli::slurp;

const fs::path kData = TEXBAKE_DATA_DIR;

class Hardening : public ::testing::Test {
 protected:
  fs::path dir;
  std::string sphere = " --proxy sphere --center 0,0,0 --radius 2 --pole 0,0,1 --equator 1,0,0";

  void SetUp() override {
    std::random_device rd;
    dir = fs::temp_directory_path() / ("texbake-hardening-" + std::to_string(rd()));
    fs::create_directories(dir);
    // A tetrahedron and the Earth map.
    std::ofstream(dir / "tet.off") << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    fs::copy_file(kData / "earth.jpg", dir / "earth.jpg");
  }
  void TearDown() override { fs::remove_all(dir); }

  std::string q(const fs::path& p) const { return shell_quote(p.string()); }

  // The names in the folder, sorted.
  std::vector<std::string> contents() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  }
  std::string bake(const std::string& rest) const {
    return "bake " + q(dir / "tet.off") + " --texture " + q(dir / "earth.jpg") + sphere + " " +
           rest;
  }
};

bool names(const std::string& message, std::initializer_list<std::string> parts) {
  return std::all_of(parts.begin(), parts.end(),
                     [&](const std::string& p) { return message.find(p) != std::string::npos; });
}

// ---- Item 8: an output that is an input is a usage error, before any work.

TEST_F(Hardening, OutputEqualToTheInputMeshIsExitTwo) {
  // The mesh as PLY, baked onto itself.
  ASSERT_EQ(run_texbake(bake("-q -o " + q(dir / "tet.ply"))).exit_code, 0);
  const std::string before = slurp(dir / "tet.ply");
  RunResult r = run_texbake("bake " + q(dir / "tet.ply") + " --texture " + q(dir / "earth.jpg") +
                            sphere + " -o " + q(dir / "tet.ply"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(names(r.err, {"texbake: error: ", "-o", "MESH", "same file"})) << r.err;
  EXPECT_EQ(slurp(dir / "tet.ply"), before);
  // Through a symbolic link too (file identity, not names).
  fs::create_symlink(dir / "tet.ply", dir / "link.ply");
  r = run_texbake("bake " + q(dir / "tet.ply") + " --texture " + q(dir / "earth.jpg") + sphere +
                  " -o " + q(dir / "link.ply"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(slurp(dir / "tet.ply"), before);
}

TEST_F(Hardening, AtlasImageEqualToTheTextureIsExitTwo) {
  // -o earth.obj writes its atlas as earth.png: make the texture earth.png.
  fs::copy_file(dir / "earth.jpg", dir / "earth.png");
  const std::string before = slurp(dir / "earth.png");
  RunResult r = run_texbake("bake " + q(dir / "tet.off") + " --texture " + q(dir / "earth.png") +
                            sphere + " --size 64 -o " + q(dir / "earth.obj"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(names(r.err, {"--texture", "-o", "same file"})) << r.err;
  EXPECT_EQ(slurp(dir / "earth.png"), before);
  EXPECT_EQ(contents(), (std::vector<std::string>{"earth.jpg", "earth.png", "tet.off"}));
}

TEST_F(Hardening, ReportEqualToTheOutputIsExitTwo) {
  RunResult r = run_texbake(bake("-o " + q(dir / "x.ply") + " --report " + q(dir / "x.ply")));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(names(r.err, {"--report", "-o", "same file"})) << r.err;
  EXPECT_EQ(contents(), (std::vector<std::string>{"earth.jpg", "tet.off"}));
  // An existing file named twice through two spellings.
  std::ofstream(dir / "r.json") << "{}";
  r = run_texbake(
      bake("-o " + q(dir / "r.json") + " --target vertex --report " + q(dir / "." / "r.json")));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(slurp(dir / "r.json"), "{}");
}

TEST_F(Hardening, FitOutputEqualToTheMeshIsExitTwo) {
  const std::string before = slurp(dir / "tet.off");
  RunResult r =
      run_texbake("fit " + q(dir / "tet.off") + " --proxy sphere -o " + q(dir / "tet.off"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(names(r.err, {"-o", "MESH", "same file"})) << r.err;
  EXPECT_EQ(slurp(dir / "tet.off"), before);
}

TEST_F(Hardening, RenderOutputEqualToTheTextureIsExitTwo) {
  fs::copy_file(dir / "earth.jpg", dir / "earth.png");
  const std::string before = slurp(dir / "earth.png");
  RunResult r = run_texbake("render " + q(dir / "tet.off") + " --texture " + q(dir / "earth.png") +
                            sphere + " --size 16x16 -o " + q(dir / "earth.png"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(names(r.err, {"--texture", "-o", "same file"})) << r.err;
  EXPECT_EQ(slurp(dir / "earth.png"), before);
}

// ---- Item 9: read-only outputs are refused; devices are written in place.

TEST_F(Hardening, ReadOnlyOutputIsRefusedAndKept) {
  std::ofstream(dir / "ro.ply") << "keep";
  fs::permissions(dir / "ro.ply",
                  fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  RunResult r = run_texbake(bake("-o " + q(dir / "ro.ply")));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(names(r.err, {"texbake: error: ", "ro.ply", "read-only"})) << r.err;
  EXPECT_EQ(slurp(dir / "ro.ply"), "keep");
  EXPECT_EQ(fs::status(dir / "ro.ply").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  EXPECT_EQ(contents(), (std::vector<std::string>{"earth.jpg", "ro.ply", "tet.off"}));
}

TEST_F(Hardening, ReportToACharacterDeviceWritesIntoIt) {
  // A private null device (major 1, minor 3): --report /dev/null must never
  // replace the system's /dev/null by a regular file.
  const fs::path null_dev = dir / "null";
  ASSERT_EQ(::mknod(null_dev.c_str(), S_IFCHR | 0666, makedev(1, 3)), 0)
      << "mknod needs root (CI runs as root): " << std::strerror(errno);
  RunResult r = run_texbake(bake("-q -o " + q(dir / "x.ply") + " --report " + q(null_dev)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_character_file(null_dev));
  EXPECT_EQ(contents(), (std::vector<std::string>{"earth.jpg", "null", "tet.off", "x.ply"}));
}

// ---- Item 10: results written to a full stdout are a failure.

TEST_F(Hardening, FullStandardOutputIsExitOne) {
  ASSERT_TRUE(fs::exists("/dev/full"));
  const std::vector<std::string> commands = {
      "map" + sphere + " --point 1,1,1",
      "map" + sphere + " --point 1,1,1 --json",
      "fit " + q(dir / "tet.off") + " --proxy sphere",
      "info " + q(dir / "tet.off"),
      "info " + q(dir / "tet.off") + " --json",
  };
  for (const std::string& c : commands) {
    RunResult r = run_texbake(c + " >/dev/full");
    EXPECT_EQ(r.exit_code, 1) << c << "\n" << r.err;
    EXPECT_TRUE(names(r.err, {"texbake: error: ", "standard output"})) << c << "\n" << r.err;
  }
  // The same commands succeed on a working stdout.
  for (const std::string& c : commands) EXPECT_EQ(run_texbake(c).exit_code, 0) << c;
}

// ---- Item 12: interrupted writes leave the folder as it was.

// Starts `texbake args` in the background and returns its pid.
pid_t spawn_texbake(const std::vector<std::string>& args) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::vector<char*> argv;
    std::string binary = TEXBAKE_BINARY;
    argv.push_back(binary.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

bool has_temporary(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().filename().string().rfind(".texbake-", 0) == 0) return true;
  }
  return false;
}

// Signals a textured-OBJ bake as soon as its first temporary appears (the
// atlas being written), and checks the previous set is intact afterwards.
void interrupt_atlas_write(const fs::path& dir, int sig) {
  const std::vector<std::string> args = {"bake",
                                         (dir / "tet.off").string(),
                                         "--texture",
                                         (dir / "earth.jpg").string(),
                                         "--proxy",
                                         "sphere",
                                         "--center",
                                         "0,0,0",
                                         "--radius",
                                         "2",
                                         "--uv",
                                         "generate",
                                         "--size",
                                         "4096",
                                         "--padding",
                                         "inf",
                                         "--format",
                                         "png16",
                                         "-q",
                                         "-o",
                                         (dir / "out.obj").string()};
  // A first, complete bake: the set to keep.
  pid_t pid = spawn_texbake(args);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const std::string obj = slurp(dir / "out.obj"), mtl = slurp(dir / "out.mtl"),
                    png = slurp(dir / "out.png");
  pid = spawn_texbake(args);
  bool seen = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    if (has_temporary(dir)) {
      seen = true;
      ::kill(pid, sig);
      break;
    }
    if (::waitpid(pid, &status, WNOHANG) == pid) break;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  if (seen) ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(seen) << "the temporary never appeared";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "status " << status;
  if (sig == SIGKILL) {
    // Nothing can catch SIGKILL: the next texbake writing there cleans up.
    RunResult r = run_texbake("fit " + shell_quote((dir / "tet.off").string()) +
                              " --proxy sphere -o " + shell_quote((dir / "p.json").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    fs::remove(dir / "p.json");
  }
  EXPECT_FALSE(has_temporary(dir));
  EXPECT_EQ(slurp(dir / "out.obj"), obj);
  EXPECT_EQ(slurp(dir / "out.mtl"), mtl);
  EXPECT_EQ(slurp(dir / "out.png"), png);
}

TEST_F(Hardening, SigintDuringAnAtlasWriteLeavesThePreviousSetAndNoTemporary) {
  interrupt_atlas_write(dir, SIGINT);
  EXPECT_EQ(contents(),
            (std::vector<std::string>{"earth.jpg", "out.mtl", "out.obj", "out.png", "tet.off"}));
}

TEST_F(Hardening, SigtermDuringAnAtlasWriteLeavesThePreviousSetAndNoTemporary) {
  interrupt_atlas_write(dir, SIGTERM);
  EXPECT_EQ(contents(),
            (std::vector<std::string>{"earth.jpg", "out.mtl", "out.obj", "out.png", "tet.off"}));
}

TEST_F(Hardening, SigkillDuringAnAtlasWriteIsCleanedByTheNextRun) {
  interrupt_atlas_write(dir, SIGKILL);
  EXPECT_EQ(contents(),
            (std::vector<std::string>{"earth.jpg", "out.mtl", "out.obj", "out.png", "tet.off"}));
}

// ---- Item 5: a proxy that maps nothing is an error; mostly nothing, a warning.

TEST_F(Hardening, ProxyThatMapsNothingIsAnError) {
  // A sphere of radius 1e308: no point of the mesh gets a (u, v).
  const std::string huge =
      " --proxy sphere --center 0,0,0 --radius 1e308 --pole 0,0,1 --equator 1,0,0";
  for (const std::string& target : {"x.ply", "x.obj --size 64"}) {
    RunResult r = run_texbake("bake " + q(dir / "tet.off") + " --texture " + q(dir / "earth.jpg") +
                              huge + " -o " + q(dir / "") + target);
    EXPECT_EQ(r.exit_code, 1) << target << "\n" << r.err;
    EXPECT_TRUE(names(r.err, {"texbake: error: ", "tet.off", "the proxy maps none of the mesh's"}))
        << r.err;
  }
  EXPECT_EQ(contents(), (std::vector<std::string>{"earth.jpg", "tet.off"}));
}

TEST_F(Hardening, ProxyThatMapsLessThanHalfWarns) {
  // v0, v1, v2 lie on the cylinder's axis (no azimuth: undefined), v3 off it.
  std::ofstream(dir / "axis.off") << "OFF\n4 2 0\n0 0 0\n0 0 1\n0 0 2\n1 0 0\n3 0 1 3\n3 1 2 3\n";
  RunResult r = run_texbake("bake " + q(dir / "axis.off") + " --texture " + q(dir / "earth.jpg") +
                            " --proxy cylinder --base 0,0,0 --axis 0,0,1 --equator 1,0,0"
                            " --radius 1 --height 2 --filter bilinear -q -o " +
                            q(dir / "axis.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("texbake: warning: 3 of 4 vertices (75.0 %) have no mapping through the "
                       "proxy; they are treated as occluded"),
            std::string::npos)
      << r.err;
}

// ---- Item 4: NaN texels are read as 0, with a warning naming the texture.

TEST_F(Hardening, NonFiniteTexelsWarnAndNeverReachTheOutput) {
  // A 2 x 1 float PFM (little-endian: scale -1), bottom row first: NaN, inf.
  std::ofstream pfm(dir / "holes.pfm", std::ios::binary);
  pfm << "PF\n2 1\n-1\n";
  const float values[6] = {std::numeric_limits<float>::quiet_NaN(), 0.5f, 0.5f,
                           std::numeric_limits<float>::infinity(),  0.5f, 0.5f};
  pfm.write(reinterpret_cast<const char*>(values), sizeof values);
  pfm.close();
  RunResult r = run_texbake("bake " + q(dir / "tet.off") + " --texture " + q(dir / "holes.pfm") +
                            sphere + " -q --ascii -o " + q(dir / "x.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(
      names(r.err, {"texbake: warning: ", "holes.pfm", "2 NaN or infinite values read as 0"}))
      << r.err;
  const std::string ply = slurp(dir / "x.ply");
  EXPECT_EQ(ply.find("nan"), std::string::npos);
}

// Long names (item 7): a legal 244-character output name is written.
TEST_F(Hardening, LongOutputNameIsWritten) {
  const std::string name = std::string(240, 'n') + ".ply";
  RunResult r = run_texbake(bake("-q -o " + q(dir / name)));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / name));
}

}  // namespace
