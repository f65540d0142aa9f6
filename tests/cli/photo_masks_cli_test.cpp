// Photo masks through the executable (SPEC section 9 "Masks"): a COLMAP
// workspace rendered by `render --unlit --colmap` (its photos' alpha is the
// bunny's coverage), masks written in COLMAP's convention
// (MASKS/<image name>.png, 0 = masked out; a grey 128 keeps as 255 does):
// bake --masks gives the bytes the same masks give put into the photos'
// alpha, vertex and atlas; a photo without a mask file is used whole with a
// warning; bad mask folders and files are errors (exit 1) with no output;
// `cameras check --masks` counts only vertices on unmasked pixels, checked
// against the cameras' own projection of the mesh; an output that is a mask
// file is refused (exit 2).
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "mesh_io/colmap_model.h"
#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "tests/cli/run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::run_texbake;
using testing_cli::slurp;

std::string q(const fs::path& p) {
  return testing_cli::shell_quote(p.string());
}

const std::string kData = TEXBAKE_DATA_DIR;
constexpr int kViews = 4, kW = 320, kH = 240;

std::string view(int k) {
  return "view_0" + std::to_string(k) + ".png";
}

class PhotoMasksCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("texbake_photo_masks_cli_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const testing_cli::RunResult r = testing_cli::render_bunny_workspace(*dir_, kViews, "320x240");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path* dir_;
};
fs::path* PhotoMasksCli::dir_ = nullptr;

// Writes MASKS/<view k>.png for every view: grey value value(k, i, j) at
// pixel column i, row j (0..255).
void write_masks(const fs::path& masks, const std::function<int(int k, int i, int j)>& value) {
  fs::create_directories(masks);
  for (int k = 0; k < kViews; ++k) {
    Image m;
    m.width = kW, m.height = kH;
    m.pixels.assign(std::size_t{kW} * kH * 4, 1.f);
    for (int j = 0; j < kH; ++j) {
      for (int i = 0; i < kW; ++i) {
        float* px = &m.pixels[(static_cast<std::size_t>(j) * kW + i) * 4];
        px[0] = px[1] = px[2] = static_cast<float>(value(k, i, j)) / 255;
      }
    }
    ASSERT_TRUE(write_image(masks / (view(k) + ".png"), m.view()));
  }
}

// A different masked region per view: a band of columns, and in view 2 a
// block; kept pixels are 255 or (odd columns) 128.
int mask_value(int k, int i, int j) {
  const bool out = (i >= 40 * k && i < 40 * k + 120) || (k == 2 && j < 60 && i > 250);
  return out ? 0 : (i % 2 ? 128 : 255);
}

TEST_F(PhotoMasksCli, MasksFolderGivesTheBytesOfTheSameMasksInTheAlpha) {
  const fs::path& d = *dir_;
  const fs::path t = testing_cli::fresh_test_dir("masks_equal");
  const std::string bunny = q(kData + "/bunny00.off");
  write_masks(t / "masks", mask_value);
  // The photos with alpha = their alpha (coverage) times the binary mask.
  fs::create_directories(t / "images");
  for (int k = 0; k < kViews; ++k) {
    Expected<Image> photo = read_image(d / "ws/images" / view(k));
    ASSERT_TRUE(photo) << photo.error().message;
    ASSERT_EQ(photo->width, kW);
    for (int j = 0; j < kH; ++j) {
      for (int i = 0; i < kW; ++i) {
        if (mask_value(k, i, j) == 0)
          photo->pixels[(static_cast<std::size_t>(j) * kW + i) * 4 + 3] = 0;
      }
    }
    ASSERT_TRUE(write_image(t / "images" / view(k), photo->view()));
  }
  const std::string model = " --cameras " + q(d / "ws/sparse/0");
  for (const std::string out : {"v.ply", "a.obj"}) {
    const std::string atlas = out == "a.obj" ? " --size 256" : "";
    testing_cli::RunResult r =
        run_texbake("bake " + bunny + model + " --masks " + q(t / "masks") + atlas +
                    " -q --report " + q(t / ("m_" + out + ".json")) + " -o " + q(t / ("m_" + out)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    r = run_texbake("bake " + bunny + model + " --images " + q(t / "images") + atlas + " -q -o " +
                    q(t / ("a_" + out)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_texbake("bake " + bunny + model + atlas + " -q -o " + q(t / ("plain_" + out)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string file = out == "a.obj" ? "_a.png" : "_v.ply";
    const std::string masked = slurp(t / ("m" + file)), alpha = slurp(t / ("a" + file));
    ASSERT_FALSE(masked.empty());
    EXPECT_TRUE(masked == alpha) << out;
    EXPECT_FALSE(masked == slurp(t / ("plain" + file))) << out << ": the masks changed nothing";
    // The report: per camera the share of its photo masked out (its
    // background, alpha 0, included), more than the band's 120 / 320.
    const nlohmann::json report = nlohmann::json::parse(slurp(t / ("m_" + out + ".json")));
    ASSERT_EQ(report["cameras"].size(), std::size_t{kViews});
    for (const auto& c : report["cameras"]) EXPECT_GT(c["masked"].get<double>(), 120.0 / 320);
  }
  // A photo without a mask file is used whole, with a warning.
  fs::remove(t / "masks" / (view(3) + ".png"));
  const testing_cli::RunResult r =
      run_texbake("bake " + bunny + model + " --masks " + q(t / "masks") + " -o " + q(t / "w.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("texbake: warning: --masks " + (t / "masks").string() +
                       ": no mask for 1 of 4 photos (the first: view_03.png, looked for " +
                       (t / "masks" / "view_03.png.png").string() + "): used whole"),
            std::string::npos)
      << r.err;
  fs::remove_all(t);
}

TEST_F(PhotoMasksCli, BadMasksAreErrorsWithNoOutput) {
  const fs::path& d = *dir_;
  const fs::path t = testing_cli::fresh_test_dir("masks_bad");
  const std::string bunny = q(kData + "/bunny00.off");
  const std::string model = " --cameras " + q(d / "ws/sparse/0");
  const fs::path out = t / "out.ply";
  // No such folder.
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + model + " --masks " + q(t / "none") + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "texbake: error: --masks " + (t / "none").string() + ": no such folder\n");
  EXPECT_FALSE(fs::exists(out));
  // A folder with no mask for any photo (masks named without the image's extension
  // would be found: COLMAP 3.10's second name; these are .jpg names).
  fs::create_directories(t / "empty");
  std::ofstream(t / "empty" / "view_00.jpg.png") << "x";
  r = run_texbake("bake " + bunny + model + " --masks " + q(t / "empty") + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("texbake: error: --masks " + (t / "empty").string() +
                       ": no mask for any of the 4 photos (COLMAP's convention: a mask per "
                       "photo named after its image name, e.g. " +
                       (t / "empty" / "view_00.png.png").string() + ")"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
  // A mask of another size than its photo (view 1: 160 x 120), vertex and atlas.
  write_masks(t / "masks", [](int, int, int) { return 255; });
  Image small;
  small.width = 160, small.height = 120;
  small.pixels.assign(std::size_t{160} * 120 * 4, 1.f);
  ASSERT_TRUE(write_image(t / "masks" / (view(1) + ".png"), small.view()));
  for (const fs::path& o : {out, t / "out.obj"}) {
    r = run_texbake("bake " + bunny + model + " --masks " + q(t / "masks") + " -o " + q(o));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("texbake: error: the mask of camera view_01.png: " +
                         (t / "masks" / "view_01.png.png").string() + " is 160 x 120, its photo " +
                         (d / "ws/images/view_01.png").string() +
                         " 320 x 240 (a mask must have its photo's size)"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(o));
  }
  // A mask file that is no image.
  std::ofstream(t / "masks" / (view(1) + ".png"), std::ios::trunc) << "not a png";
  r = run_texbake("bake " + bunny + model + " --masks " + q(t / "masks") + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("texbake: error: the mask of camera view_01.png: "), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
  // --masks without --cameras (exit 2).
  r = run_texbake("bake " + bunny + " --texture " + q(kData + "/earth.jpg") +
                  " --proxy sphere --masks " + q(t / "masks") + " -o " + q(out));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--masks applies to --cameras only"), std::string::npos) << r.err;
  fs::remove_all(t);
}

TEST_F(PhotoMasksCli, CamerasCheckCountsOnlyUnmaskedPixels) {
  const fs::path& d = *dir_;
  const fs::path t = testing_cli::fresh_test_dir("masks_check");
  const std::string bunny = q(kData + "/bunny00.off");
  const std::string check = "cameras check " + bunny + " --cameras " + q(d / "ws/sparse/0");
  // The left half of every photo masked out.
  write_masks(t / "half", [](int, int i, int) { return i < kW / 2 ? 0 : 255; });
  write_masks(t / "all", [](int, int, int) { return 0; });
  const testing_cli::RunResult plain = run_texbake(check + " --json");
  const testing_cli::RunResult half = run_texbake(check + " --masks " + q(t / "half") + " --json");
  const testing_cli::RunResult all = run_texbake(check + " --masks " + q(t / "all") + " --json");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(half.exit_code, 0) << half.err;
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const nlohmann::json p = nlohmann::json::parse(plain.out), h = nlohmann::json::parse(half.out),
                       a = nlohmann::json::parse(all.out);
  // The expectation from the cameras themselves: the vertices (all are
  // referenced by triangles) whose pixel x is left of the mask's edge. The
  // bilinear mask at continuous position x - 0.5 is 0 for x < 159.5.
  Expected<LoadedMesh> mesh = read_mesh(kData + "/bunny00.off");
  ASSERT_TRUE(mesh);
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(model);
  ASSERT_EQ(model->size(), std::size_t{kViews});
  const double n = static_cast<double>(mesh->mesh.positions.size());
  for (int k = 0; k < kViews; ++k) {
    std::size_t inside = 0, left = 0, near_edge = 0;
    for (const Float3& v : mesh->mesh.positions) {
      const CameraProjection proj = (*model)[k].camera.project({v.x, v.y, v.z});
      if (!proj.inside) continue;
      ++inside;
      left += proj.pixel.x < 159.4;
      near_edge += proj.pixel.x >= 159.4 && proj.pixel.x <= 159.6;
    }
    ASSERT_GT(left, inside / 10);
    const double in = p[k]["inside"], vis = p[k]["visible"];
    EXPECT_DOUBLE_EQ(h[k]["inside"].get<double>(), in);
    EXPECT_DOUBLE_EQ(h[k]["in_front"].get<double>(), p[k]["in_front"].get<double>());
    EXPECT_NEAR(in, inside / n, 1e-12);
    EXPECT_GE(h[k]["masked"].get<double>(), left / n - 1e-12);
    EXPECT_LE(h[k]["masked"].get<double>(), (left + near_edge) / n + 1e-12);
    // Visible now counts the unmasked vertices only: at most the inside
    // ones not masked, and at most the masked ones fewer than before.
    const double hv = h[k]["visible"];
    EXPECT_LE(hv, in - h[k]["masked"].get<double>() + 1e-12);
    EXPECT_GE(hv, vis - h[k]["masked"].get<double>() - 1e-12);
    EXPECT_LT(hv, vis);
    EXPECT_EQ(p[k]["masked"].get<double>(), 0.0);
    // Everything masked: nothing visible, everything inside masked.
    EXPECT_EQ(a[k]["visible"].get<double>(), 0.0);
    EXPECT_DOUBLE_EQ(a[k]["masked"].get<double>(), in);
  }
  // The table has a "masked" column with --masks.
  const testing_cli::RunResult table = run_texbake(check + " --masks " + q(t / "half"));
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("in front    inside    masked   visible"), std::string::npos)
      << table.out;
  // A mask of the wrong size: an error naming it.
  Image small;
  small.width = 100, small.height = 100;
  small.pixels.assign(std::size_t{100} * 100 * 4, 1.f);
  ASSERT_TRUE(write_image(t / "half" / (view(2) + ".png"), small.view()));
  const testing_cli::RunResult bad = run_texbake(check + " --masks " + q(t / "half"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("texbake: error: the mask of camera view_02.png: " +
                         (t / "half" / "view_02.png.png").string() +
                         " is 100 x 100, its camera 320 x 240 (neither that size nor that "
                         "aspect)"),
            std::string::npos)
      << bad.err;
  fs::remove_all(t);
}

TEST_F(PhotoMasksCli, AnOutputThatIsAMaskFileIsRefused) {
  const fs::path& d = *dir_;
  const fs::path t = testing_cli::fresh_test_dir("masks_distinct");
  const std::string bunny = q(kData + "/bunny00.off");
  const std::string model = " --cameras " + q(d / "ws/sparse/0");
  write_masks(t / "masks", [](int, int, int) { return 255; });
  const fs::path mask = t / "masks" / "view_00.png.png";
  const std::string before = slurp(mask);
  testing_cli::RunResult r = run_texbake("bake " + bunny + model + " --masks " + q(t / "masks") +
                                         " --report " + q(mask) + " -o " + q(t / "o.ply"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("texbake: error: --report " + mask.string() +
                       " and the mask of a photo of --cameras " + mask.string() +
                       " are the same file: texbake never overwrites an input"),
            std::string::npos)
      << r.err;
  // -o an atlas whose image is a mask (COLMAP 3.10's name without the
  // image's extension: MASKS/view_00.png for view_00.png).
  fs::create_directories(t / "m2");
  fs::copy_file(mask, t / "m2" / "view_00.png");
  r = run_texbake("bake " + bunny + model + " --masks " + q(t / "m2") + " -o " +
                  q(t / "m2" / "view_00.obj"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the atlas image of -o " + (t / "m2" / "view_00.png").string() +
                       " and the mask of a photo of --cameras"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(mask), before);
  EXPECT_EQ(slurp(t / "m2" / "view_00.png"), before);
  EXPECT_FALSE(fs::exists(t / "o.ply"));
  EXPECT_FALSE(fs::exists(t / "m2" / "view_00.obj"));
  fs::remove_all(t);
}

// Vertex colours of a PLY as 8-bit RGBA.
std::vector<std::array<int, 4>> colours(const fs::path& ply) {
  Expected<LoadedMesh> m = read_mesh(ply);
  EXPECT_TRUE(m) << m.error().message;
  std::vector<std::array<int, 4>> out;
  for (const auto& c : m->mesh.vertex_colors) {
    out.push_back({static_cast<int>(c[0] * 255 + 0.5f), static_cast<int>(c[1] * 255 + 0.5f),
                   static_cast<int>(c[2] * 255 + 0.5f), static_cast<int>(c[3] * 255 + 0.5f)});
  }
  return out;
}

// A "cameras" layer's "masks" (relative to the layers file) over base
// "none" is bake --cameras --masks where some photo sees the vertex, and
// sees fewer vertices than the layer without masks.
TEST_F(PhotoMasksCli, ACamerasLayerTakesMasks) {
  const fs::path& d = *dir_;
  const fs::path t = testing_cli::fresh_test_dir("masks_layer");
  const std::string bunny = q(kData + "/bunny00.off");
  write_masks(t / "masks", mask_value);
  const std::string model = (d / "ws/sparse/0").string();
  std::ofstream(t / "L.json") << R"({"layers":[{"cameras":")" << model << R"(","masks":"masks"}]})";
  std::ofstream(t / "N.json") << R"({"layers":[{"cameras":")" << model << R"("}]})";
  std::ofstream(t / "B.json") << R"({"layers":[{"cameras":")" << model
                              << R"(","masks":"nowhere"}]})";
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + " --layers " + q(t / "L.json") + " -q -o " + q(t / "l.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --layers " + q(t / "N.json") + " -q -o " + q(t / "n.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --cameras " + q(model) + " --masks " + q(t / "masks") +
                  " -q -o " + q(t / "p.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto layer = colours(t / "l.ply"), plain = colours(t / "n.ply"),
             photos = colours(t / "p.ply");
  ASSERT_EQ(layer.size(), photos.size());
  std::size_t seen = 0, seen_plain = 0;
  for (std::size_t v = 0; v < layer.size(); ++v) {
    seen_plain += plain[v][3] == 255;
    if (layer[v][3] == 0) continue;
    ASSERT_EQ(layer[v][3], 255) << v;
    ++seen;
    for (int c = 0; c < 3; ++c) ASSERT_EQ(layer[v][c], photos[v][c]) << "vertex " << v;
  }
  EXPECT_GT(seen, 1000u);
  EXPECT_LT(seen, seen_plain);
  r = run_texbake("bake " + bunny + " --layers " + q(t / "B.json") + " -o " + q(t / "b.ply"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("texbake: error: layers[0].masks " + (t / "nowhere").string() +
                       ": no such folder"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(t / "b.ply"));
  fs::remove_all(t);
}

}  // namespace
}  // namespace texbake
