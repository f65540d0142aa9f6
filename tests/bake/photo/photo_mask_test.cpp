// Photo masks (SPEC section 9, bake/photo/photo_bake.h "Masks") on a
// square seen straight down by pinhole cameras, whose answers are worked out
// by hand: a photo masked out wholly bakes exactly as the model without it
// (vertex and atlas, bit for bit); a photo masked on its left half leaves
// those vertices to the other photo, with the mask's edge column weighed by
// the bilinear alpha 0.5; a photo of alpha 0.5 everywhere weighs its samples
// by half in SPEC's soft blend weights; a mask file (COLMAP's rule: 0 out,
// anything else in) gives what the same mask in the photo's alpha gives.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "bake/engine/photo_atlas.h"
#include "bake/engine/photo_vertex.h"
#include "bake/photo/photo_bake.h"
#include "mesh_io/image_io.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 640, kH = 480;
constexpr double kF = 400, kCx = 320, kCy = 240;

// A pinhole camera at (cx, cy, height) looking straight down: image x along
// +x, image y along -y (look-at with up +y).
CameraProjector down_camera(double height, double cx = 0, double cy = 0) {
  Expected<CameraPose> pose = pose_from_look_at({cx, cy, height}, {cx, cy, 0}, {0, 1, 0}, "test");
  EXPECT_TRUE(pose);
  Expected<CameraProjector> c =
      CameraProjector::make({CameraModel::kPinhole, kW, kH, {kF, kF, kCx, kCy}, *pose});
  EXPECT_TRUE(c);
  return std::move(c).value();
}

// A photo of one colour (linear light, stored sRGB-encoded) and alpha
// alpha(i, j) at pixel column i, row j.
PhotoImage constant_photo(std::array<float, 3> linear,
                          const std::function<float(int i, int j)>& alpha) {
  PhotoImage img{kW, kH, std::vector<float>(std::size_t{kW} * kH * 4)};
  for (int j = 0; j < kH; ++j) {
    for (int i = 0; i < kW; ++i) {
      float* px = &img.pixels[(static_cast<std::size_t>(j) * kW + i) * 4];
      for (int ch = 0; ch < 3; ++ch) px[ch] = linear_to_srgb(linear[ch]);
      px[3] = alpha(i, j);
    }
  }
  return img;
}

// A photo of the plane z = 0 painted with an affine colour times `exposure`
// (so that several photos agree after their gains), alpha 1.
PhotoImage plane_photo(double height, double cx, double cy, double exposure) {
  PhotoImage img{kW, kH, std::vector<float>(std::size_t{kW} * kH * 4)};
  for (int j = 0; j < kH; ++j) {
    for (int i = 0; i < kW; ++i) {
      const double x = cx + (i + 0.5 - kCx) / kF * height, y = cy - (j + 0.5 - kCy) / kF * height;
      const double c[3] = {0.3 + 0.2 * x, 0.5 - 0.1 * y, 0.4 + 0.05 * (x + y)};
      float* px = &img.pixels[(static_cast<std::size_t>(j) * kW + i) * 4];
      for (int ch = 0; ch < 3; ++ch) px[ch] = linear_to_srgb(static_cast<float>(c[ch] * exposure));
      px[3] = 1;
    }
  }
  return img;
}

// The square [-1, 1]^2 at z = 0, 40 x 40 cells (vertex (i, j) at x = -1 +
// i / 20, y = -1 + j / 20), with UVs (u, v) = ((x + 1) / 2, (y + 1) / 2).
MeshData square() {
  MeshData mesh;
  test::append_grid(mesh, 40, 40, [](double s, double t) {
    return Float3{static_cast<float>(2 * s - 1), static_cast<float>(2 * t - 1), 0};
  });
  test::faces_from_triangles(mesh);
  for (const Float3& p : mesh.positions) mesh.uvs.push_back({(p.x + 1) / 2, (p.y + 1) / 2});
  for (uint32_t v : mesh.face_vertices) mesh.corner_uv.push_back(v);
  return mesh;
}

struct Shots {
  std::vector<Photo> photos;
  std::vector<PhotoImage> images;
  PhotoReader reader() const {
    return [this](const Photo& p) -> Expected<PhotoImage> {
      for (std::size_t i = 0; i < photos.size(); ++i) {
        if (photos[i].name == p.name) return images[i];
      }
      return make_error(ErrorCode::kIo, p.name + ": no such photo");
    };
  }
  void add(const std::string& name, CameraProjector camera, PhotoImage image) {
    photos.push_back({name, std::move(camera), name + ".png", {}});
    images.push_back(std::move(image));
  }
  Shots without(std::size_t k) const {
    Shots s;
    for (std::size_t i = 0; i < photos.size(); ++i) {
      if (i != k) s.add(photos[i].name, photos[i].camera, images[i]);
    }
    return s;
  }
};

// Three photos of the plane at different exposures (so the gain solve has
// work), the middle one masked out wholly.
Shots three_with_a_blank() {
  Shots s;
  s.add("a", down_camera(3, 0, 0), plane_photo(3, 0, 0, 1.0));
  s.add("blank", down_camera(3.5, 0.3, 0), plane_photo(3.5, 0.3, 0, 0.7));
  s.add("c", down_camera(4, -0.2, 0.1), plane_photo(4, -0.2, 0.1, 1.3));
  for (std::size_t i = 3; i < s.images[1].pixels.size(); i += 4) s.images[1].pixels[i] = 0;
  return s;
}

TEST(PhotoMask, APhotoMaskedOutWhollyBakesAsWithoutItVertex) {
  const MeshData mesh = square();
  const Shots with = three_with_a_blank(), without = with.without(1);
  for (PhotoBlend blend : {PhotoBlend::kSoft, PhotoBlend::kBest, PhotoBlend::kMean}) {
    PhotoBakeOptions o;
    o.blend = blend;
    Expected<PhotoBakeResult> a = bake_vertex_from_photos(mesh, with.photos, o, with.reader());
    Expected<PhotoBakeResult> b =
        bake_vertex_from_photos(mesh, without.photos, o, without.reader());
    ASSERT_TRUE(a) << a.error().message;
    ASSERT_TRUE(b) << b.error().message;
    ASSERT_EQ(a->colors.size(), b->colors.size());
    for (std::size_t v = 0; v < a->colors.size(); ++v) {
      ASSERT_EQ(a->colors[v], b->colors[v]) << "vertex " << v;  // bit for bit
    }
    ASSERT_EQ(a->cameras.size(), 3u);
    const PhotoCameraStats& blank = a->cameras[1];
    EXPECT_TRUE(blank.masked);
    EXPECT_EQ(blank.masked_share, 1.0);
    EXPECT_EQ(blank.in_view, 0u);
    EXPECT_EQ(blank.visible, 0u);
    EXPECT_EQ(blank.weight_share, 0.0);
    EXPECT_EQ(blank.gain, (std::array<double, 3>{1, 1, 1}));  // no part in the exposure solve
    EXPECT_FALSE(a->cameras[0].masked);
    EXPECT_EQ(a->cameras[0].masked_share, 0.0);
    for (int k : {0, 2}) {
      const PhotoCameraStats& x = a->cameras[k];
      const PhotoCameraStats& y = b->cameras[k / 2];
      EXPECT_EQ(x.gain, y.gain);
      EXPECT_EQ(x.in_view, y.in_view);
      EXPECT_EQ(x.weight_share, y.weight_share);
    }
    // The gains did work: photo c (exposure 1.3) gets about 1 / 1.3 of a's.
    EXPECT_NEAR(a->cameras[2].gain[0] / a->cameras[0].gain[0], 1 / 1.3, 1e-3);
  }
}

TEST(PhotoMask, APhotoMaskedOutWhollyBakesAsWithoutItAtlas) {
  const MeshData mesh = square();
  const Shots with = three_with_a_blank(), without = with.without(1);
  for (PhotoBlend blend : {PhotoBlend::kSoft, PhotoBlend::kBest, PhotoBlend::kMean}) {
    PhotoAtlasBakeOptions o;
    o.size = 64;
    o.photo.blend = blend;
    Expected<PhotoAtlasBakeResult> a = bake_atlas_from_photos(mesh, with.photos, o, with.reader());
    Expected<PhotoAtlasBakeResult> b =
        bake_atlas_from_photos(mesh, without.photos, o, without.reader());
    ASSERT_TRUE(a) << a.error().message;
    ASSERT_TRUE(b) << b.error().message;
    EXPECT_EQ(a->atlas.pixels, b->atlas.pixels);  // bit for bit
    EXPECT_EQ(a->seen, b->seen);
    EXPECT_EQ(a->seen, a->samples);  // every sample seen by a and c
    EXPECT_EQ(a->cameras[1].in_view, 0u);
    EXPECT_EQ(a->cameras[1].weight_share, 0.0);
    EXPECT_EQ(a->cameras[2].weight_share, b->cameras[1].weight_share);
  }
}

// Two photos from one camera (so q, and the soft weights, are equal): "red"
// masked on its left half (pixel columns 0 .. 319 alpha 0), "blue" whole.
// A vertex at x projects to pixel x_p = 320 + 400 x / 3, the continuous
// position x_p - 0.5 between texels floor and floor + 1: x < 0 (x_p <=
// 319.33) sees only masked texels, x > 0 (x_p >= 320.67) only kept ones,
// and x = 0 lies halfway between texels 319 (alpha 0) and 320 (alpha 1):
// red's mask there is 0.5, its colour red's own (premultiplied, so the
// masked texel does not bleed in). With equal q and exposure none:
//   x < 0: blue;  x > 0: (red + blue) / 2;  x = 0: (0.5 red + blue) / 1.5.
constexpr std::array<float, 3> kRed{0.8f, 0.1f, 0.05f}, kBlue{0.05f, 0.2f, 0.7f};

Shots half_masked() {
  Shots s;
  s.add("red", down_camera(3),
        constant_photo(kRed, [](int i, int) { return i < 320 ? 0.f : 1.f; }));
  s.add("blue", down_camera(3), constant_photo(kBlue, [](int, int) { return 1.f; }));
  return s;
}

Rgba mix(double wr, double wb) {
  Rgba c{0, 0, 0, 1};
  for (int ch = 0; ch < 3; ++ch) {
    c[ch] = static_cast<float>((wr * kRed[ch] + wb * kBlue[ch]) / (wr + wb));
  }
  return linear_to_srgb(c);
}

TEST(PhotoMask, AHalfMaskedPhotoLeavesThoseVerticesToTheOther) {
  const MeshData mesh = square();
  const Shots shots = half_masked();
  PhotoBakeOptions o;
  o.exposure = ExposureMode::kNone;
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, o, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  std::size_t left = 0, edge = 0, right = 0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const double x = mesh.positions[v].x;
    const Rgba want = x < -1e-6 ? mix(0, 1) : x > 1e-6 ? mix(1, 1) : mix(0.5, 1);
    (x < -1e-6 ? left : x > 1e-6 ? right : edge) += 1;
    for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(r->colors[v][ch], want[ch], 2e-6) << v << " x " << x;
  }
  EXPECT_EQ(left, 20u * 41);
  EXPECT_EQ(edge, 41u);
  EXPECT_EQ(r->seen, mesh.positions.size());
  // Red sees the edge column and the right half only: in view, visible.
  EXPECT_EQ(r->cameras[0].in_view, edge + right);
  EXPECT_EQ(r->cameras[0].visible, edge + right);
  EXPECT_EQ(r->cameras[1].in_view, mesh.positions.size());
  EXPECT_TRUE(r->cameras[0].masked);
  EXPECT_DOUBLE_EQ(r->cameras[0].masked_share, 0.5);
  // Weight shares: red 1/2 on the right, 1/3 on the edge, 0 on the left.
  const double red =
      (right * 0.5 + edge * (0.5 / 1.5)) / static_cast<double>(mesh.positions.size());
  EXPECT_NEAR(r->cameras[0].weight_share, red, 1e-12);
  EXPECT_NEAR(r->cameras[1].weight_share, 1 - red, 1e-12);
}

TEST(PhotoMask, AHalfMaskedPhotoLeavesThoseTexelsToTheOtherAtlas) {
  const MeshData mesh = square();
  const Shots shots = half_masked();
  PhotoAtlasBakeOptions o;
  o.size = 64;
  o.padding = 0;
  o.photo.exposure = ExposureMode::kNone;
  Expected<PhotoAtlasBakeResult> r = bake_atlas_from_photos(mesh, shots.photos, o, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  // Texel column tx holds u in [tx / 64, (tx + 1) / 64], x = 2u - 1: the
  // columns left of 31 lie wholly at x < 0 (blue), right of 32 at x > 0.
  const Rgba blue = mix(0, 1), both = mix(1, 1);
  std::size_t checked = 0;
  for (int ty = 0; ty < 64; ++ty) {
    for (int tx = 0; tx < 64; ++tx) {
      const std::size_t t = static_cast<std::size_t>(ty) * 64 + tx;
      if (!r->baked[t] || (tx >= 31 && tx <= 32)) continue;
      const Rgba& want = tx < 31 ? blue : both;
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_NEAR(r->atlas.pixels[4 * t + ch], want[ch], 2e-6) << tx << "," << ty;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 60u * 60);
  EXPECT_EQ(r->seen, r->samples);
  EXPECT_LT(r->cameras[0].in_view, r->samples * 53 / 100);
  EXPECT_GT(r->cameras[0].in_view, r->samples * 47 / 100);
  EXPECT_EQ(r->cameras[1].in_view, r->samples);
}

// Partial alpha: "near" (height 3) with alpha 0.5 everywhere and "far"
// (height 4) whole, both above the origin. On z = 0 a camera at height h
// has depth z = h at every point, cos(theta) = h / d (d the distance) and
// border 1 (every vertex lies more than 5 % of 480 px inside both photos),
// so q = (h / d) f^2 / h^2, and SPEC's soft weights times the mask:
//   w_near = 0.5 exp(-(1 - q_near / q_max) / 0.1), w_far = exp(-(1 - q_far / q_max) / 0.1).
TEST(PhotoMask, PartialAlphaWeighsTheSampleInTheSoftBlend) {
  const MeshData mesh = square();
  Shots shots;
  shots.add("near", down_camera(3), constant_photo(kRed, [](int, int) { return 0.5f; }));
  shots.add("far", down_camera(4), constant_photo(kBlue, [](int, int) { return 1.f; }));
  for (PhotoBlend blend : {PhotoBlend::kSoft, PhotoBlend::kMean, PhotoBlend::kBest}) {
    PhotoBakeOptions o;
    o.exposure = ExposureMode::kNone;
    o.blend = blend;
    Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, o, shots.reader());
    ASSERT_TRUE(r) << r.error().message;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const double x = mesh.positions[v].x, y = mesh.positions[v].y;
      auto q = [&](double h) { return h / std::sqrt(x * x + y * y + h * h) * kF * kF / (h * h); };
      const double qn = q(3), qf = q(4), qmax = std::max(qn, qf);
      double wn = 0.5, wf = 1;  // kMean: the masks alone
      if (blend == PhotoBlend::kSoft) {
        wn = 0.5 * std::exp(-(1 - qn / qmax) / 0.1);
        wf = std::exp(-(1 - qf / qmax) / 0.1);
      } else if (blend == PhotoBlend::kBest) {
        wn = 1, wf = 0;  // near is closer everywhere: the best view, its colour
      }
      const Rgba want = mix(wn, wf);
      for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(r->colors[v][ch], want[ch], 1e-5) << v;
    }
  }
  // At the origin, by hand: q_near / q_far = 16 / 9, so
  // w_near / w_far = 0.5 / exp(-(1 - 9 / 16) / 0.1) = 0.5 e^4.375 = 39.72.
  PhotoBakeOptions o;
  o.exposure = ExposureMode::kNone;
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, o, shots.reader());
  ASSERT_TRUE(r);
  const std::size_t origin = 20 * 41 + 20;
  ASSERT_EQ(mesh.positions[origin].x, 0.f);
  ASSERT_EQ(mesh.positions[origin].y, 0.f);
  const double ratio = 0.5 * std::exp(4.375);
  EXPECT_NEAR(ratio, 39.72, 0.01);
  const Rgba want = mix(ratio, 1);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(r->colors[origin][ch], want[ch], 1e-6);
}

// The same partial alpha in the atlas: the texel nearest the origin.
TEST(PhotoMask, PartialAlphaWeighsTheSampleInTheAtlas) {
  const MeshData mesh = square();
  Shots shots;
  shots.add("near", down_camera(3), constant_photo(kRed, [](int, int) { return 0.5f; }));
  shots.add("far", down_camera(4), constant_photo(kBlue, [](int, int) { return 1.f; }));
  PhotoAtlasBakeOptions o;
  o.size = 64;
  o.samples = 1;
  o.photo.exposure = ExposureMode::kNone;
  Expected<PhotoAtlasBakeResult> r = bake_atlas_from_photos(mesh, shots.photos, o, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  // samples = 1: texel (tx, ty)'s one sample sits at its centre.
  for (int ty : {5, 31, 50}) {
    for (int tx : {3, 32, 60}) {
      const double x = 2 * (tx + 0.5) / 64 - 1, y = 2 * (ty + 0.5) / 64 - 1;
      auto q = [&](double h) { return h / std::sqrt(x * x + y * y + h * h) * kF * kF / (h * h); };
      const double qn = q(3), qf = q(4), qmax = std::max(qn, qf);
      const Rgba want =
          mix(0.5 * std::exp(-(1 - qn / qmax) / 0.1), std::exp(-(1 - qf / qmax) / 0.1));
      // The atlas's rows run top (v = 1) down.
      const std::size_t t = static_cast<std::size_t>(63 - ty) * 64 + tx;
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(r->atlas.pixels[4 * t + ch], want[ch], 1e-5) << tx << "," << ty;
      }
    }
  }
}

// A mask file in COLMAP's convention (0 out, any other value in: 128 counts
// as 255) gives, bit for bit, what the same binary mask in the photo's alpha
// gives; it multiplies the photo's own alpha.
TEST(PhotoMask, AMaskFileEqualsTheSameMaskInTheAlpha) {
  const fs::path dir = fs::temp_directory_path() / ("texbake_mask_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Image mask;
  mask.width = kW, mask.height = kH;
  mask.pixels.assign(std::size_t{kW} * kH * 4, 0.f);
  auto kept = [](int i, int j) { return i >= 200 && !(j > 100 && j < 150 && i > 400); };
  for (int j = 0; j < kH; ++j) {
    for (int i = 0; i < kW; ++i) {
      float* px = &mask.pixels[(static_cast<std::size_t>(j) * kW + i) * 4];
      const float g = kept(i, j) ? (i % 2 ? 128.f / 255 : 1.f) : 0.f;
      px[0] = px[1] = px[2] = g;
      px[3] = 1;
    }
  }
  ASSERT_TRUE(write_image(dir / "a.png.png", mask.view()));
  const MeshData mesh = square();
  Shots by_file = three_with_a_blank();
  by_file.images[1] = plane_photo(3.5, 0.3, 0, 0.7);  // the middle one whole again
  // Photo c's own alpha: 0.25 on rows 0..49, which the mask file multiplies.
  for (int j = 0; j < 50; ++j) {
    for (int i = 0; i < kW; ++i)
      by_file.images[2].pixels[(static_cast<std::size_t>(j) * kW + i) * 4 + 3] = 0.25f;
  }
  Shots by_alpha = by_file;
  by_file.photos[0].mask = dir / "a.png.png";
  by_file.photos[2].mask = dir / "a.png.png";
  for (int k : {0, 2}) {
    for (int j = 0; j < kH; ++j) {
      for (int i = 0; i < kW; ++i) {
        float& a = by_alpha.images[k].pixels[(static_cast<std::size_t>(j) * kW + i) * 4 + 3];
        if (!kept(i, j)) a = 0;
      }
    }
  }
  Expected<PhotoBakeResult> a = bake_vertex_from_photos(mesh, by_file.photos, {}, by_file.reader());
  Expected<PhotoBakeResult> b =
      bake_vertex_from_photos(mesh, by_alpha.photos, {}, by_alpha.reader());
  ASSERT_TRUE(a) << a.error().message;
  ASSERT_TRUE(b) << b.error().message;
  EXPECT_EQ(a->colors, b->colors);
  EXPECT_EQ(a->cameras[0].in_view, b->cameras[0].in_view);
  EXPECT_LT(a->cameras[0].in_view, mesh.positions.size());
  EXPECT_DOUBLE_EQ(a->cameras[0].masked_share,
                   (200.0 * kH + 49.0 * 239) / (static_cast<double>(kW) * kH));
  PhotoAtlasBakeOptions o;
  o.size = 48;
  Expected<PhotoAtlasBakeResult> c =
      bake_atlas_from_photos(mesh, by_file.photos, o, by_file.reader());
  Expected<PhotoAtlasBakeResult> d =
      bake_atlas_from_photos(mesh, by_alpha.photos, o, by_alpha.reader());
  ASSERT_TRUE(c) << c.error().message;
  ASSERT_TRUE(d) << d.error().message;
  EXPECT_EQ(c->atlas.pixels, d->atlas.pixels);

  // A mask of another size than its photo is an error naming the mask file.
  mask.width = 320, mask.height = 240;
  mask.pixels.assign(std::size_t{320} * 240 * 4, 1.f);
  ASSERT_TRUE(write_image(dir / "small.png", mask.view()));
  by_file.photos[2].mask = dir / "small.png";
  Expected<PhotoBakeResult> e = bake_vertex_from_photos(mesh, by_file.photos, {}, by_file.reader());
  ASSERT_FALSE(e);
  EXPECT_EQ(e.error().code, ErrorCode::kParse);
  EXPECT_EQ(e.error().message, "the mask of camera c: " + (dir / "small.png").string() +
                                   " is 320 x 240, its photo c.png 640 x 480 (a mask must have "
                                   "its photo's size)");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace texbake
