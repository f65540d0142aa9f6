// The atlas baker end to end (without the CLI): a UV sphere through a sphere
// proxy reproduces the source image, chart borders never expose an unbaked
// texel, occlusion, determinism, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "bake/atlas/atlas_raster.h"
#include "bake/atlas/dilate.h"
#include "bake/engine/bake_atlas.h"
#include "bake/util/parallel.h"
#include "bake/uv/uv_proxy.h"
#include "mesh_io/image_io.h"
#include "tests/bake/atlas/atlas_test_util.h"
#include "tests/bake/uv/uv_sphere.h"

namespace texbake {
namespace {

Proxy unit_sphere() {
  SphereParams p;
  p.pole = {0, 0, 1};
  p.equator = Vec3{1, 0, 0};
  return make_proxy(p).value();
}

// The test's own bilinear lookup (SPEC section 1: x = u W - 0.5,
// y = (1 - v) H - 0.5; u wraps, v clamps), independent of mapping/sample.h.
std::array<double, 4> lookup(const float* px, int w, int h, double u, double v, bool wrap_u) {
  const double x = u * w - 0.5, y = (1 - v) * h - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  std::array<double, 4> out{};
  for (int dy = 0; dy < 2; ++dy) {
    for (int dx = 0; dx < 2; ++dx) {
      int xx = x0 + dx, yy = std::clamp(y0 + dy, 0, h - 1);
      xx = wrap_u ? ((xx % w) + w) % w : std::clamp(xx, 0, w - 1);
      const double wt = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
      for (int c = 0; c < 4; ++c)
        out[c] += wt * px[(static_cast<std::size_t>(yy) * w + xx) * 4 + c];
    }
  }
  return out;
}

// A smooth image, periodic in u: bilinear interpolation of it is accurate to
// well under 1e-3 at any resolution used here.
Image smooth_image(int w, int h) {
  Image img;
  img.width = w;
  img.height = h;
  img.pixels.resize(static_cast<std::size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double u = (x + 0.5) / w, v = 1 - (y + 0.5) / h;
      float* p = &img.pixels[(static_cast<std::size_t>(y) * w + x) * 4];
      // The u-dependent terms fade at the poles (times sin(pi v)), so the
      // image is a continuous function on the sphere.
      p[0] = static_cast<float>(0.5 + 0.4 * std::sin(2 * std::numbers::pi * u) *
                                          std::sin(std::numbers::pi * v));
      p[1] = static_cast<float>(0.5 + 0.4 * std::cos(std::numbers::pi * v));
      p[2] = static_cast<float>(0.5 + 0.3 * std::cos(2 * std::numbers::pi * u) *
                                          std::sin(std::numbers::pi * v));
      p[3] = 1;
    }
  }
  return img;
}

MeshData sphere_layout(int rings, int segments) {
  return proxy_uv_layout(test::make_uv_sphere(rings, segments, 0.5), unit_sphere()).value().mesh;
}

AtlasBakeOptions options(int size, int samples) {
  AtlasBakeOptions o;
  o.size = size;
  o.samples = samples;
  return o;
}

// PSNR over covered texels of the atlas against the source image resampled
// directly at the same supersample positions (no mesh, no proxy).
TEST(AtlasBake, UvSphereWithProxyUvsReproducesTheImage) {
  auto earth = read_image(TEXBAKE_DATA_DIR "/earth.jpg");
  ASSERT_TRUE(earth) << earth.error().message;
  const MeshData mesh = sphere_layout(128, 256);
  const int n = 512, spt = 4;
  auto baked = bake_atlas(mesh, earth->view(), unit_sphere(), options(n, spt));
  ASSERT_TRUE(baked) << baked.error().message;
  EXPECT_EQ(baked->counts.occluded, 0u);
  EXPECT_EQ(baked->counts.undefined, 0u);
  double se = 0;
  std::size_t count = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const std::size_t t = static_cast<std::size_t>(y) * n + x;
      if (!baked->baked[t]) continue;
      std::array<double, 4> ref{};
      for (int s = 0; s < spt; ++s) {
        const SampleOffset o = sample_offset(s, spt);
        const double u = (x + o.dx + 0.5) / n, v = 1 - (y + o.dy + 0.5) / n;
        const auto c = lookup(earth->pixels.data(), earth->width, earth->height, u, v, true);
        for (int k = 0; k < 3; ++k) ref[k] += c[k] / spt;
      }
      for (int k = 0; k < 3; ++k) {
        const double d = baked->atlas.pixels[t * 4 + k] - ref[k];
        se += d * d;
      }
      ++count;
    }
  }
  const double psnr = 10 * std::log10(1.0 / (se / (3.0 * count)));
  // The whole atlas but the pole fans' gaps (half of the first and last
  // band: 1/128 of the texels) is covered.
  EXPECT_GT(count, std::size_t(n * n * 0.99));
  EXPECT_GE(psnr, 40.0) << "covered texels " << count;
  std::printf("[ atlas PSNR vs directly resampled earth.jpg: %.2f dB over %zu texels ]\n", psnr,
              count);
}

// Seams: bilinear lookups through the mesh UVs at seeded random points of
// every triangle (a third of them within half a texel of an edge) read only
// baked texels (u wraps: the proxy layout is periodic) and match the direct
// projection of that 3D point within 1e-2.
TEST(AtlasBake, LookupsThroughMeshUvsNeverSeeUnbakedTexels) {
  const Image img = smooth_image(512, 256);
  const MeshData mesh = sphere_layout(32, 64);
  const int n = 128;
  auto baked = bake_atlas(mesh, img.view(), unit_sphere(), options(n, 4));
  ASSERT_TRUE(baked);
  const Proxy proxy = unit_sphere();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> unit(0, 1);
  double worst = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Float2 uv[3];
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      uv[k] = triangle_uv(mesh, t, k);
      const Float3 q = mesh.positions[mesh.triangles[t][k]];
      p[k] = {q.x, q.y, q.z};
    }
    for (int i = 0; i < 60; ++i) {
      double b1 = unit(rng), b2 = unit(rng);
      if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
      if (i % 3 == 0) b2 = std::min(b2, 0.5 / n * unit(rng));  // hug the edge 0-1
      const double b0 = 1 - b1 - b2;
      const double u = b0 * uv[0].u + b1 * uv[1].u + b2 * uv[2].u;
      const double v = b0 * uv[0].v + b1 * uv[1].v + b2 * uv[2].v;
      const double x = u * n - 0.5, y = (1 - v) * n - 0.5;
      const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
      for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
          const int tx = ((x0 + dx) % n + n) % n, ty = std::clamp(y0 + dy, 0, n - 1);
          ASSERT_TRUE(baked->baked[static_cast<std::size_t>(ty) * n + tx])
              << "triangle " << t << " uv " << u << "," << v;
        }
      }
      const auto got = lookup(baked->atlas.pixels.data(), n, n, u, v, true);
      const Vec3 P = b0 * p[0] + b1 * p[1] + b2 * p[2];
      const MapResult m = inverse_map(proxy, P);
      const auto want = lookup(img.pixels.data(), img.width, img.height, m.uv.u, m.uv.v, true);
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(got[k] - want[k]));
    }
  }
  // Tolerance: the atlas is the image box-filtered at 128 texels, and on
  // 64 x 32 flat triangles the linear UV interpolation departs from the
  // proxy's (u, v) of the same 3D point by a fraction of a texel; with the
  // image's gradient (at most 0.4 * 2 pi per unit u) that is a few 1e-3
  // (measured 3.3e-3). 1e-2 is 2.5 8-bit levels.
  EXPECT_LE(worst, 1e-2);
  std::printf("[ worst |atlas lookup - direct projection| = %.5f ]\n", worst);
}

TEST(AtlasBake, IndependentOfThreadCount) {
  const Image img = smooth_image(256, 128);
  const MeshData mesh = sphere_layout(12, 24);
  AtlasBakeOptions o = options(96, 3);
  o.padding = kPaddingInfinite;
  std::vector<float> one, two;
  {
    ThreadLimit limit(1);
    one = bake_atlas(mesh, img.view(), unit_sphere(), o).value().atlas.pixels;
  }
  {
    ThreadLimit limit(2);
    two = bake_atlas(mesh, img.view(), unit_sphere(), o).value().atlas.pixels;
  }
  EXPECT_EQ(one, two);
}

TEST(AtlasBake, TheVertexFiltersSettingsDoNotApply) {
  // The atlas looks each sample up bilinearly (or by EWA): the area
  // filter and its sample count are the vertex target's, so any value of
  // them gives the bilinear atlas, even a count the vertex target refuses.
  const Image img = smooth_image(256, 128);
  const MeshData mesh = sphere_layout(12, 24);
  AtlasBakeOptions bilinear = options(64, 4);
  bilinear.shading.filter = VertexFilter::kBilinear;
  Expected<AtlasBakeResult> want = bake_atlas(mesh, img.view(), unit_sphere(), bilinear);
  ASSERT_TRUE(want) << want.error().message;
  for (int samples : {0, 1, 16}) {
    AtlasBakeOptions area = bilinear;
    area.shading.filter = VertexFilter::kArea;
    area.shading.samples = samples;
    Expected<AtlasBakeResult> got = bake_atlas(mesh, img.view(), unit_sphere(), area);
    ASSERT_TRUE(got) << samples << ": " << got.error().message;
    EXPECT_EQ(got->atlas.pixels, want->atlas.pixels) << samples;
  }
}

// Plane proxy looking down +z onto square A (z = 0, x, y in [0, 1], UVs
// u = x / 2, v = y: the atlas's left half) under blocker B (z = 1,
// x in [0, 0.5], UVs in the right half). A's points with x < 0.5, i.e. atlas
// u < 0.25, are occluded. --occluded 1,0,0 paints them red exactly; the rest
// of A shows the (constant) image colour.
TEST(AtlasBake, OccludedSamplesFollowTheOccludedMode) {
  std::vector<Float3> pos = {{0, 0, 0},    {1, 0, 0}, {1, 1, 0},    {0, 0, 0},
                             {1, 1, 0},    {0, 1, 0}, {0, 0, 1},    {0.5f, 0, 1},
                             {0.5f, 1, 1}, {0, 0, 1}, {0.5f, 1, 1}, {0, 1, 1}};
  std::vector<Float2> uv;
  for (int i = 0; i < 6; ++i) uv.push_back({pos[i].x / 2, pos[i].y});
  for (int i = 6; i < 12; ++i) uv.push_back({0.5f + pos[i].x * 0.9f, pos[i].y});
  const MeshData mesh = test::make_triangle_soup(pos, uv);
  PlaneParams pp;
  pp.origin = {0, 0, 0};
  pp.u_axis = {1, 0, 0};
  pp.v_axis = {0, 1, 0};
  const Proxy plane = make_proxy(pp).value();
  Image img;
  img.width = img.height = 4;
  img.pixels.assign(64, 0.f);
  for (int i = 0; i < 16; ++i) img.pixels[i * 4 + 1] = 0.5f, img.pixels[i * 4 + 3] = 1;

  const int n = 64;
  AtlasBakeOptions o = options(n, 4);
  o.shading.occluded = OccludedMode::kColor;
  o.shading.occluded_color = {1, 0, 0, 1};
  auto red = bake_atlas(mesh, img.view(), plane, o);
  ASSERT_TRUE(red) << red.error().message;
  EXPECT_GT(red->counts.occluded, 0u);
  for (int y = 2; y < n - 2; ++y) {
    for (int x = 2; x < n / 2 - 2; ++x) {
      const float* px = &red->atlas.pixels[(static_cast<std::size_t>(y) * n + x) * 4];
      const double u = (x + 0.5) / n;
      if (u < 0.25 - 1.0 / n) {
        EXPECT_FLOAT_EQ(px[0], 1) << x << "," << y;
        EXPECT_FLOAT_EQ(px[1], 0);
      } else if (u > 0.25 + 1.0 / n) {
        EXPECT_FLOAT_EQ(px[0], 0) << x << "," << y;
        EXPECT_FLOAT_EQ(px[1], 0.5f);
      }
    }
  }
  // Occluded samples: A's x < 0.5 half (a quarter of A's and B's texels'
  // samples are not, so compare with the texel count of the region).
  // --occluded fill: the inpainted colour of a constant image is that colour.
  o.shading.occluded = OccludedMode::kFill;
  auto fill = bake_atlas(mesh, img.view(), plane, o);
  ASSERT_TRUE(fill);
  for (std::size_t t = 0; t < fill->baked.size(); ++t) {
    if (!fill->baked[t]) continue;
    EXPECT_NEAR(fill->atlas.pixels[t * 4 + 1], 0.5f, 1e-5);
    EXPECT_NEAR(fill->atlas.pixels[t * 4 + 0], 0.0f, 1e-5);
  }
}

// One triangle in the middle of a 64 x 64 atlas under the default plane.
struct PaddingScene {
  Image img = smooth_image(64, 32);
  MeshData mesh = test::make_triangle_soup({{0, 0, 1}, {1, 0, 1}, {0, 1, 1}},
                                           {{0.3f, 0.3f}, {0.6f, 0.3f}, {0.3f, 0.6f}});
  Proxy plane = make_proxy(PlaneParams{}).value();
  AtlasBakeResult bake(int padding) const {
    AtlasBakeOptions o = options(64, 1);
    o.padding = padding;
    return bake_atlas(mesh, img.view(), plane, o).value();
  }
};

TEST(AtlasBake, PaddingFillsTheGutterAndBakedTexelsStay) {
  const PaddingScene scene;
  auto none = scene.bake(0);
  auto three = scene.bake(3);
  auto inf = scene.bake(kPaddingInfinite);
  std::size_t covered = 0;
  for (std::size_t t = 0; t < none.baked.size(); ++t) {
    covered += none.baked[t];
    if (none.baked[t]) {
      for (int c = 0; c < 4; ++c) {
        EXPECT_EQ(three.atlas.pixels[t * 4 + c], none.atlas.pixels[t * 4 + c]);
        EXPECT_EQ(inf.atlas.pixels[t * 4 + c], none.atlas.pixels[t * 4 + c]);
      }
    } else {
      EXPECT_EQ(none.atlas.pixels[t * 4 + 3], 0);  // transparent background
      EXPECT_EQ(inf.atlas.pixels[t * 4 + 3], 1);   // push-pull: everything opaque
    }
  }
  EXPECT_EQ(none.counts.padded, 0u);
  EXPECT_GT(three.counts.padded, 0u);
  EXPECT_EQ(inf.counts.padded, none.baked.size() - covered);
}

// The default padding (issue #11 item 4): covered texels as without
// padding, the default_padding(size) rings as an explicit --padding of that
// many (all four channels), every other texel alpha 0 with a colour inside
// the range of the covered ones (push-pull of chart colours, never black).
TEST(AtlasBake, DefaultPaddingIsRingsThenTransparentPushPull) {
  const PaddingScene scene;
  auto none = scene.bake(0);
  auto rings = scene.bake(default_padding(64));
  auto def = scene.bake(kPaddingDefault);
  float lo[3] = {2, 2, 2}, hi[3] = {-1, -1, -1};
  for (std::size_t t = 0; t < none.baked.size(); ++t) {
    if (!none.baked[t]) continue;
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], none.atlas.pixels[t * 4 + c]);
      hi[c] = std::max(hi[c], none.atlas.pixels[t * 4 + c]);
    }
  }
  std::size_t ring_texels = 0;
  for (std::size_t t = 0; t < none.baked.size(); ++t) {
    const bool ring = !none.baked[t] && rings.atlas.pixels[t * 4 + 3] > 0;
    ring_texels += ring;
    for (int c = 0; c < 4; ++c) {
      const float v = def.atlas.pixels[t * 4 + c];
      if (none.baked[t]) {
        EXPECT_EQ(v, none.atlas.pixels[t * 4 + c]) << t;
      } else if (ring) {
        EXPECT_EQ(v, rings.atlas.pixels[t * 4 + c]) << t;
      } else if (c == 3) {
        EXPECT_EQ(v, 0.f) << t;
      } else {
        EXPECT_GE(v, lo[c]) << t;
        EXPECT_LE(v, hi[c]) << t;
      }
    }
  }
  EXPECT_GT(ring_texels, 0u);
  EXPECT_EQ(rings.counts.padded, ring_texels);
  EXPECT_EQ(def.counts.padded, none.baked.size() - none.counts.texels);  // every other texel
}

TEST(AtlasBake, BadInputIsRejected) {
  const Image img = smooth_image(8, 4);
  const MeshData mesh = sphere_layout(4, 8);
  for (int size : {0, kMaxAtlasSize + 1}) {
    auto r = bake_atlas(mesh, img.view(), unit_sphere(), options(size, 4));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  }
  AtlasBakeOptions o = options(16, 4);
  o.padding = -5;
  auto r = bake_atlas(mesh, img.view(), unit_sphere(), o);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("--padding"), std::string::npos);
  MeshData no_uv = test::make_uv_sphere(4, 8, 0);
  r = bake_atlas(no_uv, img.view(), unit_sphere(), options(16, 4));
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("no UV"), std::string::npos);
}

}  // namespace
}  // namespace texbake

namespace texbake {
namespace {

// --filter ewa's footprint on the atlas, read off the MIP level it lands
// on: a unit square under a plane proxy with atlas UV = proxy UV, so an
// atlas texel of a 64 atlas covers 1024 / 64 = 16 image texels a side of a
// 1024 x 1024 image, whose given MIP levels (ImageView::mip_levels, as a
// MIP-mapped file's) are constants: level L has red L / 16. A lookup whose
// ellipse has semi-axes s texels reads lod = log2(s), the blend of levels
// floor(lod) and the next with weight frac(lod), so red = lod / 16.
// By hand (README, Footprint filtering): one sample per texel, semi-axes
// 0.85 x 16 / sqrt(2) = 9.617 texels, lod 3.266; four samples, cells of
// 8 texels, semi-axes 8 / sqrt(2) = 5.657, lod 2.5.
TEST(AtlasBake, EwaFootprintIsTheSupersampleCellsEllipse) {
  std::vector<Float3> pos = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<Float2> uv;
  for (const Float3& p : pos) uv.push_back({p.x, p.y});
  const MeshData mesh = test::make_triangle_soup(pos, uv);
  const Proxy plane = make_proxy(PlaneParams{}).value();
  std::vector<std::vector<float>> levels;
  for (int l = 0, w = 1024; w >= 1; ++l, w /= 2) {
    std::vector<float> texels(static_cast<std::size_t>(w) * w * 4);
    for (std::size_t i = 0; i < texels.size(); i += 4) {
      texels[i] = static_cast<float>(l) / 16;
      texels[i + 3] = 1;
    }
    levels.push_back(std::move(texels));
  }
  std::vector<ImageView> views;
  for (std::size_t l = 1; l < levels.size(); ++l) {
    const int w = 1024 >> l;
    views.push_back(ImageView{w, w, levels[l].data(), ColorSpace::kSrgb});
  }
  ImageView image{1024, 1024, levels[0].data(), ColorSpace::kSrgb};
  image.mip_levels = views.data();
  image.mip_level_count = static_cast<int>(views.size());
  for (const auto& [samples, semi_axis] :
       {std::pair{1, 0.85 * 16 / std::sqrt(2.0)}, std::pair{4, 8 / std::sqrt(2.0)}}) {
    SCOPED_TRACE(samples);
    AtlasBakeOptions o = options(64, samples);
    o.padding = 0;
    o.shading.visibility = Visibility::kAll;
    o.shading.filter = VertexFilter::kEwa;
    auto r = bake_atlas(mesh, image, plane, o);
    ASSERT_TRUE(r) << r.error().message;
    const double red = std::log2(semi_axis) / 16;
    for (std::size_t t = 0; t < 64 * 64; ++t) {
      ASSERT_TRUE(r->baked[t]) << t;
      ASSERT_NEAR(r->atlas.pixels[t * 4], red, 1e-6) << t;
    }
  }
}

}  // namespace
}  // namespace texbake
