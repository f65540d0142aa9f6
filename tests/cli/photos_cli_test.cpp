// bake --cameras and cameras check through the executable (SPEC section 9):
// a COLMAP workspace written by `render --unlit --colmap` from the bunny
// with the Earth map, baked back (vertex and atlas targets: the atlas
// against the direct atlas on the same generated UVs); the same model in
// binary gives the same bytes; a pose given camera-to-world is caught by `cameras check`; bad
// inputs are errors naming the file and line or photo, with no output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "mesh_io/colmap_model.h"
#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "tests/cli/run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::run_texbake;

std::string q(const fs::path& p) {
  return testing_cli::shell_quote(p.string());
}

const std::string kData = TEXBAKE_DATA_DIR;

class PhotosCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // (Not fresh_test_dir: no test is running yet to name the folder after.)
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("texbake_photos_cli_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const std::string bunny = q(kData + "/bunny00.off");
    ASSERT_EQ(
        run_texbake("fit " + bunny + " --proxy sphere --up y -o " + q(*dir_ / "s.json")).exit_code,
        0);
    const testing_cli::RunResult r =
        run_texbake("render " + bunny + " --texture " + q(kData + "/earth.jpg") + " --proxy-file " +
                    q(*dir_ / "s.json") + " --up y --unlit --views 6 --size 640x480 --colmap " +
                    q(*dir_ / "ws"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path* dir_;
};
fs::path* PhotosCli::dir_ = nullptr;

std::vector<std::array<int, 3>> ply_ascii_colors(const fs::path& path) {
  Expected<LoadedMesh> m = read_mesh(path);
  EXPECT_TRUE(m) << m.error().message;
  std::vector<std::array<int, 3>> out;
  for (const auto& c : m->mesh.vertex_colors) {
    out.push_back({static_cast<int>(c[0] * 255 + 0.5f), static_cast<int>(c[1] * 255 + 0.5f),
                   static_cast<int>(c[2] * 255 + 0.5f)});
  }
  return out;
}

TEST_F(PhotosCli, RendersBakedBackAgreeWithTheDirectBakeAndBinaryEqualsText) {
  const std::string bunny = q(kData + "/bunny00.off");
  const fs::path& d = *dir_;
  ASSERT_TRUE(fs::exists(d / "ws/images/view_05.png"));
  ASSERT_TRUE(fs::exists(d / "ws/sparse/0/cameras.txt"));
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + " --cameras " + q(d / "ws/sparse/0") +
                  " -q --occluded 1,0,1 --report " + q(d / "r.json") + " -o " + q(d / "photo.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --texture " + q(kData + "/earth.jpg") + " --proxy-file " +
                  q(d / "s.json") + " --filter bilinear --occluded 1,0,1 -q -o " +
                  q(d / "direct.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto photo = ply_ascii_colors(d / "photo.ply"), direct = ply_ascii_colors(d / "direct.ply");
  ASSERT_EQ(photo.size(), direct.size());
  std::vector<int> errors;
  for (std::size_t v = 0; v < photo.size(); ++v) {
    const std::array<int, 3> magenta{255, 0, 255};
    if (photo[v] == magenta || direct[v] == magenta) continue;  // unseen by either
    int worst = 0;
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(photo[v][c] - direct[v][c]));
    errors.push_back(worst);
  }
  ASSERT_GT(errors.size(), photo.size() / 2);
  std::sort(errors.begin(), errors.end());
  // 8-bit photos of 640x480, coarser than the API test's float renders of
  // 960x720 (tests/bake/photo/photo_roundtrip_test.cpp). Measured: median
  // 1, 95th percentile 17 levels.
  EXPECT_LE(errors[errors.size() / 2], 2);
  EXPECT_LE(errors[errors.size() * 95 / 100], 24);
  // The report has one entry per photo.
  const std::string report = testing_cli::slurp(d / "r.json");
  EXPECT_NE(report.find("\"view_05.png\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"gain\""), std::string::npos);

  // The same model in COLMAP's binary form: the same bytes.
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(model);
  fs::create_directories(d / "wsb/sparse/0");
  ASSERT_TRUE(write_colmap_model(d / "wsb/sparse/0", *model, /*binary=*/true));
  r = run_texbake("bake " + bunny + " --cameras " + q(d / "wsb/sparse/0") + " --images " +
                  q(d / "ws/images") + " -q --occluded 1,0,1 -o " + q(d / "photo_bin.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(testing_cli::slurp(d / "photo_bin.ply"), testing_cli::slurp(d / "photo.ply"));
}

// The workspace's model in COLMAP's binary form (wsb/sparse/0), once.
fs::path binary_model(const fs::path& d) {
  const fs::path model = d / "wsb/sparse/0";
  if (!fs::exists(model / "images.bin")) {
    Expected<std::vector<ColmapImage>> text = read_colmap_model(d / "ws/sparse/0");
    EXPECT_TRUE(text);
    fs::create_directories(model);
    EXPECT_TRUE(write_colmap_model(model, *text, /*binary=*/true));
  }
  return model;
}

Image read_png(const fs::path& path) {
  Expected<Image> image = read_image(path);
  EXPECT_TRUE(image) << image.error().message;
  return image ? std::move(*image) : Image{};
}

int level(float v) {
  return static_cast<int>(v * 255 + 0.5f);
}

TEST_F(PhotosCli, AtlasRoundTripAgreesWithTheDirectAtlasAndBinaryEqualsText) {
  const std::string bunny = q(kData + "/bunny00.off");
  const fs::path& d = *dir_;
  const std::string atlas = " --uv generate --size 512 -q ";
  // --uv generate is deterministic: both bakes lay the same charts out.
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + " --cameras " + q(d / "ws/sparse/0") + atlas + "-o " +
                  q(d / "pa.obj") + " --report " + q(d / "pa.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --cameras " + q(d / "ws/sparse/0") + atlas +
                  "--occluded 1,0,1 -o " + q(d / "pa_m.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string direct = "bake " + bunny + " --texture " + q(kData + "/earth.jpg") +
                             " --proxy-file " + q(d / "s.json") + atlas;
  r = run_texbake(direct + "-o " + q(d / "da.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake(direct + "--occluded 1,0,1 -o " + q(d / "da_m.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image pa = read_png(d / "pa.png"), pa_m = read_png(d / "pa_m.png"),
              da = read_png(d / "da.png"), da_m = read_png(d / "da_m.png");
  ASSERT_EQ(pa.width, 512);
  ASSERT_EQ(da.width, 512);
  // Covered texels (alpha 255) are the same in both: the same layout.
  std::size_t covered = 0, mismatched = 0;
  std::vector<int> errors;
  for (std::size_t t = 0; t < std::size_t{512} * 512; ++t) {
    const bool pc = level(pa.pixels[4 * t + 3]) == 255, dc = level(da.pixels[4 * t + 3]) == 255;
    mismatched += pc != dc;
    if (!pc) continue;
    ++covered;
    // Wholly seen by the photos and by the proxy: the fill and the magenta
    // bakes agree (no sample took either).
    bool seen = true;
    for (int c = 0; c < 3; ++c) {
      seen = seen && level(pa.pixels[4 * t + c]) == level(pa_m.pixels[4 * t + c]) &&
             level(da.pixels[4 * t + c]) == level(da_m.pixels[4 * t + c]);
    }
    if (!seen) continue;
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      worst = std::max(worst, std::abs(level(pa.pixels[4 * t + c]) - level(da.pixels[4 * t + c])));
    }
    errors.push_back(worst);
  }
  EXPECT_EQ(mismatched, 0u);
  ASSERT_GT(errors.size(), covered / 2);
  std::sort(errors.begin(), errors.end());
  std::printf("atlas round trip over %zu of %zu texels: median %d, 95th percentile %d levels\n",
              errors.size(), covered, errors[errors.size() / 2], errors[errors.size() * 95 / 100]);
  // 8-bit photos of 640 x 480 (the vertex test's; coarser than the atlas's
  // 512 texels on the bunny). Measured: median 1, 95th percentile 13
  // levels over 138,372 of 205,328 covered texels.
  EXPECT_LE(errors[errors.size() / 2], 2);
  EXPECT_LE(errors[errors.size() * 95 / 100], 18);
  const std::string report = testing_cli::slurp(d / "pa.json");
  EXPECT_NE(report.find("\"target\": \"atlas\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"view_05.png\""), std::string::npos);
  EXPECT_NE(report.find("\"gain\""), std::string::npos);

  // The binary model: the same atlas, byte for byte.
  r = run_texbake("bake " + bunny + " --cameras " + q(binary_model(d)) + " --images " +
                  q(d / "ws/images") + atlas + "-o " + q(d / "pa_bin.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(testing_cli::slurp(d / "pa_bin.png"), testing_cli::slurp(d / "pa.png"));

  // A .glb embeds the atlas.
  r = run_texbake("bake " + bunny + " --cameras " + q(d / "ws/sparse/0") + " --size 128 -q -o " +
                  q(d / "pa.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(fs::file_size(d / "pa.glb"), 1000u);
}

TEST_F(PhotosCli, AtlasFlagsWithCamerasAreChecked) {
  const std::string bunny = q(kData + "/bunny00.off");
  const fs::path& d = *dir_;
  const std::string cams = " --cameras " + q(d / "ws/sparse/0");
  struct Case {
    std::string flags, want;
  };
  const std::vector<Case> cases = {
      {" --uv proxy -o " + q(d / "x.obj"), "--uv proxy needs a proxy, and --cameras has none"},
      {" --size 64 -o " + q(d / "x.ply"), "--size applies to --target atlas only"},
      {" --samples 4 -o " + q(d / "x.ply"), "--samples applies to --target atlas only"},
      {" --ascii -o " + q(d / "x.obj"), "--ascii applies to --target vertex only"},
      {" --size 0 -o " + q(d / "x.obj"), "--size 0 is out of range"},
      {" --format exr -o " + q(d / "x.glb"), "--format exr"},
      {" --uv mesh -o " + q(d / "x.obj"), "has no UV coordinates"},
  };
  for (const Case& c : cases) {
    const testing_cli::RunResult r = run_texbake("bake " + bunny + cams + c.flags);
    EXPECT_EQ(r.exit_code, 2) << c.flags << ": " << r.err;
    EXPECT_NE(r.err.find(c.want), std::string::npos) << c.flags << ": " << r.err;
  }
  for (const char* f : {"x.obj", "x.mtl", "x.png", "x.ply", "x.glb"}) {
    EXPECT_FALSE(fs::exists(d / f)) << f;
  }
}

TEST_F(PhotosCli, CamerasCheckCatchesACameraToWorldPose) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  testing_cli::RunResult r =
      run_texbake("cameras check " + bunny + " --cameras " + q(d / "ws/sparse/0") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // every view sees the whole bunny in front of it
  EXPECT_NE(r.out.find("\"inside\": 1.0"), std::string::npos) << r.out;
  // The poses inverted (as if camera-to-world had been written where
  // world-to-camera belongs): QW QX QY QZ -> conjugate, T -> the centre.
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(model);
  std::vector<ColmapImage> inverted;
  for (const ColmapImage& img : *model) {
    CameraSpec spec = img.camera.spec();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) spec.pose.r[3 * i + j] = img.camera.spec().pose.r[3 * j + i];
    }
    spec.pose.t = img.camera.centre();
    Expected<CameraProjector> c = CameraProjector::make(spec);
    ASSERT_TRUE(c);
    inverted.push_back({img.image_id, img.camera_id, img.name, *c});
  }
  ASSERT_TRUE(write_colmap_model(d / "inv/sparse/0", inverted, false));
  r = run_texbake("cameras check " + bunny + " --cameras " + q(d / "inv/sparse/0") + " --images " +
                  q(d / "ws/images"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (int k = 0; k < 6; ++k) {
    EXPECT_NE(r.err.find("texbake: warning: view_0" + std::to_string(k) +
                         ".png: camera-to-world given as world-to-camera?"),
              std::string::npos)
        << r.err;
  }
}

TEST_F(PhotosCli, BadInputsAreErrorsWithNoOutput) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  const std::string images = testing_cli::slurp(d / "ws/sparse/0/images.txt");
  struct Case {
    std::string cameras_txt, images_txt, want;
    int exit_code;
  };
  const std::string cams = testing_cli::slurp(d / "ws/sparse/0/cameras.txt");
  std::string unknown_id = images;
  unknown_id.replace(unknown_id.find(" 1 view_00.png"), 14, " 7 view_00.png");
  std::string missing_photo = images;
  missing_photo.replace(missing_photo.find("view_03.png"), 11, "view_99.png");
  const std::vector<Case> cases = {
      {"1 FISHEYE 640 480 1 2 3\n", images, "cameras.txt line 1: unknown camera model FISHEYE", 1},
      {"1 PINHOLE 640 480 500 500 320\n", images,
       "cameras.txt line 1: PINHOLE takes 4 parameters, got 3", 1},
      {cams, unknown_id, "names camera id 7, which cameras.txt does not define", 1},
      {cams, missing_photo, "the photo of camera view_99.png:", 1},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path model = d / ("bad" + std::to_string(i)) / "sparse" / "0";
    fs::create_directories(model);
    std::ofstream(model / "cameras.txt") << cases[i].cameras_txt;
    std::ofstream(model / "images.txt") << cases[i].images_txt;
    const fs::path out = d / ("bad" + std::to_string(i) + ".ply");
    const testing_cli::RunResult r =
        run_texbake("bake " + bunny + " --cameras " + q(model) + " --images " + q(d / "ws/images") +
                    " -o " + q(out));
    EXPECT_EQ(r.exit_code, cases[i].exit_code) << r.err;
    EXPECT_NE(r.err.find("texbake: error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(cases[i].want), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  // A photo of the wrong size and aspect.
  const fs::path model = d / "badsize" / "sparse" / "0";
  fs::create_directories(model);
  std::ofstream(model / "cameras.txt") << "1 PINHOLE 640 640 500 500 320 320\n";
  std::ofstream(model / "images.txt") << images;
  const testing_cli::RunResult r =
      run_texbake("bake " + bunny + " --cameras " + q(model) + " --images " + q(d / "ws/images") +
                  " -o " + q(d / "badsize.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("is 640 x 480, its camera 640 x 640"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "badsize.ply"));
  // Flags of the single projection do not mix with --cameras (exit 2).
  const testing_cli::RunResult mix =
      run_texbake("bake " + bunny + " --cameras " + q(d / "ws/sparse/0") + " --texture " +
                  q(kData + "/earth.jpg") + " -o " + q(d / "mix.ply"));
  EXPECT_EQ(mix.exit_code, 2);
  EXPECT_NE(mix.err.find("--texture does not apply to --cameras"), std::string::npos) << mix.err;
}

}  // namespace
}  // namespace texbake
