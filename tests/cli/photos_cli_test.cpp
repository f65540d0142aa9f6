// bake --cameras and cameras check through the executable (SPEC section 9):
// a COLMAP workspace written by `render --unlit --colmap` from the bunny
// with the Earth map, baked back (vertex and atlas targets: the atlas
// against the direct atlas on the same generated UVs); the same model in
// binary gives the same bytes; a pose given camera-to-world is caught by `cameras check`; bad
// inputs are errors naming the file and line or photo, with no output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mesh_io/atomic_file.h"
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
    const testing_cli::RunResult r = testing_cli::render_bunny_workspace(*dir_, 6, "640x480");
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
  // One line per image: the POINTS2D lines (empty here) left out. The
  // first image is on line 5 (after the writer's four comment lines).
  std::string one_line = images;
  for (std::size_t at; (at = one_line.find("\n\n")) != std::string::npos;) one_line.erase(at, 1);
  ASSERT_EQ(one_line.find("\n1 "), one_line.find("# Number of images: 6\n") + 21);
  const std::vector<Case> cases = {
      {"1 FISHEYE 640 480 1 2 3\n", images, "cameras.txt line 1: unknown camera model FISHEYE", 1},
      {"1 PINHOLE 640 480 500 500 320\n", images,
       "cameras.txt line 1: PINHOLE takes 4 parameters, got 3", 1},
      {cams, unknown_id, "names camera id 7, which cameras.txt does not define", 1},
      // Bad intrinsics: the camera's line and id, not the first image using it.
      {"1 PINHOLE 640 480 0 500 320 240\n", images,
       "cameras.txt line 1: camera id 1: PINHOLE: the focal length must be positive (got 0)", 1},
      {"1 PINHOLE 640 480 500 500 320 -inf\n", images,
       "cameras.txt line 1: camera id 1: a camera parameter is not a finite number (-inf)", 1},
      {cams, one_line,
       "images.txt line 6: expected the 2D points of the image on line 5 (X Y POINT3D_ID "
       "triples, possibly none): COLMAP's images.txt has two lines per image",
       1},
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

// The workspace's model with image `name` renamed to `to` (a missing photo).
void model_renaming(const fs::path& d, const std::string& name, const std::string& to,
                    const fs::path& folder) {
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(model);
  for (ColmapImage& i : *model) {
    if (i.name == name) i.name = to;
  }
  ASSERT_TRUE(write_colmap_model(folder, *model, /*binary=*/false));
}

TEST_F(PhotosCli, AnUnreadablePhotoIsLeftOutWithAWarningAndReported) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  // view_03.png missing (the model names view_99.png), and view_01.png's
  // file not an image, in a copy of the photos.
  fs::create_directories(d / "gaps/images");
  for (int k = 0; k < 6; ++k) {
    const std::string name = "view_0" + std::to_string(k) + ".png";
    if (k == 1) {
      std::ofstream(d / "gaps/images" / name) << "not a PNG";
    } else {
      fs::copy_file(d / "ws/images" / name, d / "gaps/images" / name,
                    fs::copy_options::overwrite_existing);
    }
  }
  model_renaming(d, "view_03.png", "view_99.png", d / "gaps/sparse/0");
  // The expected result: the model without those two images.
  {
    Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
    ASSERT_TRUE(model);
    std::erase_if(*model, [](const ColmapImage& i) {
      return i.name == "view_01.png" || i.name == "view_03.png";
    });
    ASSERT_TRUE(write_colmap_model(d / "four/sparse/0", *model, /*binary=*/false));
  }
  const std::string images = " --images " + q(d / "gaps/images");
  for (const std::string target : {"vertex", "atlas"}) {
    const std::string ext = target == "vertex" ? ".ply" : ".glb";
    const std::string atlas = target == "atlas" ? " --size 256" : "";
    testing_cli::RunResult r = run_texbake(
        "bake " + bunny + " --cameras " + q(d / "gaps/sparse/0") + images + atlas + " --report " +
        q(d / ("gaps_" + target + ".json")) + " -o " + q(d / ("gaps" + ext)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string path99 = (d / "gaps/images/view_99.png").string();
    EXPECT_NE(r.err.find("texbake: warning: the photo of camera view_99.png is left out: " +
                         path99 + ": no such file\n"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("texbake: warning: the photo of camera view_01.png is left out: " +
                         (d / "gaps/images/view_01.png").string()),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.out.find("from 4 photos"), std::string::npos) << r.out;
    const nlohmann::json report =
        nlohmann::json::parse(testing_cli::slurp(d / ("gaps_" + target + ".json")));
    ASSERT_EQ(report["photos_skipped"].size(), 2u) << report.dump(1);
    EXPECT_EQ(report["photos_skipped"][0]["image"], "view_01.png");
    EXPECT_EQ(report["photos_skipped"][1]["image"], "view_99.png");
    EXPECT_EQ(report["photos_skipped"][1]["path"], path99);
    EXPECT_EQ(report["photos_skipped"][1]["reason"], path99 + ": no such file");
    EXPECT_EQ(report["cameras"].size(), 4u);
    // The same bytes as the model without those photos.
    r = run_texbake("bake " + bunny + " --cameras " + q(d / "four/sparse/0") + " --images " +
                    q(d / "ws/images") + atlas + " -q -o " + q(d / ("four" + ext)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(testing_cli::slurp(d / ("gaps" + ext)), testing_cli::slurp(d / ("four" + ext)))
        << target;
    // --strict-photos: the first unreadable photo is an error, no output.
    r = run_texbake("bake " + bunny + " --cameras " + q(d / "gaps/sparse/0") + images + atlas +
                    " --strict-photos -o " + q(d / ("strict" + ext)));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("texbake: error: the photo of camera view_01.png: " +
                         (d / "gaps/images/view_01.png").string()),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(d / ("strict" + ext)));
  }
  // No usable photo left: an error naming the count and the first reason.
  fs::create_directories(d / "no_photos");
  const testing_cli::RunResult none =
      run_texbake("bake " + bunny + " --cameras " + q(d / "ws/sparse/0") + " --images " +
                  q(d / "no_photos") + " -o " + q(d / "none.ply"));
  EXPECT_EQ(none.exit_code, 1) << none.err;
  EXPECT_NE(none.err.find("texbake: error: no usable photo: all 6 photos cannot be read (the "
                          "first: " +
                          (d / "no_photos/view_00.png").string() + ": no such file)"),
            std::string::npos)
      << none.err;
  EXPECT_FALSE(fs::exists(d / "none.ply"));
  // --strict-photos without photos to bake is a usage error.
  const testing_cli::RunResult usage =
      run_texbake("bake " + bunny + " --texture " + q(kData + "/earth.jpg") + " --proxy-file " +
                  q(d / "s.json") + " --strict-photos -o " + q(d / "usage.ply"));
  EXPECT_EQ(usage.exit_code, 2) << usage.err;
  EXPECT_NE(usage.err.find("--strict-photos applies to --cameras and --layers only"),
            std::string::npos)
      << usage.err;
}

TEST_F(PhotosCli, ACamerasLayerLeavesOutAnUnreadablePhoto) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  model_renaming(d, "view_02.png", "view_42.png", d / "layer/sparse/0");
  nlohmann::json layers = {
      {"base", "none"},
      {"layers",
       {{{"cameras", (d / "layer/sparse/0").string()}, {"images", (d / "ws/images").string()}}}}};
  std::ofstream(d / "layers.json") << layers.dump();
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + " --layers " + q(d / "layers.json") + " --report " +
                  q(d / "layers_r.json") + " -o " + q(d / "layers.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("texbake: warning: layers[0]: the photo of camera view_42.png is left "
                       "out: " +
                       (d / "ws/images/view_42.png").string() + ": no such file"),
            std::string::npos)
      << r.err;
  const nlohmann::json report = nlohmann::json::parse(testing_cli::slurp(d / "layers_r.json"));
  ASSERT_EQ(report["layers"][0]["photos_skipped"].size(), 1u) << report.dump(1);
  EXPECT_EQ(report["layers"][0]["photos_skipped"][0]["image"], "view_42.png");
  r = run_texbake("bake " + bunny + " --layers " + q(d / "layers.json") + " --strict-photos -o " +
                  q(d / "layers_strict.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  // (A layers bake's input errors are prefixed by the mesh's name.)
  EXPECT_NE(r.err.find("texbake: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(": layers[0]: the photo of camera view_42.png: " +
                       (d / "ws/images/view_42.png").string() + ": no such file\n"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "layers_strict.ply"));
}

TEST_F(PhotosCli, CamerasCheckNeedsNoPhotos) {
  // A model outside any workspace, no --images: the check needs only the
  // poses and sizes (it demanded --images before).
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  fs::create_directories(d / "loose");
  for (const char* f : {"cameras.txt", "images.txt"}) {
    fs::copy_file(d / "ws/sparse/0" / f, d / "loose" / f, fs::copy_options::overwrite_existing);
  }
  const testing_cli::RunResult loose =
      run_texbake("cameras check " + bunny + " --cameras " + q(d / "loose") + " --json");
  ASSERT_EQ(loose.exit_code, 0) << loose.err;
  // Without its photos only the photo-consistency figures are missing, with a note.
  EXPECT_NE(loose.err.find("texbake: note: photo agreement not measured: no usable photo"),
            std::string::npos)
      << loose.err;
  const testing_cli::RunResult ws = run_texbake("cameras check " + bunny + " --cameras " +
                                                q(d / "ws/sparse/0") + " --json --no-photos");
  ASSERT_EQ(ws.exit_code, 0) << ws.err;
  EXPECT_EQ(loose.out, ws.out);
  EXPECT_EQ(nlohmann::json::parse(loose.out).size(), 6u);
  // A bake from the same folder still needs the photos' folder (exit 2).
  const testing_cli::RunResult bake =
      run_texbake("bake " + bunny + " --cameras " + q(d / "loose") + " -o " + q(d / "l.ply"));
  EXPECT_EQ(bake.exit_code, 2) << bake.err;
  EXPECT_NE(bake.err.find("give the photos' folder with --images"), std::string::npos) << bake.err;
}

// Photo-consistency in cameras check: the true poses' photos agree (an
// unlit render: the same colour from every view, gains 1); the same model
// with each camera given the next camera's photo disagrees, with a warning.
TEST_F(PhotosCli, CamerasCheckMeasuresHowWellThePhotosAgree) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  testing_cli::RunResult r =
      run_texbake("cameras check " + bunny + " --cameras " + q(d / "ws/sparse/0") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const nlohmann::json checks = nlohmann::json::parse(r.out);
  ASSERT_EQ(checks.size(), 6u);
  for (const nlohmann::json& c : checks) {
    EXPECT_GT(c["shared"].get<std::size_t>(), 1000u) << c.dump();
    EXPECT_LT(c["deviation"].get<double>(), 0.05) << c.dump();
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(c["gain"][ch].get<double>(), 1.0, 0.05) << c.dump();
  }
  // The text table: its columns and the model's line.
  r = run_texbake("cameras check " + bunny + " --cameras " + q(d / "ws/sparse/0"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("visible    shared deviation   gain"), std::string::npos) << r.out;
  const std::size_t line = r.out.find("photo agreement: ");
  ASSERT_NE(line, std::string::npos) << r.out;
  EXPECT_GE(std::stoi(r.out.substr(line + 17)), 90) << r.out;  // percent agreeing
  r = run_texbake("cameras check " + bunny + " --cameras " + q(d / "ws/sparse/0") + " --no-photos");
  EXPECT_EQ(r.out.find("photo agreement"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("shared"), std::string::npos) << r.out;

  // Camera k with photo k + 1: the geometry is the same, the photos are not.
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(model);
  std::vector<ColmapImage> swapped = *model;
  for (std::size_t k = 0; k < swapped.size(); ++k) {
    swapped[k].name = (*model)[(k + 1) % swapped.size()].name;
  }
  ASSERT_TRUE(write_colmap_model(d / "swapped/sparse/0", swapped, false));
  r = run_texbake("cameras check " + bunny + " --cameras " + q(d / "swapped/sparse/0") +
                  " --images " + q(d / "ws/images"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t bad = r.out.find("photo agreement: ");
  ASSERT_NE(bad, std::string::npos) << r.out;
  EXPECT_LT(std::stoi(r.out.substr(bad + 17)), 50) << r.out;
  EXPECT_NE(r.err.find("the photos disagree on the mesh"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("texbake cameras refine"), std::string::npos) << r.err;
}

TEST_F(PhotosCli, RenderColmapReplacesABinaryModelAndWritesAllOrNothing) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  // A workspace holding a stale binary model of 6 views: rendering 2 views
  // over it replaces it (before: text files beside it, the binary model read).
  const fs::path bin = binary_model(d);
  fs::create_directories(d / "ws2/sparse/0");
  for (const char* f : {"cameras.bin", "images.bin"}) {
    fs::copy_file(bin / f, d / "ws2/sparse/0" / f, fs::copy_options::overwrite_existing);
  }
  std::ofstream(d / "ws2/sparse/0/points3D.bin", std::ios::binary) << std::string(8, '\0');
  const std::string render = "render " + bunny + " --views 2 --size 64x48 --colmap ";
  testing_cli::RunResult r = run_texbake(render + q(d / "ws2"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* gone : {"cameras.bin", "images.bin", "points3D.bin"}) {
    EXPECT_FALSE(fs::exists(d / "ws2/sparse/0" / gone)) << gone;
  }
  for (const char* made : {"cameras.txt", "images.txt", "points3D.txt"}) {
    EXPECT_TRUE(fs::exists(d / "ws2/sparse/0" / made)) << made;
  }
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws2/sparse/0");
  ASSERT_TRUE(model) << model.error().message;
  EXPECT_EQ(model->size(), 2u);
  EXPECT_EQ((*model)[0].camera.spec().width, 64);
  // The model cannot be written (images.txt is a folder): nothing is, no
  // view, no cameras.txt, no temporary; exit 1 naming the file.
  fs::create_directories(d / "ws3/sparse/0/images.txt");
  r = run_texbake(render + q(d / "ws3"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("texbake: error: cannot write " + (d / "ws3/sparse/0/images.txt").string() +
                       ": it is a folder"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "ws3/images/view_00.png"));
  EXPECT_FALSE(fs::exists(d / "ws3/sparse/0/cameras.txt"));
  EXPECT_TRUE(list_texbake_temporaries(d / "ws3/images").empty());
  EXPECT_TRUE(list_texbake_temporaries(d / "ws3/sparse/0").empty());
}

}  // namespace
}  // namespace texbake
