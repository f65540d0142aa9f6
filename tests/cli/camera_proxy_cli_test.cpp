// A camera as a --proxy-file (SPEC section 9, issue #13 item 1): `map`
// prints the photo pixel, `render --texture PHOTO --proxy-file CAMERA`
// projects the photo back onto the mesh, and `bake` colours the mesh from
// that one photo. Expected values are worked out by hand (map), or come from
// a second route: a photo rendered by `render --colmap` from a known camera,
// projected back through that camera and seen from the same camera, is the
// photo itself (every pixel centre's ray hits a point that projects back to
// that pixel centre, where the bilinear lookup returns the pixel exactly).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "mesh_io/colmap_model.h"
#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "tests/cli/run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::run_texbake;

std::string q(const fs::path& p) {
  return testing_cli::quoted(p);
}

const std::string kData = TEXBAKE_DATA_DIR;

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A PINHOLE camera 5 units in front of the origin, looking along +z:
// x = 500 X / Z + 320, y = 400 Y / Z + 240 with Z = Pz + 5.
const char* kPinhole = R"({"kind":"camera","model":"PINHOLE","width":640,"height":480,)"
                       R"("params":[500,400,320,240],"pose":{"q_wxyz":[1,0,0,0],"t":[0,0,5]}})";

class CameraProxyMap : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_cli::fresh_test_dir("texbake_camera_map");
    write_file(dir_ / "cam.json", kPinhole);
  }
  void TearDown() override { fs::remove_all(dir_); }
  nlohmann::json map_json(const std::string& point) {
    const testing_cli::RunResult r =
        run_texbake("map --proxy-file " + q(dir_ / "cam.json") + " --point " + point + " --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  }
  fs::path dir_;
};

TEST_F(CameraProxyMap, PinholeByHand) {
  // P = (1, 0.5, 0): camera (1, 0.5, 5): x = 100 + 320, y = 40 + 240.
  nlohmann::json j = map_json("1,0.5,0");
  EXPECT_EQ(j["status"], "ok");
  EXPECT_DOUBLE_EQ(j["x"].get<double>(), 420.0);
  EXPECT_DOUBLE_EQ(j["y"].get<double>(), 280.0);
  EXPECT_DOUBLE_EQ(j["u"].get<double>(), 420.0 / 640);
  EXPECT_DOUBLE_EQ(j["v"].get<double>(), 1 - 280.0 / 480);
  EXPECT_DOUBLE_EQ(j["depth"].get<double>(), 5.0);
  // The photo's top-left corner (0, 0): X/Z = -320/500, Y/Z = -240/400 at Z = 10.
  j = map_json("-6.4,-6,5");
  EXPECT_EQ(j["status"], "ok");
  EXPECT_NEAR(j["x"].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(j["y"].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(j["v"].get<double>(), 1.0, 1e-15);
}

TEST_F(CameraProxyMap, BehindOffThePhotoAndPastTheTurningPointAreOutside) {
  nlohmann::json j = map_json("0,0,-6");  // Z = -1
  EXPECT_EQ(j["status"], "outside");
  EXPECT_EQ(j["reason"], "behind the camera");
  EXPECT_TRUE(j["x"].is_null());
  EXPECT_TRUE(j["u"].is_null());
  j = map_json("10,0,0");  // x = 500 * 2 + 320 = 1320 > 640
  EXPECT_EQ(j["status"], "outside");
  EXPECT_EQ(j["reason"], "outside the photo");
  EXPECT_DOUBLE_EQ(j["x"].get<double>(), 1320.0);
  // SIMPLE_RADIAL with k = -0.5: r_d = r (1 - 0.5 r^2) turns at r^2 = 2/3.
  // r = 1 (P = (5, 0, 0), Z = 5) lands at r_d = 0.5, inside the photo
  // (x = 1000 * 0.5 + 1000), yet past the turning point.
  write_file(dir_ / "cam.json",
             R"({"kind":"camera","model":"SIMPLE_RADIAL","width":2000,"height":2000,)"
             R"("params":[1000,1000,1000,-0.5],"pose":{"q_wxyz":[1,0,0,0],"t":[0,0,5]}})");
  j = map_json("5,0,0");
  EXPECT_EQ(j["status"], "outside");
  EXPECT_EQ(j["reason"], "past the distortion's turning point");
  EXPECT_DOUBLE_EQ(j["x"].get<double>(), 1500.0);
  j = map_json("3,0,0");  // r = 0.6, r^2 = 0.36 < 2/3: x = 1000 * 0.6 * 0.82 + 1000
  EXPECT_EQ(j["status"], "ok");
  EXPECT_NEAR(j["x"].get<double>(), 1492.0, 1e-9);
}

TEST_F(CameraProxyMap, HumanOutputAndUsageErrors) {
  testing_cli::RunResult r =
      run_texbake("map --proxy-file " + q(dir_ / "cam.json") + " --point 1,0.5,0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("camera (PINHOLE, 640 x 480)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("pixel    x 420, y 280"), std::string::npos) << r.out;
  r = run_texbake("map --proxy-file " + q(dir_ / "cam.json") + " --point 0,0,-9");
  EXPECT_NE(r.out.find("status   outside (behind the camera)"), std::string::npos) << r.out;
  r = run_texbake("map --proxy-file " + q(dir_ / "cam.json") + " --dir 1,0,0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("texbake: error: --dir applies only to a sphere"), std::string::npos);
  r = run_texbake("map --proxy-file " + q(dir_ / "cam.json") + " --point 0,0,0 --image 10x10");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--image does not apply to a camera"), std::string::npos) << r.err;
  // A bad camera file is the file's fault, named with its key.
  write_file(dir_ / "cam.json",
             R"({"kind":"camera","model":"PINHOLE","width":640,"height":480,)"
             R"("params":[500,400,320],"pose":{"q_wxyz":[1,0,0,0],"t":[0,0,5]}})");
  r = run_texbake("map --proxy-file " + q(dir_ / "cam.json") + " --point 0,0,0");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cam.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("params"), std::string::npos) << r.err;
  // fit cannot take a camera: the proxy reader says why.
  write_file(dir_ / "cam.json", kPinhole);
  r = run_texbake("fit " + q(kData + "/bunny00.off") + " --proxy-file " + q(dir_ / "cam.json") +
                  " -o " + q(dir_ / "out.json"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(fs::exists(dir_ / "out.json"));
}

// The photos of a COLMAP workspace rendered by texbake from the bunny, and
// each camera as a camera proxy file.
class CameraProxyPhotos : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("texbake_camera_proxy_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const testing_cli::RunResult r =
        testing_cli::render_bunny_workspace(*dir_, 6, "320x240", " --samples 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Expected<std::vector<ColmapImage>> model = read_colmap_model(*dir_ / "ws/sparse/0");
    ASSERT_TRUE(model) << model.error().message;
    ASSERT_EQ(model->size(), 6u);
    for (const ColmapImage& image : *model) {
      const CameraSpec& spec = image.camera.spec();
      nlohmann::json j;
      j["kind"] = "camera";
      j["model"] = std::string(camera_model_name(spec.model));
      j["width"] = spec.width;
      j["height"] = spec.height;
      j["params"] = spec.params;
      const auto& m = spec.pose.r;
      j["pose"] = {{"R", {{m[0], m[1], m[2]}, {m[3], m[4], m[5]}, {m[6], m[7], m[8]}}},
                   {"t", {spec.pose.t.x, spec.pose.t.y, spec.pose.t.z}}};
      write_file(*dir_ / (fs::path(image.name).stem().string() + ".json"), j.dump());
    }
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path* dir_;
};
fs::path* CameraProxyPhotos::dir_ = nullptr;

TEST_F(CameraProxyPhotos, RenderingAPhotoBackFromItsCameraGivesThePhoto) {
  const fs::path& d = *dir_;
  for (int view : {0, 2, 5}) {
    const std::string name = "view_0" + std::to_string(view);
    const fs::path photo = d / "ws/images" / (name + ".png");
    const fs::path back = d / (name + "_back.png");
    // --views 6 puts view k at azimuth 60 k, elevation 20.
    testing_cli::RunResult r =
        run_texbake("render " + q(kData + "/bunny00.off") + " --texture " + q(photo) +
                    " --proxy-file " + q(d / (name + ".json")) + " --up y --unlit --view " +
                    std::to_string(60 * view) + ",20 --samples 1 --size 320x240 -o " + q(back));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Expected<Image> a = read_image(photo), b = read_image(back);
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->width, b->width);
    ASSERT_EQ(a->height, b->height);
    // Same coverage (alpha), and on covered pixels the same colour: measured
    // identical; one level allows a different rounding of the ray's hit.
    std::size_t covered = 0;
    float worst = 0;
    for (std::size_t i = 0; i < a->pixels.size(); i += 4) {
      ASSERT_EQ(a->pixels[i + 3], b->pixels[i + 3]) << "pixel " << i / 4;
      if (a->pixels[i + 3] == 0) continue;
      ++covered;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(a->pixels[i + c] - b->pixels[i + c]));
    }
    EXPECT_GT(covered, 10000u);
    EXPECT_LE(worst, 1.0f / 255 + 1e-6f) << name;
  }
}

TEST_F(CameraProxyPhotos, PointsOffThePhotoAreGreyOrTheOutsideColour) {
  // View 0's camera with its principal point moved by half the photo's
  // width: whatever projected right of the photo's centre now lands off it.
  const fs::path& d = *dir_;
  nlohmann::json cam = nlohmann::json::parse(testing_cli::slurp(d / "view_00.json"));
  cam["params"][2] = cam["params"][2].get<double>() + 160;
  write_file(d / "shifted.json", cam.dump());
  auto render = [&](const std::string& extra, const fs::path& out) {
    const testing_cli::RunResult r = run_texbake(
        "render " + q(kData + "/bunny00.off") + " --texture " + q(d / "ws/images/view_00.png") +
        " --proxy-file " + q(d / "shifted.json") +
        " --up y --unlit --view 0,20 --samples 1 --size 320x240 " + extra + " -o " + q(out));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    Expected<Image> image = read_image(out);
    EXPECT_TRUE(image);
    return std::move(image).value();
  };
  const Image magenta = render("--outside 1,0,1", d / "magenta.png");
  const Image grey = render("", d / "grey.png");
  std::size_t covered = 0, off = 0;
  for (std::size_t i = 0; i < magenta.pixels.size(); i += 4) {
    if (magenta.pixels[i + 3] == 0) continue;
    ++covered;
    const float* m = &magenta.pixels[i];
    if (m[0] == 1 && m[1] == 0 && m[2] == 1) {
      ++off;
      // Without --outside the same pixel is the grey albedo (0.7).
      // 0.7 is 178.5 levels: 8 bits round it to 178 or 179.
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(grey.pixels[i + c], 0.7f, 0.501f / 255);
    }
  }
  EXPECT_GT(off, covered / 5) << off << " of " << covered;
  EXPECT_LT(off, covered * 4 / 5) << off << " of " << covered;
}

TEST_F(CameraProxyPhotos, RenderBadInputs) {
  const fs::path& d = *dir_;
  // A photo of the wrong size is an error naming it, with no output.
  testing_cli::RunResult r =
      run_texbake("render " + q(kData + "/bunny00.off") + " --texture " + q(kData + "/earth.jpg") +
                  " --proxy-file " + q(d / "view_00.json") + " --up y -o " + q(d / "bad.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("earth.jpg: the photo is"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "bad.png"));
  r = run_texbake("render " + q(kData + "/bunny00.off") + " --texture " +
                  q(d / "ws/images/view_00.png") + " --proxy-file " + q(d / "view_00.json") +
                  " --wrap repeat -o " + q(d / "bad.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--wrap"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "bad.png"));
}

TEST_F(CameraProxyPhotos, TruncatedBinaryModelAndSkewRotationAreErrorsWithNoOutput) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(model);
  const fs::path bin = d / "bin/sparse/0";
  fs::create_directories(bin);
  ASSERT_TRUE(write_colmap_model(bin, *model, /*binary=*/true));
  // Cut images.bin inside its third image record.
  const std::string images = testing_cli::slurp(bin / "images.bin");
  write_file(bin / "images.bin", images.substr(0, images.size() * 5 / 12));
  testing_cli::RunResult r = run_texbake("bake " + bunny + " --cameras " + q(bin) + " --images " +
                                         q(d / "ws/images") + " -o " + q(d / "bin.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("texbake: error: "), std::string::npos) << r.err;
  // (The record count is checked against the file's size before any record
  // is read.)
  EXPECT_NE(r.err.find("images.bin: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "bin.ply"));

  // A JSON camera list whose R is skewed by 1e-3: not orthonormal within 1e-5.
  nlohmann::json cam = nlohmann::json::parse(testing_cli::slurp(d / "view_00.json"));
  cam["pose"]["R"][0][1] = cam["pose"]["R"][0][1].get<double>() + 1e-3;
  cam["image"] = "view_00.png";
  nlohmann::json list;
  list["cameras"] = nlohmann::json::array({cam});
  write_file(d / "skew.json", list.dump());
  r = run_texbake("bake " + bunny + " --cameras " + q(d / "skew.json") + " --images " +
                  q(d / "ws/images") + " -o " + q(d / "skew.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("skew.json: cameras[0]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("orthonormal"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "skew.ply"));
}

TEST_F(CameraProxyPhotos, BakingOnePhotoThroughItsCameraFile) {
  // bake --proxy-file CAMERA --texture PHOTO is bake --cameras with that one
  // photo, except that the camera proxy sees up to 90 degrees (SPEC section
  // 9: only surfaces facing away are unseen) where several photos stop at 75.
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  const fs::path photo = d / "ws/images/view_02.png";
  nlohmann::json cam = nlohmann::json::parse(testing_cli::slurp(d / "view_02.json"));
  cam["image"] = "view_02.png";
  nlohmann::json list;
  list["cameras"] = nlohmann::json::array({cam});
  write_file(d / "one.json", list.dump());
  testing_cli::RunResult r = run_texbake(
      "bake " + bunny + " --proxy-file " + q(d / "view_02.json") + " --texture " + q(photo) +
      " --occluded 1,0,1 -q --report " + q(d / "single.json") + " -o " + q(d / "single.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --cameras " + q(d / "one.json") + " --images " +
                  q(d / "ws/images") + " --occluded 1,0,1 -q -o " + q(d / "list.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Expected<LoadedMesh> single = read_mesh(d / "single.ply"), listed = read_mesh(d / "list.ply");
  ASSERT_TRUE(single && listed);
  auto magenta = [](const std::array<float, 4>& c) { return c[0] == 1 && c[1] == 0 && c[2] == 1; };
  std::size_t both = 0, only_single = 0;
  for (std::size_t v = 0; v < single->mesh.vertex_colors.size(); ++v) {
    const auto& a = single->mesh.vertex_colors[v];
    const auto& b = listed->mesh.vertex_colors[v];
    if (!magenta(b)) {
      ASSERT_FALSE(magenta(a)) << "vertex " << v;  // what 75 degrees sees, 90 sees
      EXPECT_EQ(a, b) << "vertex " << v;           // through the same lens, the same sample
      ++both;
    } else if (!magenta(a)) {
      ++only_single;  // seen between 75 and 90 degrees
    }
  }
  EXPECT_GT(both, 5000u);
  EXPECT_GT(only_single, 100u);
  const std::string report = testing_cli::slurp(d / "single.json");
  EXPECT_NE(report.find("\"proxy_file\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"visible\": " + std::to_string(both + only_single)), std::string::npos)
      << report;

  // The atlas target through the same camera: an OBJ + MTL + PNG set.
  r = run_texbake("bake " + bunny + " --proxy-file " + q(d / "view_02.json") + " --texture " +
                  q(photo) + " --target atlas --uv generate --size 256 -q -o " +
                  q(d / "single_atlas.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "single_atlas.png"));

  // Flags of the analytic projection do not apply (exit 2, no output).
  for (const std::string flag : {"--filter bilinear", "--visibility all", "--linear",
                                 "--outside 1,0,0", "--blend best", "--radius 2"}) {
    r = run_texbake("bake " + bunny + " --proxy-file " + q(d / "view_02.json") + " --texture " +
                    q(photo) + " " + flag + " -o " + q(d / "flag.ply"));
    EXPECT_EQ(r.exit_code, 2) << flag << ": " << r.err;
    EXPECT_FALSE(fs::exists(d / "flag.ply")) << flag;
  }
  // A photo of another aspect is an error naming it.
  r = run_texbake("bake " + bunny + " --proxy-file " + q(d / "view_02.json") + " --texture " +
                  q(kData + "/earth.jpg") + " -o " + q(d / "wrong.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("earth.jpg"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "wrong.ply"));
}

}  // namespace
}  // namespace texbake
