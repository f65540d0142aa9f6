// texbake cameras refine (SPEC section 9, issue 30 item 3) through the
// executable. The scene: the bunny with the Earth map rendered by texbake
// itself (render --unlit --colmap, 6 views of 320 x 240, 64 samples per
// pixel) from known cameras. Each photo's pose is then moved by hand (a
// rotation of 0.5-1 degree about a fixed axis and its centre by 1 % of its
// distance to the origin, which is inside the bunny) and refined; the
// recovery test uses half that (see there).
//
// How close a pose is to the truth is measured by what the bake sees: the
// mean displacement, in pixels, of the bunny's vertices projected by the
// refined camera and by the true one (mapping/camera.h's projection, not
// the refinement's code). A photometric refinement is blind to what does
// not move the image (a rotation about the object's centre traded against
// a translation: the orbit of a narrow view), so that is the figure to
// bound, with the angle and the centre given for information.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>

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

const std::string kBunny = std::string(TEXBAKE_DATA_DIR) + "/bunny00.off";

class RefineCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("texbake_refine_cli_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const testing_cli::RunResult r =
        testing_cli::render_bunny_workspace(*dir_, 6, "320x240", " --samples 64");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path truth() { return *dir_ / "ws/sparse/0"; }
  static fs::path images() { return *dir_ / "ws/images"; }
  static fs::path* dir_;
};
fs::path* RefineCli::dir_ = nullptr;

std::vector<ColmapImage> read_model(const fs::path& folder) {
  Expected<std::vector<ColmapImage>> m = read_colmap_model(folder);
  EXPECT_TRUE(m) << m.error().message;
  return m ? std::move(*m) : std::vector<ColmapImage>{};
}

using Mat3 = std::array<double, 9>;

Mat3 mul(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
    }
  }
  return c;
}
Mat3 transpose(const Mat3& a) {
  return {a[0], a[3], a[6], a[1], a[4], a[7], a[2], a[5], a[8]};
}
// Rodrigues: the rotation by `deg` about the unit axis n.
Mat3 rotation(Vec3 n, double deg) {
  n = normalize(n);
  const double t = deg * std::numbers::pi / 180, c = std::cos(t), s = std::sin(t), v = 1 - c;
  return {c + n.x * n.x * v,       n.x * n.y * v - n.z * s, n.x * n.z * v + n.y * s,
          n.y * n.x * v + n.z * s, c + n.y * n.y * v,       n.y * n.z * v - n.x * s,
          n.z * n.x * v - n.y * s, n.z * n.y * v + n.x * s, c + n.z * n.z * v};
}
double angle_deg(const Mat3& a, const Mat3& b) {
  const Mat3 d = mul(a, transpose(b));
  const double c = std::clamp((d[0] + d[4] + d[8] - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180 / std::numbers::pi;
}
Vec3 apply(const Mat3& r, Vec3 v) {
  return {r[0] * v.x + r[1] * v.y + r[2] * v.z, r[3] * v.x + r[4] * v.y + r[5] * v.z,
          r[6] * v.x + r[7] * v.y + r[8] * v.z};
}

// The model with every pose moved: photo k rotated by 0.5 + 0.1 k degrees
// about a fixed axis of its own and its centre moved by `fraction` of its
// distance to the origin, perpendicular-ish to the view.
std::vector<ColmapImage> perturbed(std::vector<ColmapImage> model, double scale = 1) {
  const double fraction = 0.01 * scale;
  const Vec3 axes[] = {{1, 2, 3}, {-2, 1, 1}, {3, -1, 2}, {1, 1, -3}, {-1, -3, 1}, {2, 2, 1}};
  for (std::size_t k = 0; k < model.size(); ++k) {
    CameraSpec spec = model[k].camera.spec();
    const Vec3 centre = camera_centre(spec.pose);
    const Mat3 r =
        mul(rotation(axes[k % 6], scale * (0.5 + 0.1 * static_cast<double>(k % 6))), spec.pose.r);
    const Vec3 move = normalize(cross(axes[(k + 1) % 6], centre)) * (fraction * length(centre));
    const Vec3 c2 = centre + move;
    spec.pose.r = r;
    spec.pose.t = -apply(r, c2);
    model[k].camera = CameraProjector::make(spec).value();
  }
  return model;
}

fs::path write_model(const fs::path& folder, const std::vector<ColmapImage>& model,
                     bool binary = false) {
  fs::create_directories(folder);
  EXPECT_TRUE(write_colmap_model(folder, model, binary));
  return folder;
}

const MeshData& bunny() {
  static const MeshData mesh = read_mesh(kBunny).value().mesh;
  return mesh;
}

// Mean displacement (pixels) of every 4th vertex of the bunny between the
// projections of `a` and `b`, over the vertices in front of both.
double displacement_px(const CameraProjector& a, const CameraProjector& b) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t v = 0; v < bunny().positions.size(); v += 4) {
    const Float3 p = bunny().positions[v];
    const CameraProjection pa = a.project({p.x, p.y, p.z}), pb = b.project({p.x, p.y, p.z});
    if (!(pa.depth > 0 && pb.depth > 0)) continue;
    sum += std::hypot(pa.pixel.x - pb.pixel.x, pa.pixel.y - pb.pixel.y);
    ++n;
  }
  return sum / static_cast<double>(n);
}

// Vertices whose photo bake from `model` is within 8 levels of the direct
// bake through the sphere (both marking unseen vertices magenta; those of
// either left out).
std::size_t agreeing(const fs::path& d, const fs::path& model, const std::string& name) {
  const fs::path out = d / (name + ".ply"), direct = d / "direct.ply";
  if (!fs::exists(direct)) {
    const auto r =
        run_texbake("bake " + q(kBunny) + " --texture " +
                    q(std::string(TEXBAKE_DATA_DIR) + "/earth.jpg") + " --proxy-file " +
                    q(d / "s.json") + " --filter bilinear --occluded 1,0,1 -q -o " + q(direct));
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
  const auto r = run_texbake("bake " + q(kBunny) + " --cameras " + q(model) + " --images " +
                             q(d / "ws/images") + " --occluded 1,0,1 -q -o " + q(out));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const auto a = read_mesh(out).value().mesh.vertex_colors;
  const auto b = read_mesh(direct).value().mesh.vertex_colors;
  std::size_t n = 0;
  for (std::size_t v = 0; v < a.size(); ++v) {
    const auto magenta = [](const std::array<float, 4>& c) {
      return c[0] > 0.99f && c[1] < 0.01f && c[2] > 0.99f;
    };
    if (magenta(a[v]) || magenta(b[v])) continue;
    float worst = 0;
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(a[v][c] - b[v][c]));
    n += worst * 255 <= 8;
  }
  return n;
}

TEST_F(RefineCli, PerturbedPosesComeBackAndTheBakeAgreesBetter) {
  const fs::path& d = *dir_;
  const std::vector<ColmapImage> truth_model = read_model(truth());
  // Half the perturbation (0.25-0.5 degree, 0.5 % of the
  // distance: 1.6-5.6 px here). At the full 0.5-1 degree (3-11 px, 0.7-2.8
  // texels of these 320 x 240 photos' coarsest level) the refinement does
  // not converge (measured: 3.7-12 px left). On 1920 x 1080 photos it
  // does (bench/photos/align_refine.sh).
  const fs::path moved = write_model(d / "moved", perturbed(truth_model, 0.5));
  const auto r =
      run_texbake("cameras refine " + q(kBunny) + " --cameras " + q(moved) + " --images " +
                  q(images()) + " -o " + q(d / "refined") + " --report " + q(d / "refine.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<ColmapImage> before = read_model(moved), after = read_model(d / "refined");
  ASSERT_EQ(after.size(), truth_model.size());
  for (std::size_t k = 0; k < after.size(); ++k) {
    const CameraProjector& t = truth_model[k].camera;
    const double px_before = displacement_px(before[k].camera, t);
    const double px_after = displacement_px(after[k].camera, t);
    const double deg = angle_deg(after[k].camera.spec().pose.r, t.spec().pose.r);
    const double centre = length(after[k].camera.centre() - t.centre()) / length(t.centre());
    std::printf("%s: %.3f px -> %.3f px; after: %.4f deg, centre %.4f %% of the distance\n",
                after[k].name.c_str(), px_before, px_after, deg, 100 * centre);
    EXPECT_GT(px_before, 1.5) << after[k].name;
    // Measured (the photos' alpha masking out the background): 0.13-0.34 px.
    EXPECT_LT(px_after, 0.6) << after[k].name;
  }
  // The report: one entry per photo with its figures.
  const nlohmann::json report = nlohmann::json::parse(testing_cli::slurp(d / "refine.json"));
  ASSERT_EQ(report["photos"].size(), after.size());
  std::size_t clamped = 0;
  for (const auto& p : report["photos"]) {
    EXPECT_GT(p["rotation_change_deg"].get<double>(), 0.05);
    EXPECT_LT(p["residual_after"].get<double>(), p["residual_before"].get<double>());
    EXPECT_GT(p["iterations"].get<int>(), 0);
    clamped += p["clamped"].get<bool>();
  }
  // (Not asserted: "clamped". The orbit mode, a turn about the object
  // traded against a move of the centre, lets steps reach the default
  // bounds while the image displacement shrinks: measured 6 of 6.)
  std::printf("clamped: %zu of %zu\n", clamped, after.size());
  // The photo bake agrees with the direct bake on more vertices.
  const std::size_t n_truth = agreeing(d, truth(), "truth");
  const std::size_t n_moved = agreeing(d, moved, "moved");
  const std::size_t n_refined = agreeing(d, d / "refined", "refined");
  std::printf(
      "vertices within 8 levels of the direct bake: true poses %zu, moved %zu, "
      "refined %zu\n",
      n_truth, n_moved, n_refined);
  // Measured: true poses 20345, moved 13142, refined 20149.
  EXPECT_GT(n_refined, n_moved + (n_truth - n_moved) * 9 / 10);
}

TEST_F(RefineCli, UnperturbedPosesMoveLittle) {
  const fs::path& d = *dir_;
  const auto r = run_texbake("cameras refine " + q(kBunny) + " --cameras " + q(truth()) +
                             " --images " + q(images()) + " -q -o " + q(d / "still"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<ColmapImage> truth_model = read_model(truth()), after = read_model(d / "still");
  for (std::size_t k = 0; k < after.size(); ++k) {
    const double px = displacement_px(after[k].camera, truth_model[k].camera);
    std::printf("%s: moved %.3f px\n", after[k].name.c_str(), px);
    EXPECT_LT(px, 0.6) << after[k].name;
  }
}

TEST_F(RefineCli, AChangePastTheBoundIsClampedAndFlagged) {
  const fs::path& d = *dir_;
  const fs::path moved = write_model(d / "moved_bound", perturbed(read_model(truth())));
  const auto r = run_texbake("cameras refine " + q(kBunny) + " --cameras " + q(moved) +
                             " --images " + q(images()) + " --max-rotation 0.1 --iterations 10" +
                             " --report " + q(d / "bound.json") + " -o " + q(d / "bound"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("clamped"), std::string::npos) << r.err;
  const std::vector<ColmapImage> before = read_model(moved), after = read_model(d / "bound");
  const nlohmann::json report = nlohmann::json::parse(testing_cli::slurp(d / "bound.json"));
  std::size_t flagged = 0;
  for (std::size_t k = 0; k < after.size(); ++k) {
    // From the files themselves: at most 0.1 degree (files hold 17 digits).
    EXPECT_LE(angle_deg(after[k].camera.spec().pose.r, before[k].camera.spec().pose.r), 0.1 + 1e-7)
        << after[k].name;
    flagged += report["photos"][k]["clamped"].get<bool>();
  }
  // Every photo was moved by at least half a degree: every one needs more.
  EXPECT_EQ(flagged, after.size());
}

TEST_F(RefineCli, BadInputsAreErrorsWithNoOutput) {
  const fs::path& d = *dir_;
  const std::string head = "cameras refine " + q(kBunny) + " --cameras ";
  // -o the input model itself.
  auto r = run_texbake(head + q(truth()) + " --images " + q(images()) + " -o " + q(truth()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("texbake never overwrites an input"), std::string::npos) << r.err;
  // A model of one photo: nothing to agree with.
  std::vector<ColmapImage> one = read_model(truth());
  one.resize(1);
  const fs::path single = write_model(d / "single", one);
  r = run_texbake(head + q(single) + " --images " + q(images()) + " -o " + q(d / "o1"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("texbake: error: cameras refine needs two photos or more: one photo has "
                       "nothing to agree with"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "o1"));
  // No photo at all where --images points.
  fs::create_directories(d / "empty");
  r = run_texbake(head + q(truth()) + " --images " + q(d / "empty") + " -o " + q(d / "o2"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no usable photo: all 6 photos cannot be read"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "o2"));
  // Only one photo readable.
  fs::create_directories(d / "one_photo");
  fs::copy_file(images() / "view_00.png", d / "one_photo/view_00.png");
  r = run_texbake(head + q(truth()) + " --images " + q(d / "one_photo") + " -o " + q(d / "o3"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("only the photo of view_00.png can be read"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "o3"));
  // Not a COLMAP model folder.
  r = run_texbake(head + q(d / "s.json") + " -o " + q(d / "o4"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("cameras refine takes a COLMAP model folder"), std::string::npos) << r.err;
  // Options out of range.
  r = run_texbake(head + q(truth()) + " --max-rotation 0 -o " + q(d / "o5"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_FALSE(fs::exists(d / "o5"));
}

TEST_F(RefineCli, AMissingPhotoIsLeftOutAndItsPoseKept) {
  const fs::path& d = *dir_;
  fs::create_directories(d / "five");
  for (int k = 0; k < 5; ++k) {
    const std::string name = "view_0" + std::to_string(k) + ".png";
    fs::copy_file(images() / name, d / "five" / name);
  }
  const fs::path moved = write_model(d / "moved_bin", perturbed(read_model(truth())), true);
  const auto r = run_texbake("cameras refine " + q(kBunny) + " --cameras " + q(moved) +
                             " --images " + q(d / "five") + " --iterations 5 -q --report " +
                             q(d / "five.json") + " -o " + q(d / "five_out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("the photo of camera view_05.png is left out"), std::string::npos) << r.err;
  // Binary in, binary out; the missing photo's pose written as it was.
  EXPECT_TRUE(fs::exists(d / "five_out/images.bin"));
  EXPECT_FALSE(fs::exists(d / "five_out/images.txt"));
  const std::vector<ColmapImage> before = read_model(moved), after = read_model(d / "five_out");
  // (Up to the quaternion's round trip through the file.)
  EXPECT_LT(angle_deg(after[5].camera.spec().pose.r, before[5].camera.spec().pose.r), 1e-6);
  EXPECT_LT(length(after[5].camera.spec().pose.t - before[5].camera.spec().pose.t), 1e-12);
  EXPECT_GT(angle_deg(after[0].camera.spec().pose.r, before[0].camera.spec().pose.r), 0.05);
  const nlohmann::json report = nlohmann::json::parse(testing_cli::slurp(d / "five.json"));
  EXPECT_TRUE(report["photos"][5]["skipped"].get<bool>());
  EXPECT_EQ(report["photos_skipped"][0]["image"], "view_05.png");
}

// Each photo blotched by an opaque green block over the bunny, at a place of
// its own (what a passer-by or a reflection does to a real photo), and a
// COLMAP mask per photo that is 0 exactly there: with --masks the blotches
// are never sampled, so true poses stay where they are, as for clean photos.
TEST_F(RefineCli, MaskedOutPixelsAreNeverSampled) {
  const fs::path& d = *dir_;
  const fs::path blotched = d / "blotched", masks = d / "masks", dead = d / "dead_masks";
  fs::create_directories(blotched);
  fs::create_directories(masks);
  fs::create_directories(dead);
  const std::vector<ColmapImage> truth_model = read_model(truth());
  for (std::size_t k = 0; k < truth_model.size(); ++k) {
    const std::string name = truth_model[k].name;
    Image photo = read_image(images() / name).value();
    Image mask;
    mask.width = photo.width;
    mask.height = photo.height;
    mask.pixels.assign(static_cast<std::size_t>(photo.width) * photo.height * 4, 1.0f);
    Image none = mask;
    std::fill(none.pixels.begin(), none.pixels.end(), 0.0f);
    const int x0 = 110 + 12 * static_cast<int>(k), y0 = 85 + 6 * static_cast<int>(k);
    for (int y = y0; y < y0 + 50; ++y) {
      for (int x = x0; x < x0 + 70; ++x) {
        float* px = &photo.pixels[4 * (static_cast<std::size_t>(y) * photo.width + x)];
        px[0] = 0, px[1] = 1, px[2] = 0, px[3] = 1;
        float* m = &mask.pixels[4 * (static_cast<std::size_t>(y) * mask.width + x)];
        m[0] = m[1] = m[2] = 0;
      }
    }
    ASSERT_TRUE(write_image(blotched / name, photo.view()));
    ASSERT_TRUE(write_image(masks / (name + ".png"), mask.view()));
    // Every photo but the first masked out whole.
    ASSERT_TRUE(write_image(dead / (name + ".png"), (k == 0 ? mask : none).view()));
  }
  // 50 steps per level (not the default 200): these runs measure what the
  // masks keep out, not how far the steps go, and the unmasked one steps
  // the whole way (about 4 minutes under ASan at 200).
  const std::string head = "cameras refine " + q(kBunny) + " --cameras " + q(truth()) +
                           " --images " + q(blotched) + " --iterations 50 -q ";
  auto r = run_texbake(head + "--masks " + q(masks) + " -o " + q(d / "masked") + " --report " +
                       q(d / "masked.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake(head + "-o " + q(d / "unmasked") + " --report " + q(d / "unmasked.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("cameras refine " + q(kBunny) + " --cameras " + q(truth()) + " --images " +
                  q(images()) + " --iterations 50 -q -o " + q(d / "clean") + " --report " +
                  q(d / "clean.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The photos' disagreement before any step (RMS per channel, linear
  // light): the blotches raise it unless the masks take them out, which
  // leaves about the clean photos' (the rest of each photo is theirs).
  const auto rms = [&](const char* report) {
    const nlohmann::json j = nlohmann::json::parse(testing_cli::slurp(d / report));
    std::vector<double> out;
    for (const auto& p : j["photos"]) out.push_back(p["residual_before"].get<double>());
    return out;
  };
  const std::vector<double> rms_masked = rms("masked.json"), rms_unmasked = rms("unmasked.json"),
                            rms_clean = rms("clean.json");
  ASSERT_EQ(rms_masked.size(), truth_model.size());
  for (std::size_t k = 0; k < rms_masked.size(); ++k) {
    std::printf("%s: RMS before: clean %.4f, blotched and masked %.4f, blotched %.4f\n",
                truth_model[k].name.c_str(), rms_clean[k], rms_masked[k], rms_unmasked[k]);
    EXPECT_LT(rms_masked[k], 1.25 * rms_clean[k]) << truth_model[k].name;
    // Measured: clean 0.0023-0.0035, masked 0.0019-0.0029, blotched 0.13-0.32.
    EXPECT_GT(rms_unmasked[k], 10 * rms_masked[k]) << truth_model[k].name;
  }
  const std::vector<ColmapImage> masked = read_model(d / "masked"),
                                 unmasked = read_model(d / "unmasked");
  double worst_unmasked = 0;
  for (std::size_t k = 0; k < truth_model.size(); ++k) {
    const double px = displacement_px(masked[k].camera, truth_model[k].camera);
    const double px_unmasked = displacement_px(unmasked[k].camera, truth_model[k].camera);
    std::printf("%s: masked %.3f px, unmasked %.3f px\n", masked[k].name.c_str(), px, px_unmasked);
    // As clean photos (UnperturbedPosesMoveLittle).
    EXPECT_LT(px, 0.6) << masked[k].name;
    worst_unmasked = std::max(worst_unmasked, px_unmasked);
  }
  std::printf("unmasked: the worst photo moved %.3f px\n", worst_unmasked);
  // Masks that leave one photo: no point is seen by two, nothing written.
  r = run_texbake(head + "--masks " + q(dead) + " -o " + q(d / "dead"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no point of the mesh is seen by two photos"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "dead"));
  // A mask of another size than its photo names the mask.
  Image small;
  small.width = 16;
  small.height = 12;
  small.pixels.assign(16 * 12 * 4, 1.0f);
  fs::create_directories(d / "bad_masks");
  for (const ColmapImage& im : truth_model) {
    ASSERT_TRUE(write_image(
        d / "bad_masks" / (im.name + ".png"),
        (im.name == "view_02.png" ? small : read_image(masks / (im.name + ".png")).value())
            .view()));
  }
  r = run_texbake(head + "--masks " + q(d / "bad_masks") + " -o " + q(d / "bad"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("the mask of camera view_02.png"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "bad"));
}

}  // namespace
}  // namespace texbake
