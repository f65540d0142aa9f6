// Colouring from photographs (bake/photo/photo_bake.h) on scenes whose
// answer is known in closed form: a square seen straight down by pinhole
// cameras whose photos were painted here from an affine function of the
// world point behind each pixel (so bilinear interpolation in linear light
// is exact), an occluder with a shadow computed by similar triangles,
// photos scaled in exposure, cameras behind the surface, and the blend
// weights of SPEC section 9 worked out by hand.
#include "bake/photo/photo_bake.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bake/engine/bake_atlas.h"
#include "bake/engine/photo_atlas.h"
#include "bake/engine/photo_vertex.h"
#include "bake/util/parallel.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

constexpr int kW = 640, kH = 480;
constexpr double kF = 400, kCx = 320, kCy = 240;

// The truth, in linear light, at world (x, y) on the plane z = 0.
Rgba truth(double x, double y) {
  return {static_cast<float>(0.3 + 0.2 * x), static_cast<float>(0.5 - 0.1 * y),
          static_cast<float>(0.4 + 0.05 * (x + y)), 1};
}

// A pinhole camera at (cx, cy, height) looking straight down, image x along
// +x and image y along -y (look-at with up +y).
CameraProjector down_camera(double height, double cx = 0, double cy = 0) {
  Expected<CameraPose> pose = pose_from_look_at({cx, cy, height}, {cx, cy, 0}, {0, 1, 0}, "test");
  EXPECT_TRUE(pose);
  Expected<CameraProjector> c =
      CameraProjector::make({CameraModel::kPinhole, kW, kH, {kF, kF, kCx, kCy}, *pose});
  EXPECT_TRUE(c);
  return std::move(c).value();
}

// The photo such a camera takes of the plane z = 0 painted with truth() times
// `exposure` (in linear light), stored sRGB-encoded as floats.
PhotoImage photo_of_plane(double height, double exposure, double cx = 0, double cy = 0, int w = kW,
                          int h = kH) {
  PhotoImage img{w, h, std::vector<float>(static_cast<std::size_t>(w) * h * 4)};
  const double s = static_cast<double>(kW) / w;  // camera pixels per photo pixel
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const double a = ((i + 0.5) * s - kCx) / kF, b = ((j + 0.5) * s - kCy) / kF;
      const Rgba c = truth(cx + a * height, cy - b * height);
      float* px = &img.pixels[(static_cast<std::size_t>(j) * w + i) * 4];
      for (int ch = 0; ch < 3; ++ch) px[ch] = linear_to_srgb(static_cast<float>(c[ch] * exposure));
      px[3] = 1;
    }
  }
  return img;
}

// The square [-1, 1]^2 at z = 0, 40 x 40 cells, normals +z; optionally an
// occluding square [-r, r]^2 at z = 1 (normals +z).
MeshData scene(double occluder = 0) {
  MeshData mesh;
  test::append_grid(mesh, 40, 40, [](double s, double t) {
    return Float3{static_cast<float>(2 * s - 1), static_cast<float>(2 * t - 1), 0};
  });
  if (occluder > 0) {
    test::append_grid(mesh, 2, 2, [&](double s, double t) {
      return Float3{static_cast<float>(occluder * (2 * s - 1)),
                    static_cast<float>(occluder * (2 * t - 1)), 1};
    });
  }
  test::faces_from_triangles(mesh);
  return mesh;
}

constexpr std::size_t kGridVertices = 41 * 41;

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
};

TEST(PhotoBake, OnePhotoGivesTheTruthExactly) {
  const MeshData mesh = scene();
  Shots shots;
  shots.add("top", down_camera(3), photo_of_plane(3, 1));
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, {}, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->seen, kGridVertices);
  EXPECT_EQ(r->cameras[0].in_view, kGridVertices);
  EXPECT_EQ(r->cameras[0].visible, kGridVertices);
  EXPECT_DOUBLE_EQ(r->cameras[0].weight_share, 1.0);
  for (std::size_t v = 0; v < kGridVertices; ++v) {
    const Rgba want = linear_to_srgb(truth(mesh.positions[v].x, mesh.positions[v].y));
    for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(r->colors[v][ch], want[ch], 2e-5) << v;
    EXPECT_EQ(r->colors[v][3], 1);
  }
}

TEST(PhotoBake, AnOccluderShadowsBySimilarTrianglesAndTheShadowIsFilled) {
  // CameraProjector at height 3, occluder [-0.31, 0.31]^2 at height 1: its shadow on
  // z = 0 is [-0.465, 0.465]^2 (scale 3 / 2), between grid lines 0.45 and 0.5.
  const MeshData mesh = scene(0.31);
  Shots shots;
  shots.add("top", down_camera(3), photo_of_plane(3, 1));
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, {}, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  std::size_t shadowed = 0;
  for (std::size_t v = 0; v < kGridVertices; ++v) {
    shadowed += std::abs(mesh.positions[v].x) < 0.465 && std::abs(mesh.positions[v].y) < 0.465;
  }
  EXPECT_EQ(shadowed, 19u * 19u);
  EXPECT_EQ(r->cameras[0].in_view, mesh.positions.size());
  EXPECT_EQ(r->cameras[0].visible, mesh.positions.size() - shadowed);
  EXPECT_EQ(r->seen, mesh.positions.size() - shadowed);
  EXPECT_EQ(r->filled, shadowed);
  // The truth is affine in x and y, so its harmonic extension over the
  // shadow is the truth itself (in linear light), up to the grid's
  // discrete Laplacian being exact on affine functions.
  for (std::size_t v = 0; v < kGridVertices; ++v) {
    const Rgba want = linear_to_srgb(truth(mesh.positions[v].x, mesh.positions[v].y));
    for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(r->colors[v][ch], want[ch], 1e-4) << v;
  }
}

TEST(PhotoBake, ExposureGainsRecoverTheInverseScales) {
  const MeshData mesh = scene();
  Shots shots;
  const std::vector<double> exposure = {1.0, 0.8, 1.25};
  shots.add("a", down_camera(3), photo_of_plane(3, exposure[0]));
  shots.add("b", down_camera(3.5, 0.2, -0.1), photo_of_plane(3.5, exposure[1], 0.2, -0.1));
  shots.add("c", down_camera(2.8, -0.15, 0.1), photo_of_plane(2.8, exposure[2], -0.15, 0.1));
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, {}, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  // g_k exposure_k is the same for every photo (the common factor), and the
  // gains' geometric mean is 1: g_k = c / exposure_k with c the exposures'
  // geometric mean (here 1: 1 x 0.8 x 1.25 = 1).
  double log_sum = 0;
  for (double e : exposure) log_sum += std::log(e);
  const double common = std::exp(log_sum / 3);  // every blended colour is truth * common
  for (std::size_t k = 0; k < 3; ++k) {
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(r->cameras[k].gain[ch], common / exposure[k], 1e-3) << k << " " << ch;
    }
  }
  for (std::size_t v = 0; v < kGridVertices; ++v) {
    const Rgba t = truth(mesh.positions[v].x, mesh.positions[v].y);
    for (int ch = 0; ch < 3; ++ch) {
      ASSERT_NEAR(srgb_to_linear(r->colors[v][ch]), t[ch] * common, 2e-4) << v;
    }
  }
  // Without gains the same scene blends three different exposures.
  PhotoBakeOptions none;
  none.exposure = ExposureMode::kNone;
  Expected<PhotoBakeResult> raw = bake_vertex_from_photos(mesh, shots.photos, none, shots.reader());
  ASSERT_TRUE(raw);
  EXPECT_EQ(raw->cameras[1].gain[0], 1);
}

TEST(PhotoBake, AnUnreadablePhotoIsLeftOutAndTheRestGiveTheSameResult) {
  // Three photos, the middle one's file missing: the bake is exactly the
  // bake of the other two (gains included), with a warning and the photo
  // listed; strict_photos makes it an error; none readable is an error.
  const MeshData mesh = scene();
  Shots all, two;
  all.add("a", down_camera(3), photo_of_plane(3, 1.0));
  all.add("b", down_camera(3.5, 0.2, -0.1), photo_of_plane(3.5, 0.8, 0.2, -0.1));
  all.add("c", down_camera(2.8, -0.15, 0.1), photo_of_plane(2.8, 1.25, -0.15, 0.1));
  two.add("a", down_camera(3), photo_of_plane(3, 1.0));
  two.add("c", down_camera(2.8, -0.15, 0.1), photo_of_plane(2.8, 1.25, -0.15, 0.1));
  const PhotoReader all_reader = all.reader();
  const PhotoReader missing_b = [&](const Photo& p) -> Expected<PhotoImage> {
    if (p.name == "b") return make_error(ErrorCode::kIo, "b.png: no such file");
    return all_reader(p);
  };
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, all.photos, {}, missing_b);
  ASSERT_TRUE(r) << r.error().message;
  Expected<PhotoBakeResult> want = bake_vertex_from_photos(mesh, two.photos, {}, two.reader());
  ASSERT_TRUE(want) << want.error().message;
  ASSERT_EQ(r->cameras.size(), 2u);
  EXPECT_EQ(r->cameras[0].name, "a");
  EXPECT_EQ(r->cameras[1].name, "c");
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(r->cameras[k].gain, want->cameras[k].gain);
    EXPECT_EQ(r->cameras[k].visible, want->cameras[k].visible);
  }
  EXPECT_EQ(r->colors, want->colors);
  ASSERT_EQ(r->skipped.size(), 1u);
  EXPECT_EQ(r->skipped[0].name, "b");
  EXPECT_EQ(r->skipped[0].path, "b.png");
  EXPECT_EQ(r->skipped[0].reason, "b.png: no such file");
  EXPECT_EQ(r->warnings,
            std::vector<std::string>{"the photo of camera b is left out: b.png: no such file"});

  PhotoBakeOptions strict;
  strict.strict_photos = true;
  Expected<PhotoBakeResult> s = bake_vertex_from_photos(mesh, all.photos, strict, missing_b);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kIo);
  EXPECT_EQ(s.error().message, "the photo of camera b: b.png: no such file");

  const PhotoReader none = [](const Photo& p) -> Expected<PhotoImage> {
    return make_error(ErrorCode::kParse, p.name + ".png: not an image");
  };
  Expected<PhotoBakeResult> n = bake_vertex_from_photos(mesh, all.photos, {}, none);
  ASSERT_FALSE(n);
  EXPECT_EQ(n.error().code, ErrorCode::kIo);
  EXPECT_EQ(n.error().message,
            "no usable photo: all 3 photos cannot be read (the first: a.png: not an image)");
  // A cancelled read is no unreadable photo: it stops the bake.
  const PhotoReader cancel = [](const Photo&) -> Expected<PhotoImage> {
    return make_error(ErrorCode::kCancelled, "cancelled");
  };
  Expected<PhotoBakeResult> c = bake_vertex_from_photos(mesh, all.photos, {}, cancel);
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error().code, ErrorCode::kCancelled);
}

TEST(PhotoBake, BlendWeightsByHand) {
  // Constant photos: 0.2 (linear) from height 2, 0.6 from height 4, both
  // straight above the centre vertex (cos theta = 1, border 1): q = f^2 / z^2,
  // so q_far / q_near = 4 / 16 = 0.25 and the soft weight of the far photo
  // is exp(-(1 - 0.25) / 0.1) = exp(-7.5).
  const MeshData mesh = scene();
  auto constant = [](float linear) {
    PhotoImage img{kW, kH, std::vector<float>(kW * kH * 4, linear_to_srgb(linear))};
    for (std::size_t i = 3; i < img.pixels.size(); i += 4) img.pixels[i] = 1;
    return img;
  };
  Shots shots;
  shots.add("near", down_camera(2), constant(0.2f));
  shots.add("far", down_camera(4), constant(0.6f));
  const std::size_t centre = 20 * 41 + 20;
  ASSERT_EQ(mesh.positions[centre].x, 0);
  auto centre_linear = [&](PhotoBlend blend) {
    PhotoBakeOptions o;
    o.blend = blend;
    o.exposure = ExposureMode::kNone;
    Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, o, shots.reader());
    EXPECT_TRUE(r);
    return srgb_to_linear(r->colors[centre][0]);
  };
  const double e = std::exp(-7.5);
  EXPECT_NEAR(centre_linear(PhotoBlend::kSoft), (0.2 + 0.6 * e) / (1 + e), 1e-6);
  EXPECT_NEAR(centre_linear(PhotoBlend::kBest), 0.2, 1e-6);
  EXPECT_NEAR(centre_linear(PhotoBlend::kMean), 0.4, 1e-6);
}

TEST(PhotoBake, CamerasBehindTheSurfaceSeeNothing) {
  // Looking up at the square from below: every normal faces away.
  const MeshData mesh = scene();
  Expected<CameraPose> pose = pose_from_look_at({0, 0, -3}, {0, 0, 0}, {0, 1, 0}, "below");
  ASSERT_TRUE(pose);
  Expected<CameraProjector> cam =
      CameraProjector::make({CameraModel::kPinhole, kW, kH, {kF, kF, kCx, kCy}, *pose});
  ASSERT_TRUE(cam);
  Shots shots;
  shots.add("below", *cam, photo_of_plane(3, 1));
  PhotoBakeOptions o;
  o.occluded_color = {1, 0, 1, 1};
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, o, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->cameras[0].in_view, 0u);
  EXPECT_EQ(r->seen, 0u);
  EXPECT_EQ(r->unfilled, kGridVertices);
  EXPECT_EQ(r->colors[0], (Rgba{1, 0, 1, 1}));
}

TEST(PhotoBake, ALinearPhotoIsNotLinearisedAgain) {
  // The same photo stored as linear values and tagged linear: the same bake.
  const MeshData mesh = scene();
  Shots srgb, linear;
  srgb.add("top", down_camera(3), photo_of_plane(3, 1));
  PhotoImage lin = photo_of_plane(3, 1);
  for (std::size_t i = 0; i < lin.pixels.size(); ++i) {
    if (i % 4 != 3) lin.pixels[i] = srgb_to_linear(lin.pixels[i]);
  }
  lin.color_space = ColorSpace::kLinear;
  linear.add("top", down_camera(3), std::move(lin));
  Expected<PhotoBakeResult> a = bake_vertex_from_photos(mesh, srgb.photos, {}, srgb.reader());
  Expected<PhotoBakeResult> b = bake_vertex_from_photos(mesh, linear.photos, {}, linear.reader());
  ASSERT_TRUE(a && b);
  for (std::size_t v = 0; v < kGridVertices; ++v) {
    for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(a->colors[v][ch], b->colors[v][ch], 1e-6) << v;
  }
}

TEST(PhotoBake, PhotoSizes) {
  const MeshData mesh = scene();
  Shots half;
  half.add("half", down_camera(3), photo_of_plane(3, 1, 0, 0, kW / 2, kH / 2));
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, half.photos, {}, half.reader());
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_NE(r->warnings[0].find("320 x 240"), std::string::npos) << r->warnings[0];
  EXPECT_TRUE(r->cameras[0].scaled);
  for (std::size_t v = 0; v < kGridVertices; ++v) {
    const Rgba want = linear_to_srgb(truth(mesh.positions[v].x, mesh.positions[v].y));
    ASSERT_NEAR(r->colors[v][0], want[0], 2e-5) << v;  // still exact: the truth is affine
  }
  Shots wrong;
  wrong.add("wrong", down_camera(3), photo_of_plane(3, 1, 0, 0, 640, 640));
  Expected<PhotoBakeResult> bad = bake_vertex_from_photos(mesh, wrong.photos, {}, wrong.reader());
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message,
            "wrong.png: the photo of wrong is 640 x 640, its camera 640 x 480 (neither that size "
            "nor that aspect)");
  EXPECT_FALSE(bake_vertex_from_photos(mesh, {}, {}, wrong.reader()));
}

TEST(PhotoBake, UnseenVerticesFollowTheOccludedModeAndAnUnseenComponentTakesTheColour) {
  // SPEC section 9: vertices no photo sees follow --occluded: the fill in
  // linear light (project acts as fill: there is nothing to project), or the
  // colour as given; a component no photo sees at all (a square under the
  // plane, hidden from both cameras) takes the colour under every mode.
  // Seen vertices keep their blend whatever the mode.
  MeshData mesh;
  test::append_grid(mesh, 40, 40, [](double s, double t) {
    return Float3{static_cast<float>(2 * s - 1), static_cast<float>(2 * t - 1), 0};
  });
  test::append_grid(mesh, 2, 2, [](double s, double t) {  // the occluder
    return Float3{static_cast<float>(0.62 * s - 0.31), static_cast<float>(0.62 * t - 0.31), 1};
  });
  test::append_grid(mesh, 3, 3, [](double s, double t) {  // hidden below the plane
    return Float3{static_cast<float>(s - 0.5), static_cast<float>(t - 0.5), -1};
  });
  test::faces_from_triangles(mesh);
  const std::size_t hidden_first = mesh.positions.size() - 16;
  Shots shots;
  shots.add("top", down_camera(3), photo_of_plane(3, 1));
  shots.add("side", down_camera(4, 0.3, -0.2), photo_of_plane(4, 0.7, 0.3, -0.2));
  const Rgba colour{0.25f, 0.5f, 0.75f, 1};
  std::vector<Expected<PhotoBakeResult>> r;
  for (OccludedMode mode : {OccludedMode::kFill, OccludedMode::kProject, OccludedMode::kColor}) {
    PhotoBakeOptions o;
    o.occluded = mode;
    o.occluded_color = colour;
    o.keep_points = true;
    r.push_back(bake_vertex_from_photos(mesh, shots.photos, o, shots.reader()));
    ASSERT_TRUE(r.back()) << r.back().error().message;
  }
  const PhotoBakeResult &fill = *r[0], &project = *r[1], &constant = *r[2];
  // The occluder's shadow on the plane, and the hidden square, are unseen.
  ASSERT_LT(fill.seen + 16, mesh.positions.size());
  EXPECT_EQ(fill.unfilled, 16u);
  EXPECT_EQ(fill.filled, mesh.positions.size() - fill.seen - 16);
  EXPECT_EQ(constant.filled, 0u);
  std::size_t unseen = 0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    SCOPED_TRACE(testing::Message() << "vertex " << v);
    const bool seen = fill.points.state[v] == PhotoPoints::kSeen;
    unseen += !seen;
    for (int ch = 0; ch < 4; ++ch) {
      ASSERT_EQ(project.colors[v][ch], fill.colors[v][ch]);  // project acts as fill
      if (seen) {
        ASSERT_EQ(constant.colors[v][ch], fill.colors[v][ch]);  // the blend, whatever the mode
      } else {
        ASSERT_EQ(constant.colors[v][ch], colour[ch]);  // the colour as given
      }
      if (v >= hidden_first) {
        ASSERT_EQ(fill.colors[v][ch], colour[ch]);
      }
    }
    if (seen) {
      EXPECT_EQ(fill.colors[v][3], 1.f);  // the blend is opaque
    }
  }
  EXPECT_EQ(unseen, mesh.positions.size() - fill.seen);
}

TEST(PhotoBake, IdenticalWithOneAndTwoThreads) {
  const MeshData mesh = scene(0.31);
  Shots shots;
  shots.add("a", down_camera(3), photo_of_plane(3, 1));
  shots.add("b", down_camera(3.5, 0.2, -0.1), photo_of_plane(3.5, 0.9, 0.2, -0.1));
  std::vector<Rgba> one, two;
  {
    ThreadLimit limit(1);
    Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, {}, shots.reader());
    ASSERT_TRUE(r);
    one = r->colors;
  }
  {
    ThreadLimit limit(2);
    Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, {}, shots.reader());
    ASSERT_TRUE(r);
    two = r->colors;
  }
  EXPECT_EQ(one, two);
}

TEST(PhotoBake, AtlasIdenticalWithOneAndTwoThreads) {
  // The photo atlas's passes (cull and segments per camera, weights,
  // colours, texel means, the fill from the vertex bake, padding) under
  // each blend, on the occluded scene with three photos: the same bits and
  // per-camera figures at one and two threads. (A small scene: the round
  // trip's own thread test is too slow for the ThreadSanitizer stage.)
  const MeshData grid = scene(0.31);
  std::vector<Float2> uvs;
  for (const Float3& p : grid.positions) uvs.push_back({0.5f + 0.45f * p.x, 0.5f + 0.45f * p.y});
  const MeshData mesh = mesh_with_triangle_uvs(grid, uvs, grid.triangles);
  Shots shots;
  shots.add("a", down_camera(3), photo_of_plane(3, 1));
  shots.add("b", down_camera(3.5, 0.2, -0.1), photo_of_plane(3.5, 0.9, 0.2, -0.1));
  shots.add("c", down_camera(2.8, -0.15, 0.1), photo_of_plane(2.8, 1.1, -0.15, 0.1));
  for (PhotoBlend blend : {PhotoBlend::kSoft, PhotoBlend::kBest, PhotoBlend::kMean}) {
    PhotoAtlasBakeOptions o;
    o.size = 64;
    o.photo.blend = blend;
    std::vector<PhotoAtlasBakeResult> results;
    for (int threads : {1, 2}) {
      ThreadLimit limit(threads);
      Expected<PhotoAtlasBakeResult> r =
          bake_atlas_from_photos(mesh, shots.photos, o, shots.reader());
      ASSERT_TRUE(r) << r.error().message;
      results.push_back(std::move(*r));
    }
    EXPECT_EQ(results[0].atlas.pixels, results[1].atlas.pixels);
    ASSERT_EQ(results[0].cameras.size(), 3u);
    ASSERT_EQ(results[1].cameras.size(), 3u);
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_GT(results[0].cameras[c].visible, 0u);
      EXPECT_EQ(results[0].cameras[c].visible, results[1].cameras[c].visible);
      EXPECT_EQ(results[0].cameras[c].weight_share, results[1].cameras[c].weight_share);
    }
  }
}

// Grey stripes across x, 0.1 wide (linear 0.2 and 0.8, so the luminance
// is the grey itself), their edges at x = 0.1 k - 0.025: every grid vertex
// (x = 0.05 i - 1) lies 0.025 (3.3 photo pixels at height 3) from an edge,
// where the bilinear lookup reads one stripe only.
double stripe(double x) {
  return static_cast<long>(std::floor((x + 0.025) / 0.1)) % 2 == 0 ? 0.2 : 0.8;
}

// The photo of the stripes taken by a camera at (cx + shift, 0, height)
// looking down; given to a camera at (cx, 0, height), its pose is wrong by
// `shift` along x.
PhotoImage photo_of_stripes(double height, double cx, double shift) {
  PhotoImage img{kW, kH, std::vector<float>(static_cast<std::size_t>(kW) * kH * 4)};
  for (int j = 0; j < kH; ++j) {
    for (int i = 0; i < kW; ++i) {
      const double a = (i + 0.5 - kCx) / kF;
      const float g = linear_to_srgb(static_cast<float>(stripe(cx + shift + a * height)));
      float* px = &img.pixels[(static_cast<std::size_t>(j) * kW + i) * 4];
      px[0] = px[1] = px[2] = g;
      px[3] = 1;
    }
  }
  return img;
}

TEST(PhotoConsistency, PhotosOfTheRightPlaceAgreeEverywhere) {
  // Both cameras see the whole square (half-widths 2.4 x 1.8 at height 3,
  // inside 75 degrees): every vertex is seen by both, with the same grey.
  const MeshData mesh = scene();
  Shots shots;
  shots.add("a", down_camera(3, 0.1), photo_of_stripes(3, 0.1, 0));
  shots.add("b", down_camera(3, -0.1), photo_of_stripes(3, -0.1, 0));
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, {}, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->consistency.vertices, kGridVertices);
  EXPECT_EQ(r->consistency.agreeing, 1.0);
  EXPECT_LT(r->consistency.median_deviation, 1e-4);
  EXPECT_LT(r->consistency.gain_ratio, 1.001);
  for (const PhotoCameraStats& c : r->cameras) {
    EXPECT_EQ(c.shared, kGridVertices);
    EXPECT_LT(c.deviation, 1e-4);
  }
  for (const std::string& w : r->warnings) EXPECT_EQ(w.find("disagree"), std::string::npos) << w;
}

TEST(PhotoConsistency, APoseOffByOneStripeDisagreesEverywhereAndWarns) {
  // Camera b's photo was taken 0.1 further along x than its pose says: at
  // every vertex it shows the other stripe, 0.2 against 0.8. With gains
  // off, each vertex's deviation is |0.2 - 0.8| / (0.2 + 0.8) = 0.6 (the
  // median of two is their mean, 0.5), and so is each photo's.
  const MeshData mesh = scene();
  Shots shots;
  shots.add("a", down_camera(3, 0.1), photo_of_stripes(3, 0.1, 0));
  shots.add("b", down_camera(3, -0.1), photo_of_stripes(3, -0.1, 0.1));
  PhotoBakeOptions options;
  options.exposure = ExposureMode::kNone;
  Expected<PhotoBakeResult> r =
      bake_vertex_from_photos(mesh, shots.photos, options, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->consistency.vertices, kGridVertices);
  EXPECT_EQ(r->consistency.agreeing, 0.0);
  EXPECT_NEAR(r->consistency.median_deviation, 0.6, 1e-4);
  for (const PhotoCameraStats& c : r->cameras) EXPECT_NEAR(c.deviation, 0.6, 1e-4);
  bool warned = false;
  for (const std::string& w : r->warnings) {
    if (w.find("the photos disagree on the mesh (0 % of 1681 vertices") == 0) warned = true;
  }
  EXPECT_TRUE(warned);
  EXPECT_EQ(r->warnings.back().find("texbake cameras align") != std::string::npos, true);

  // The check off (--no-alignment-check): the same figures, no warning.
  options.consistency_warning = false;
  Expected<PhotoBakeResult> quiet =
      bake_vertex_from_photos(mesh, shots.photos, options, shots.reader());
  ASSERT_TRUE(quiet);
  EXPECT_EQ(quiet->consistency.agreeing, 0.0);
  for (const std::string& w : quiet->warnings) EXPECT_EQ(w.find("disagree"), std::string::npos);
}

TEST(PhotoConsistency, GainsSpreadWiderThanFourFoldWarn) {
  // Exposures 1 and 5 of the same place: the gains undo them (ratio 5 >
  // kGainRatioDoubtful) and the photos then agree, but a fivefold exposure
  // difference is the mark of photos matched against the wrong surface.
  const MeshData mesh = scene();
  Shots shots;
  shots.add("a", down_camera(3), photo_of_plane(3, 0.2));
  shots.add("b", down_camera(3.5, 0.2, -0.1), photo_of_plane(3.5, 1.0, 0.2, -0.1));
  Expected<PhotoBakeResult> r = bake_vertex_from_photos(mesh, shots.photos, {}, shots.reader());
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_NEAR(r->consistency.gain_ratio, 5.0, 0.02);
  EXPECT_GT(r->consistency.agreeing, 0.99);
  bool warned = false;
  for (const std::string& w : r->warnings) warned |= w.find("gains within 5x") != std::string::npos;
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace texbake
