// texbake bake: runs the built binary (TEXBAKE_BINARY) on a small plane mesh
// and an 8-bit image whose texel values are their own pixel coordinates, so
// the baked bytes are known exactly; exit codes, messages, and no output left
// behind on failure.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "mesh_io/image_io.h"
#include "run_texbake.h"

namespace {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

class BakeCli : public ::testing::Test {
 protected:
  fs::path dir;
  fs::path mesh, image, out;

  // Grid vertices (i, j), i, j in 0..4, at x = (40 i + 20.5) / 256,
  // y = (40 j + 20.5) / 256, z = 0. With the plane proxy over [0,1]^2 and
  // the 256 x 256 image below, vertex (i, j) sits at pixel position
  // (40 i + 20, 235 - 40 j) exactly (SPEC section 1: x = uW - 0.5,
  // y = (1 - v)H - 0.5), i.e. on a texel centre.
  static constexpr int kN = 5;
  static double coord(int i) { return (40 * i + 20.5) / 256; }

  void SetUp() override {
    std::random_device rd;
    dir = fs::temp_directory_path() / ("texbake-bake-cli-" + std::to_string(rd()));
    fs::create_directories(dir);
    mesh = dir / "grid.off";
    std::ofstream off(mesh);
    off << "OFF\n" << kN * kN << " " << 2 * (kN - 1) * (kN - 1) << " 0\n";
    char line[128];
    for (int j = 0; j < kN; ++j) {
      for (int i = 0; i < kN; ++i) {
        std::snprintf(line, sizeof line, "%.17g %.17g 0\n", coord(i), coord(j));
        off << line;
      }
    }
    for (int j = 0; j + 1 < kN; ++j) {
      for (int i = 0; i + 1 < kN; ++i) {
        const int a = j * kN + i;
        off << "3 " << a << " " << a + 1 << " " << a + kN + 1 << "\n";
        off << "3 " << a << " " << a + kN + 1 << " " << a + kN << "\n";
      }
    }
    off.close();
    // 8-bit RGB: red = x / 255, green = y / 255, blue = 77 / 255.
    texbake::Image img;
    img.width = img.height = 256;
    img.pixels.resize(256 * 256 * 4);
    for (int y = 0; y < 256; ++y) {
      for (int x = 0; x < 256; ++x) {
        float* p = &img.pixels[(static_cast<std::size_t>(y) * 256 + x) * 4];
        p[0] = x / 255.0f, p[1] = y / 255.0f, p[2] = 77 / 255.0f, p[3] = 1;
      }
    }
    image = dir / "ramp.png";
    ASSERT_TRUE(texbake::write_image(image, img.view()));
    out = dir / "out.ply";
  }
  void TearDown() override { fs::remove_all(dir); }

  CliRun run(const std::string& args) {
    const fs::path err_file = dir / "stderr.txt";
    const std::string cmd =
        quote(TEXBAKE_BINARY) + " bake " + args + " 2>" + quote(err_file.string());
    CliRun r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf;
    for (std::size_t n; (n = fread(buf.data(), 1, buf.size(), p)) > 0;) r.out.append(buf.data(), n);
    const int status = pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream e(err_file);
    r.err.assign(std::istreambuf_iterator<char>(e), {});
    fs::remove(err_file);
    return r;
  }

  // The plane over [0,1]^2, seen from +z.
  std::string plane() const { return "--proxy plane --origin 0,0,1 --u-axis 1,0,0 --v-axis 0,1,0"; }
  std::string base(const fs::path& output) const {
    return quote(mesh.string()) + " --texture " + quote(image.string()) + " " + plane() + " -o " +
           quote(output.string());
  }

  // Files in dir other than the inputs (outputs and any temporary leftovers).
  std::vector<std::string> outputs() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string n = e.path().filename().string();
      if (n != "grid.off" && n != "ramp.png") names.push_back(n);
    }
    return names;
  }
};

// Reads an ASCII PLY written with colours: x y z r g b per vertex.
struct PlyVertex {
  double x, y, z;
  int r, g, b;
};
std::vector<PlyVertex> read_ascii_ply(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t count = 0;
  while (std::getline(in, line) && line != "end_header") {
    if (line.rfind("element vertex ", 0) == 0) count = std::stoul(line.substr(15));
  }
  std::vector<PlyVertex> v(count);
  for (auto& p : v) in >> p.x >> p.y >> p.z >> p.r >> p.g >> p.b;
  return v;
}

using texbake::testing_cli::slurp;

TEST_F(BakeCli, BakesTheKnownBytesIntoAsciiPly) {
  const CliRun r = run(base(out) + " --ascii --filter bilinear -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");  // --quiet
  const std::vector<PlyVertex> v = read_ascii_ply(out);
  ASSERT_EQ(v.size(), static_cast<std::size_t>(kN * kN));
  for (int j = 0; j < kN; ++j) {
    for (int i = 0; i < kN; ++i) {
      const PlyVertex& p = v[j * kN + i];
      EXPECT_NEAR(p.x, coord(i), 1e-6);
      EXPECT_EQ(p.r, 40 * i + 20) << i << "," << j;
      EXPECT_EQ(p.g, 235 - 40 * j) << i << "," << j;
      EXPECT_EQ(p.b, 77);
    }
  }
}

TEST_F(BakeCli, ObjWithVertexTargetHasColouredVertices) {
  const fs::path obj = dir / "out.obj";
  const CliRun r = run(base(obj) + " --target vertex --filter bilinear -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(obj);
  std::string tag;
  double x, y, z, cr, cg, cb;
  std::string line;
  int vertices = 0;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    if (!(s >> tag) || tag != "v") continue;
    ASSERT_TRUE(s >> x >> y >> z >> cr >> cg >> cb) << line;
    const int i = vertices % kN, j = vertices / kN;
    EXPECT_NEAR(cr * 255, 40 * i + 20, 1e-3);
    EXPECT_NEAR(cg * 255, 235 - 40 * j, 1e-3);
    ++vertices;
  }
  EXPECT_EQ(vertices, kN * kN);
}

TEST_F(BakeCli, ThreadCountDoesNotChangeTheOutput) {
  // The bunny (37,706 vertices: dozens of work chunks, so two threads really
  // split the work) inside a sphere projector: slanted rays, occluded vertices
  // filled by the harmonic solve, area samples from many triangles.
  const fs::path one = dir / "one.ply", two = dir / "two.ply", report = dir / "r.json";
  const std::string sphere =
      quote(TEXBAKE_DATA_DIR "/bunny00.off") + " --texture " + quote(image.string()) +
      " --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1 -q";
  ASSERT_EQ(
      run(sphere + " --threads 1 --report " + quote(report.string()) + " -o " + quote(one.string()))
          .exit_code,
      0);
  ASSERT_EQ(run(sphere + " --threads 2 -o " + quote(two.string())).exit_code, 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(report));
  EXPECT_GT(j["counts"]["occluded"].get<int>(), 1000) << "the fill must take part";
  const std::string a = slurp(one), b = slurp(two);
  EXPECT_GT(a.size(), 37706u * 15);
  EXPECT_EQ(a, b);
}

TEST_F(BakeCli, ReportHoldsInputsProxyCountsAndTimings) {
  const fs::path report = dir / "report.json";
  const CliRun r = run(base(out) + " --report " + quote(report.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("baked 25 vertices"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j["inputs"]["mesh"], mesh.string());
  EXPECT_EQ(j["inputs"]["image"]["width"], 256);
  EXPECT_EQ(j["inputs"]["options"]["filter"], "area");
  EXPECT_EQ(j["proxy"]["kind"], "plane");
  EXPECT_EQ(j["proxy"]["origin"], nlohmann::json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ(j["counts"]["vertices"], 25);
  EXPECT_EQ(j["counts"]["triangles"], 32);
  EXPECT_EQ(j["counts"]["samples"], 25 * 16);
  EXPECT_EQ(j["counts"]["occluded"], 0);
  for (const char* stage : {"load", "scene_build", "bake", "fill", "write", "total"}) {
    EXPECT_TRUE(j["timings"][stage].is_number()) << stage;
    EXPECT_GE(j["timings"][stage].get<double>(), 0.0) << stage;
  }
}

TEST_F(BakeCli, OutsideColourAndOccludedColourAreApplied) {
  // The plane's image covers only [0, 0.5] in x: the right half is outside.
  const CliRun r = run(quote(mesh.string()) + " --texture " + quote(image.string()) +
                       " --proxy plane --origin 0,0,1 --u-axis 0.5,0,0 --v-axis 0,1,0"
                       " --filter bilinear --outside 0,1,0 --ascii -q -o " +
                       quote(out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<PlyVertex> v = read_ascii_ply(out);
  ASSERT_EQ(v.size(), 25u);
  for (const PlyVertex& p : v) {
    if (p.x > 0.5) {
      EXPECT_EQ(p.r, 0);
      EXPECT_EQ(p.g, 255);
      EXPECT_EQ(p.b, 0);
    } else {
      EXPECT_EQ(p.b, 77);
    }
  }
}

// ---- Usage errors: exit 2, the flag named, nothing written. ----

struct UsageCase {
  std::string args;  // appended to base(out) unless it starts with '!'
  std::string needle;
};

TEST_F(BakeCli, UsageErrorsExit2NamingTheFlagAndWriteNothing) {
  const std::string in = quote(mesh.string()) + " --texture " + quote(image.string());
  const std::string o = " -o " + quote(out.string());
  const std::vector<UsageCase> cases = {
      // (A missing geometry flag is fitted, bake_fit_test.cpp; a flag of another kind is not.)
      {in + " --proxy sphere --center 0,0,0 --axis 0,0,1" + o, "--axis does not apply"},
      {in + " --proxy-file " + quote(image.string()) + " --radius 2" + o, "--radius"},
      {in + " " + plane() + o + " --samples 0", "--samples"},
      {in + " " + plane() + o + " --samples -3", "--samples"},
      {in + " " + plane() + o + " --samples many", "--samples"},
      {in + " " + plane() + o + " --filter nearest", "--filter"},
      {in + " " + plane() + o + " --visibility some", "--visibility"},
      {in + " " + plane() + o + " --occluded 2,0,0", "--occluded"},
      {in + " " + plane() + o + " --occluded 1,0", "--occluded"},
      {in + " " + plane() + o + " --occluded black", "--occluded"},
      {in + " " + plane() + o + " --outside 0,0,0,0,0", "--outside"},
      {in + " " + plane() + o + " --wrap mirror", "--wrap"},
      {in + " " + plane() + o + " --threads 0", "--threads"},
      {in + " " + plane() + o + " --target texels", "--target"},
      {in + " --proxy sphere --center 0,0,0 --radius 1 --wrap repeat" + o, "--wrap"},
      {in + " " + plane() + " -o " + quote((dir / "out.stl").string()), "unknown output format"},
      {in + " " + plane() + " --target atlas" + o, "PLY has no standard texture"},
      {in + " " + plane(), "--output"},
      {quote(mesh.string()) + " " + plane() + o, "--texture"},
      {in + o, "--proxy"},
  };
  for (const UsageCase& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("texbake: error: ", 0), 0u) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_TRUE(outputs().empty()) << c.args;
  }
}

// ---- Failed work: exit 1, the file named, nothing written. ----

TEST_F(BakeCli, AtlasOfAMeshWithOnlyDegenerateTrianglesFailsWithExit1NamingTheMesh) {
  // The mesh loads (degenerate triangles are not fatal, SPEC section 8), but
  // there is nothing to lay out: the work fails on this file (exit 1), it is
  // not a usage error.
  const fs::path degenerate = dir / "degenerate.off";
  std::ofstream(degenerate) << "OFF\n4 2 0\n0 0 0\n1 1 1\n2 2 2\n3 3 3\n3 0 1 2\n3 1 2 3\n";
  const fs::path obj = dir / "deg.obj";
  const CliRun r =
      run(quote(degenerate.string()) + " --texture " + quote(image.string()) +
          " --proxy sphere --center 0,0,0 --radius 1 --uv generate -q -o " + quote(obj.string()));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("texbake: error: " + degenerate.string()), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(obj));
  EXPECT_FALSE(fs::exists(dir / "deg.png"));
  EXPECT_FALSE(fs::exists(dir / "deg.mtl"));
}

TEST_F(BakeCli, BadInputsExit1NamingTheFileAndWriteNothing) {
  const fs::path nan_mesh = dir / "nan.off";
  std::ofstream(nan_mesh) << "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n";
  const fs::path empty_image = dir / "empty.png";
  std::ofstream(empty_image).close();
  const fs::path missing = dir / "missing.off";
  const fs::path no_folder = dir / "no_such_folder" / "out.ply";
  struct Case {
    std::string args, needle;
  };
  const std::string tex = " --texture " + quote(image.string()) + " ";
  const std::string o = " -o " + quote(out.string());
  const std::vector<Case> cases = {
      {quote(missing.string()) + tex + plane() + o, missing.string()},
      {quote(nan_mesh.string()) + tex + plane() + o, nan_mesh.string()},
      {quote(mesh.string()) + " --texture " + quote((dir / "none.png").string()) + " " + plane() +
           o,
       "none.png"},
      {quote(mesh.string()) + " --texture " + quote(empty_image.string()) + " " + plane() + o,
       empty_image.string()},
      {quote(mesh.string()) + tex + plane() + " -o " + quote(no_folder.string()),
       no_folder.string()},
      {quote(mesh.string()) + tex + plane() + o + " --report " +
           quote((dir / "nowhere" / "r.json").string()),
       "r.json"},
  };
  for (const Case& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("texbake: error: ", 0), 0u) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << c.args << "\n" << r.err;
    std::vector<std::string> left = outputs();
    std::erase_if(left, [](const std::string& n) { return n == "nan.off" || n == "empty.png"; });
    EXPECT_TRUE(left.empty()) << c.args << ": " << (left.empty() ? "" : left.front());
  }
}

TEST_F(BakeCli, FailedBakeLeavesAnExistingOutputUntouched) {
  std::ofstream(out) << "previous result";
  const CliRun r = run(quote(mesh.string()) + " --texture " + quote((dir / "none.png").string()) +
                       " " + plane() + " -o " + quote(out.string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(slurp(out), "previous result");
}

}  // namespace
