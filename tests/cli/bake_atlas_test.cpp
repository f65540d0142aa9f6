// texbake bake --target atlas and .glb outputs through the built binary
// (SPEC sections 4, 5, 7): OBJ + MTL + PNG and GLB written and re-opened
// (OpenImageIO, a few lines of OBJ/MTL parsing, tinygltf's loader), atlas
// values against the image resampled independently, usage errors, no
// partial outputs, thread-count independence.
#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "mesh_io/image_io.h"
#include "run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::RunResult;

const fs::path kData = TEXBAKE_DATA_DIR;
constexpr double kPi = 3.14159265358979323846;

std::string q(const fs::path& p) {
  return testing_cli::shell_quote(p.string());
}
using testing_cli::slurp;

// The test image's colour at (u, v): periodic in u so the sphere's seam
// does not matter, a ramp in v.
float red_at(double u) {
  return static_cast<float>(0.5 + 0.5 * std::cos(2 * kPi * u));
}
float green_at(double v) {
  return static_cast<float>(v);
}

class BakeAtlasCli : public ::testing::Test {
 protected:
  static constexpr int kNu = 32, kNv = 16;  // UV sphere segments (azimuth, polar)

  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_atlas_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    write_uv_sphere(dir_ / "sphere.obj");
    // 128 x 64 image: red = red_at(u), green = green_at(v), blue = 0.25 at
    // texel centres (SPEC section 1: u = (x + 0.5) / W, v = 1 - (y + 0.5) / H).
    Image img;
    img.width = 128;
    img.height = 64;
    img.pixels.resize(std::size_t(128) * 64 * 4);
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 128; ++x) {
        float* p = &img.pixels[(std::size_t(y) * 128 + x) * 4];
        p[0] = red_at((x + 0.5) / 128);
        p[1] = green_at(1 - (y + 0.5) / 64);
        p[2] = 0.25f;
        p[3] = 1;
      }
    }
    ASSERT_TRUE(write_image(dir_ / "map.png", img.view()));
  }
  void TearDown() override {
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add);
    fs::remove_all(dir_);
  }

  // A unit UV sphere whose vt are the sphere proxy's own (u, v) (pole +Z,
  // equator +X): v = phi / pi from the south pole, u counter-clockwise from
  // +X. The seam column is duplicated (u = 0 and u = 1), pole triangles are
  // single triangles.
  static void write_uv_sphere(const fs::path& path) {
    std::ofstream obj(path);
    char line[160];
    for (int j = 0; j <= kNv; ++j) {
      for (int i = 0; i <= kNu; ++i) {
        const double u = double(i) / kNu, v = double(j) / kNv;
        const double s = std::sin(kPi * v);
        std::snprintf(line, sizeof line, "v %.9f %.9f %.9f\nvt %.9f %.9f\n",
                      s * std::cos(2 * kPi * u), s * std::sin(2 * kPi * u), -std::cos(kPi * v), u,
                      v);
        obj << line;
      }
    }
    auto id = [](int i, int j) { return j * (kNu + 1) + i + 1; };  // 1-based, v and vt alike
    auto face = [&](int a, int b, int c) {
      obj << "f " << a << "/" << a << " " << b << "/" << b << " " << c << "/" << c << "\n";
    };
    for (int j = 0; j < kNv; ++j) {
      for (int i = 0; i < kNu; ++i) {
        // Counter-clockwise seen from outside: east (i + 1) then north (j + 1).
        if (j != 0) face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        if (j != kNv - 1) face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  }

  std::string sphere_bake(const fs::path& out) const {
    return "bake " + q(dir_ / "sphere.obj") + " --texture " + q(dir_ / "map.png") +
           " --proxy sphere --center 0,0,0 --radius 1 --pole 0,0,1 --equator 1,0,0 -o " + q(out);
  }

  // Files in the folder other than the inputs.
  std::vector<std::string> outputs() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (n != "sphere.obj" && n != "map.png") names.push_back(n);
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path dir_;
};

TEST_F(BakeAtlasCli, ObjOutputWritesMtlAndPngBesideItMatchingTheImage) {
  const fs::path out = dir_ / "baked.obj";
  const RunResult r = testing_cli::run_texbake(sphere_bake(out) + " --uv mesh --size 64");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("baked a 64x64 atlas (uv mesh"), std::string::npos) << r.out;
  EXPECT_EQ(outputs(), (std::vector<std::string>{"baked.mtl", "baked.obj", "baked.png"}));

  // The OBJ names its MTL, the MTL its PNG, both relative (same folder).
  const std::string obj = slurp(out), mtl = slurp(dir_ / "baked.mtl");
  EXPECT_NE(obj.find("mtllib baked.mtl"), std::string::npos) << obj.substr(0, 200);
  EXPECT_NE(obj.find("usemtl "), std::string::npos);
  EXPECT_NE(mtl.find("map_Kd baked.png"), std::string::npos) << mtl;

  // The atlas is the image resampled through the sphere: at texel (x, y)
  // the layout's (u, v) is the texel centre, and the sphere maps the 3D
  // point there back to about the same (u, v) (the mesh is faceted: a
  // chord's point maps a little off its interpolated vt).
  Expected<Image> atlas = read_image(dir_ / "baked.png");
  ASSERT_TRUE(atlas) << atlas.error().message;
  ASSERT_EQ(atlas->width, 64);
  ASSERT_EQ(atlas->height, 64);
  double sum = 0, worst = 0;
  int n = 0, far = 0;
  for (int y = 0; y < 64; ++y) {
    const double v = 1 - (y + 0.5) / 64;
    // The pole rows of the layout are half covered (single triangles): their
    // other half is padding, copied from neighbours.
    if (v < 1.0 / kNv || v > 1 - 1.0 / kNv) continue;
    for (int x = 0; x < 64; ++x) {
      const double u = (x + 0.5) / 64;
      const float* p = &atlas->pixels[(std::size_t(y) * 64 + x) * 4];
      const double e = std::max(
          {std::abs(p[0] - red_at(u)), std::abs(p[1] - green_at(v)), std::abs(p[2] - 0.25f)});
      sum += e;
      worst = std::max(worst, e);
      far += e > 0.03;
      ++n;
      EXPECT_EQ(p[3], 1.0f) << x << "," << y;
    }
  }
  EXPECT_LT(sum / n, 0.008) << "mean error";
  EXPECT_LE(far, n / 100) << "texels more than 0.03 off; worst " << worst;
}

TEST_F(BakeAtlasCli, GlbEmbedsTheSameAtlasAsTheObj) {
  const fs::path obj = dir_ / "a.obj", glb = dir_ / "a.glb";
  ASSERT_EQ(testing_cli::run_texbake(sphere_bake(obj) + " --size 32 -q").exit_code, 0);
  const RunResult r = testing_cli::run_texbake(sphere_bake(glb) + " --size 32 -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());  // --quiet

  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, glb.string())) << err;
  ASSERT_EQ(model.meshes.size(), 1u);
  const tinygltf::Primitive& prim = model.meshes[0].primitives.at(0);
  EXPECT_TRUE(prim.attributes.count("POSITION"));
  EXPECT_TRUE(prim.attributes.count("TEXCOORD_0"));
  const tinygltf::Material& mat = model.materials.at(prim.material);
  const int tex = mat.pbrMetallicRoughness.baseColorTexture.index;
  ASSERT_GE(tex, 0);
  const tinygltf::Image& image = model.images.at(model.textures.at(tex).source);
  EXPECT_EQ(image.mimeType, "image/png");
  ASSERT_EQ(image.width, 32);
  ASSERT_EQ(image.height, 32);
  ASSERT_EQ(image.bits, 8);
  // Same bake, same atlas: the embedded PNG decodes to the OBJ's PNG.
  Expected<Image> png = read_image(dir_ / "a.png");
  ASSERT_TRUE(png) << png.error().message;
  const int comp = image.component;
  ASSERT_GE(comp, 3);
  for (int i = 0; i < 32 * 32; ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(image.image[std::size_t(i) * comp + c], std::lround(png->pixels[i * 4 + c] * 255))
          << i << "," << c;
    }
  }
}

// glTF COLOR_0 is linear (SPEC section 7): a one-colour image of sRGB
// 8-bit (128, 64, 255) gives every vertex ((c/255 + 0.055) / 1.055)^2.4:
// 128 -> 0.2158605, 64 -> 0.0512695, 255 -> 1 (IEC 61966-2-1).
TEST_F(BakeAtlasCli, VertexTargetGlbHasLinearColor0PerInputVertex) {
  Image one;
  one.width = one.height = 1;
  one.pixels = {128 / 255.f, 64 / 255.f, 1, 1};
  ASSERT_TRUE(write_image(dir_ / "one.png", one.view()));
  const fs::path glb = dir_ / "v.glb";
  const RunResult r = testing_cli::run_texbake(
      "bake " + q(dir_ / "sphere.obj") + " --texture " + q(dir_ / "one.png") +
      " --proxy sphere --center 0,0,0 --radius 1 --target vertex -q -o " + q(glb));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, glb.string())) << err;
  const tinygltf::Primitive& prim = model.meshes.at(0).primitives.at(0);
  ASSERT_TRUE(prim.attributes.count("COLOR_0"));
  const tinygltf::Accessor& a = model.accessors[prim.attributes.at("COLOR_0")];
  ASSERT_EQ(a.type, TINYGLTF_TYPE_VEC4);
  ASSERT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  EXPECT_EQ(a.count, std::size_t((kNu + 1) * (kNv + 1)));  // the input's vertices
  const tinygltf::BufferView& view = model.bufferViews[a.bufferView];
  const unsigned char* data =
      model.buffers[view.buffer].data.data() + view.byteOffset + a.byteOffset;
  const std::size_t stride = view.byteStride ? view.byteStride : 16;
  for (std::size_t i = 0; i < a.count; ++i) {
    float c[4];
    std::memcpy(c, data + i * stride, sizeof c);
    ASSERT_NEAR(c[0], 0.2158605f, 2e-6) << i;
    ASSERT_NEAR(c[1], 0.0512695f, 2e-6) << i;
    ASSERT_NEAR(c[2], 1.0f, 2e-6) << i;
    ASSERT_NEAR(c[3], 1.0f, 2e-6) << i;
  }
}

TEST_F(BakeAtlasCli, ThreadCountDoesNotChangeTheAtlas) {
  // Generated UVs on a shared mesh: layout, bake and padding all threaded.
  const std::string bake = "bake " + q(kData / "suzanne_uv.obj") + " --texture " +
                           q(dir_ / "map.png") + " --proxy sphere --uv generate --size 128 -q";
  const fs::path one = dir_ / "one.obj", two = dir_ / "two.obj";
  RunResult r = testing_cli::run_texbake(bake + " --threads 1 -o " + q(one));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = testing_cli::run_texbake(bake + " --threads 2 -o " + q(two));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string png1 = slurp(dir_ / "one.png"), png2 = slurp(dir_ / "two.png");
  EXPECT_GT(png1.size(), 100u);
  EXPECT_EQ(png1, png2);
  // The OBJs differ only in the names of their MTL and material library.
  std::string obj2 = slurp(two);
  for (std::size_t at; (at = obj2.find("two.")) != std::string::npos;) obj2.replace(at, 4, "one.");
  EXPECT_EQ(slurp(one), obj2);
}

TEST_F(BakeAtlasCli, MeshUvsAreCheckedWithWarnings) {
  // suzanne_uv.obj's UVs are Blender's: inside [0, 1], no overlaps expected
  // to be reported beyond what the check counts. The report states the
  // counts; a warning line appears exactly when a count is non-zero.
  const fs::path out = dir_ / "s.obj", report = dir_ / "r.json";
  const RunResult r = testing_cli::run_texbake(
      "bake " + q(kData / "suzanne_uv.obj") + " --texture " + q(dir_ / "map.png") +
      " --proxy sphere --size 256 --report " + q(report) + " -o " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j.at("target"), "atlas");
  EXPECT_EQ(j.at("atlas").at("uv"), "mesh");  // auto: the mesh has UVs
  const auto outside = j.at("atlas").at("uv_check").at("corners_outside").get<std::size_t>();
  const auto overlap = j.at("atlas").at("uv_check").at("overlap_texels").get<std::size_t>();
  EXPECT_EQ(r.err.find("UV corners lie outside") != std::string::npos, outside > 0) << r.err;
  EXPECT_EQ(r.err.find("overlapping UV triangles") != std::string::npos, overlap > 0) << r.err;
}

TEST_F(BakeAtlasCli, UvsOutsideTheUnitSquareAreWarnedAboutWithCounts) {
  // Two triangles whose four UV corners are (0,0), (2,0), (2,1), (0,1):
  // corners (2,0) and (2,1) are outside, used by 3 face corners.
  const fs::path mesh = dir_ / "wide.obj";
  std::ofstream(mesh) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                         "vt 0 0\nvt 2 0\nvt 2 1\nvt 0 1\n"
                         "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  const fs::path report = dir_ / "r.json";
  const RunResult r = testing_cli::run_texbake(
      "bake " + q(mesh) + " --texture " + q(dir_ / "map.png") +
      " --proxy plane --origin 0,0,0 --u-axis 1,0,0 --v-axis 0,1,0 --uv mesh --size 16 -q"
      " --report " +
      q(report) + " -o " + q(dir_ / "w.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(report));
  const auto outside = j.at("atlas").at("uv_check").at("corners_outside").get<std::size_t>();
  EXPECT_GT(outside, 0u);
  EXPECT_NE(r.err.find("texbake: warning: " + std::to_string(outside) + " UV corners"),
            std::string::npos)
      << r.err;  // warnings print even with --quiet
}

TEST_F(BakeAtlasCli, ReportHoldsTheAtlasObjectCountsAndTimings) {
  const fs::path report = dir_ / "r.json";
  const RunResult r =
      testing_cli::run_texbake(sphere_bake(dir_ / "o.glb") +
                               " --size 32 --samples 2 --padding inf -q --report " + q(report));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j.at("target"), "atlas");
  EXPECT_EQ(j.at("proxy").at("kind"), "sphere");
  EXPECT_EQ(j.at("proxy_fitted"), nlohmann::json::array());
  EXPECT_EQ(j.at("inputs").at("options").at("samples"), 2);
  const nlohmann::json& a = j.at("atlas");
  EXPECT_EQ(a.at("size"), 32);
  EXPECT_EQ(a.at("samples_per_texel"), 2);
  EXPECT_EQ(a.at("padding"), "inf");
  const auto texels = j.at("counts").at("texels").get<std::size_t>();
  EXPECT_GT(texels, 32u * 32 / 2);
  EXPECT_LE(texels, 32u * 32);
  EXPECT_EQ(j.at("counts").at("samples"), texels * 2);
  EXPECT_EQ(j.at("counts").at("texels"), a.at("counts").at("texels"));
  // With --padding inf every texel not covered is filled.
  EXPECT_EQ(j.at("counts").at("padded").get<std::size_t>() + texels, 32u * 32);
  EXPECT_EQ(j.at("counts").at("vertices"), (kNu + 1) * (kNv + 1));
  for (const char* stage : {"load", "fit", "uv_layout", "rasterize", "scene_build", "sample",
                            "fill", "pad", "write", "total"}) {
    ASSERT_TRUE(j.at("timings").at(stage).is_number()) << stage;
    EXPECT_GE(j.at("timings").at(stage).get<double>(), 0.0) << stage;
  }
}

// ---- Usage errors (exit 2) and failed work (exit 1): nothing written. ----

TEST_F(BakeAtlasCli, UsageErrorsExit2NamingTheFlagAndWriteNothing) {
  const fs::path plain = dir_ / "plain.off";  // a mesh without UVs
  std::ofstream(plain) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::string in = "bake " + q(dir_ / "sphere.obj") + " --texture " + q(dir_ / "map.png") +
                         " --proxy sphere --center 0,0,0 --radius 1";
  struct Case {
    std::string args, needle;
  };
  const std::vector<Case> cases = {
      {in + " --target atlas -o " + q(dir_ / "o.ply"), "PLY has no standard texture"},
      {in + " --size 0 -o " + q(dir_ / "o.obj"), "--size 0"},
      {in + " --size 16385 -o " + q(dir_ / "o.obj"), "--size 16385"},
      {in + " --size -4 -o " + q(dir_ / "o.obj"), "--size"},
      {in + " --samples 257 -o " + q(dir_ / "o.obj"), "--samples 257"},
      {in + " --padding lots -o " + q(dir_ / "o.obj"), "--padding"},
      {in + " --uv wrong -o " + q(dir_ / "o.obj"), "--uv"},
      {in + " --format exr -o " + q(dir_ / "o.glb"), "--format exr"},
      {in + " --format jpg -o " + q(dir_ / "o.obj"), "--format"},
      {in + " --size 512 -o " + q(dir_ / "o.ply"), "--size applies to --target atlas only"},
      {in + " --uv generate --target vertex -o " + q(dir_ / "o.obj"), "--uv applies"},
      {in + " --filter area -o " + q(dir_ / "o.obj"), "--filter area applies to --target vertex"},
      {in + " --ascii -o " + q(dir_ / "o.obj"), "--ascii"},
      {in + " -o " + q(dir_ / "o.stl"), "unknown output format '.stl'"},
      {"bake " + q(plain) + " --texture " + q(dir_ / "map.png") +
           " --proxy sphere --center 0,0,0 --radius 1 --uv mesh -o " + q(dir_ / "o.obj"),
       "has no UV coordinates"},
  };
  for (const Case& c : cases) {
    const RunResult r = testing_cli::run_texbake(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("texbake: error: ", 0), 0u) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << c.args << "\n" << r.err;
    std::vector<std::string> left = outputs();
    std::erase(left, "plain.off");
    EXPECT_TRUE(left.empty()) << c.args << ": " << (left.empty() ? "" : left.front());
  }
}

TEST_F(BakeAtlasCli, UnwritableAtlasBesideTheObjExits1AndLeavesNothing) {
  // A folder where the atlas PNG would go: the PNG cannot be written.
  fs::create_directory(dir_ / "o.png");
  const RunResult r = testing_cli::run_texbake(sphere_bake(dir_ / "o.obj") + " --size 16");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("texbake: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("o.png"), std::string::npos) << r.err;
  EXPECT_EQ(outputs(), (std::vector<std::string>{"o.png"}));  // the folder only: no OBJ, MTL, temp
  EXPECT_TRUE(fs::is_empty(dir_ / "o.png"));
}

}  // namespace
}  // namespace texbake
