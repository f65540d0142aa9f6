// The streamed atlas bake (bands of rows rasterised and baked one at a time,
// the fill computed up front or deferred) against a whole-atlas reference
// written here: every sample of rasterize_atlas at once, visibility of all
// of them in one compute_visibility call, texel means in double. And the
// frontier dilation against the textbook full-image passes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bake/atlas/atlas_raster.h"
#include "bake/atlas/dilate.h"
#include "bake/engine/bake_atlas.h"
#include "bake/engine/bake_vertex.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "mapping/sample.h"
#include "tests/bake/atlas/atlas_test_util.h"

namespace texbake {
namespace {

struct Reference {
  std::vector<float> pixels;
  std::vector<uint8_t> baked;
  std::size_t occluded = 0, undefined = 0;
};

// The unbanded reference of bake_atlas (padding 0, sRGB working encoding).
Reference reference_atlas(const MeshData& mesh, const ImageView& image, const Proxy& proxy,
                          const AtlasBakeOptions& o) {
  const AtlasRaster raster = rasterize_atlas(mesh, {o.size, o.samples}).value();
  const std::size_t count = raster.sample_count();
  std::vector<Vec3> points(count), dirs(count);
  std::vector<MapResult> maps(count);
  for (std::size_t s = 0; s < count; ++s) {
    const auto& tri = mesh.triangles[raster.sample_triangle[s]];
    const double b1 = raster.sample_b1[s], b2 = raster.sample_b2[s], b0 = 1.0 - b1 - b2;
    const Float3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    points[s] = {b0 * a.x + b1 * b.x + b2 * c.x, b0 * a.y + b1 * b.y + b2 * c.y,
                 b0 * a.z + b1 * b.z + b2 * c.z};
    maps[s] = inverse_map(proxy, points[s]);
    dirs[s] = maps[s].status == MapStatus::kUndefined ? Vec3{0, 0, 1} : maps[s].to_projector;
  }
  std::vector<uint8_t> visible(count, 1);
  if (o.shading.visibility == Visibility::kFirst) {
    const EmbreeScene scene = EmbreeScene::build(mesh, BuildQuality::kLow).value();
    visible = compute_visibility(scene, points, dirs);
  }
  VertexBakeOptions vo = o.shading;
  vo.filter = VertexFilter::kBilinear;
  vo.occluded = OccludedMode::kFill;
  const std::vector<Rgba> fill = bake_vertex(mesh, image, proxy, vo).value().colors;

  const std::size_t spt = raster.samples_per_texel;
  const int n = o.size;
  Reference ref;
  ref.pixels.assign(static_cast<std::size_t>(n) * n * 4, 0.f);
  ref.baked.assign(static_cast<std::size_t>(n) * n, 0);
  const OccludedMode mode = o.shading.occluded;
  for (std::size_t k = 0; k < raster.texels.size(); ++k) {
    double acc[4] = {0, 0, 0, 0};
    std::vector<std::size_t> to_fill;
    for (std::size_t s = k * spt; s < (k + 1) * spt; ++s) {
      Rgba c;
      if (maps[s].status == MapStatus::kUndefined) {
        ++ref.undefined;
        if (mode != OccludedMode::kColor) {
          to_fill.push_back(s);
          continue;
        }
        c = o.shading.occluded_color;
      } else if (!visible[s]) {
        ++ref.occluded;
        if (mode == OccludedMode::kFill) {
          to_fill.push_back(s);
          continue;
        }
        c = mode == OccludedMode::kColor
                ? o.shading.occluded_color
                : sample_bilinear(image, maps[s].uv, wrap_u(proxy), wrap_v(proxy));
      } else {
        c = sample_bilinear(image, maps[s].uv, wrap_u(proxy), wrap_v(proxy));
      }
      for (int ch = 0; ch < 4; ++ch) acc[ch] += c[ch];
    }
    for (std::size_t s : to_fill) {
      const auto& tri = mesh.triangles[raster.sample_triangle[s]];
      const double b1 = raster.sample_b1[s], b2 = raster.sample_b2[s], b0 = 1 - b1 - b2;
      for (int ch = 0; ch < 4; ++ch) {
        acc[ch] += b0 * fill[tri[0]][ch] + b1 * fill[tri[1]][ch] + b2 * fill[tri[2]][ch];
      }
    }
    const std::size_t t = raster.texels[k];
    for (int ch = 0; ch < 4; ++ch) ref.pixels[t * 4 + ch] = static_cast<float>(acc[ch] / spt);
    ref.baked[t] = 1;
  }
  return ref;
}

// A smooth, non-constant RGBA image.
Image gradient_image(int w, int h) {
  Image img;
  img.width = w;
  img.height = h;
  img.pixels.resize(static_cast<std::size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float* p = &img.pixels[(static_cast<std::size_t>(y) * w + x) * 4];
      p[0] = static_cast<float>(x) / (w - 1);
      p[1] = static_cast<float>(y) / (h - 1);
      p[2] = static_cast<float>(0.5 + 0.5 * std::sin(0.7 * x + 0.3 * y));
      p[3] = 1;
    }
  }
  return img;
}

// Square A (z = 0) under blocker B (z = 1, x < 0.5), UVs side by side, plane
// proxy looking down z (as in atlas_bake_test.cpp): occluded samples on A.
MeshData occlusion_scene() {
  std::vector<Float3> pos = {{0, 0, 0},    {1, 0, 0}, {1, 1, 0},    {0, 0, 0},
                             {1, 1, 0},    {0, 1, 0}, {0, 0, 1},    {0.5f, 0, 1},
                             {0.5f, 1, 1}, {0, 0, 1}, {0.5f, 1, 1}, {0, 1, 1}};
  std::vector<Float2> uv;
  for (int i = 0; i < 6; ++i) uv.push_back({0.02f + pos[i].x * 0.45f, 0.03f + pos[i].y * 0.9f});
  for (int i = 6; i < 12; ++i) uv.push_back({0.52f + pos[i].x * 0.9f, 0.05f + pos[i].y * 0.9f});
  return test::make_triangle_soup(pos, uv);
}

Proxy plane_proxy() {
  PlaneParams pp;
  pp.origin = {-0.1, -0.2, 0};
  pp.u_axis = {1.3, 0, 0};
  pp.v_axis = {0, 1.4, 0};
  return make_proxy(pp).value();
}

void expect_matches_reference(const MeshData& mesh, const Image& img, const Proxy& proxy,
                              AtlasBakeOptions o, const std::string& what) {
  o.padding = 0;
  const Reference ref = reference_atlas(mesh, img.view(), proxy, o);
  for (int threads : {1, 2}) {
    ThreadLimit limit(threads);
    auto baked = bake_atlas(mesh, img.view(), proxy, o);
    ASSERT_TRUE(baked) << baked.error().message;
    EXPECT_EQ(baked->baked, ref.baked) << what;
    EXPECT_EQ(baked->counts.occluded, ref.occluded) << what;
    EXPECT_EQ(baked->counts.undefined, ref.undefined) << what;
    ASSERT_EQ(baked->atlas.pixels.size(), ref.pixels.size());
    std::size_t bad = 0;
    for (std::size_t i = 0; i < ref.pixels.size(); ++i) {
      // Same formulas in the same order: equal up to the compiler's freedom
      // in contracting the point interpolation (far below 1e-6).
      if (std::abs(baked->atlas.pixels[i] - ref.pixels[i]) > 1e-6f) ++bad;
    }
    EXPECT_EQ(bad, 0u) << what << " threads " << threads;
  }
}

// 64 texels = 4 bands of 16 rows; 96 = 6; 40: a short last band.
TEST(AtlasStream, BandedBakeEqualsWholeAtlasReferenceWithOcclusion) {
  const MeshData mesh = occlusion_scene();
  const Image img = gradient_image(16, 12);
  const Proxy proxy = plane_proxy();
  for (int size : {40, 64, 96}) {
    for (int samples : {1, 4, 5}) {
      for (OccludedMode mode :
           {OccludedMode::kFill, OccludedMode::kColor, OccludedMode::kProject}) {
        AtlasBakeOptions o;
        o.size = size;
        o.samples = samples;
        o.shading.occluded = mode;
        o.shading.occluded_color = {1, 0, 0.25f, 1};
        expect_matches_reference(mesh, img, proxy, o,
                                 "size " + std::to_string(size) + " samples " +
                                     std::to_string(samples) + " mode " +
                                     std::to_string(static_cast<int>(mode)));
      }
    }
  }
}

// A flat square whose corners sit on texel centres, under a sphere proxy
// centred on its first corner: the sample of that corner's texel lands
// exactly on the centre and has no mapping (undefined), and so do the border
// samples clamped onto the corner. --occluded project
// and --visibility all take the deferred fill path, visibility with fill the
// up-front one; all must equal the reference.
TEST(AtlasStream, UndefinedSamplesAreFilledLikeTheReference) {
  const int n = 64;
  const float lo = 4.5f / n, hi = 59.5f / n;  // texel centres 4 and 59 (exact in binary)
  const MeshData mesh =
      test::make_flat_uv_soup({{lo, lo}, {hi, lo}, {hi, hi}, {lo, lo}, {hi, hi}, {lo, hi}});
  SphereParams sp;
  sp.center = {lo, lo, 0};
  sp.radius = 2;
  sp.pole = {0, 0, 1};
  sp.equator = Vec3{1, 0, 0};
  const Proxy sphere = make_proxy(sp).value();
  const Image img = gradient_image(32, 16);
  struct Case {
    OccludedMode mode;
    Visibility visibility;
  };
  for (Case c : {Case{OccludedMode::kProject, Visibility::kFirst},
                 Case{OccludedMode::kFill, Visibility::kAll},
                 Case{OccludedMode::kFill, Visibility::kFirst}}) {
    AtlasBakeOptions o;
    o.size = n;
    o.samples = 1;
    o.shading.occluded = c.mode;
    o.shading.visibility = c.visibility;
    const std::string what = "mode " + std::to_string(static_cast<int>(c.mode));
    auto baked = bake_atlas(mesh, img.view(), sphere, o);
    ASSERT_TRUE(baked) << baked.error().message;
    // The corner's texel (4, 59) and the three border texels beyond the
    // corner, (3, 59), (3, 60) and (4, 60), whose samples clamp onto it.
    EXPECT_EQ(baked->counts.undefined, 4u) << what;
    expect_matches_reference(mesh, img, sphere, o, what);
  }
}

// The textbook dilation: `texels` passes over the whole image.
std::size_t dilate_full_passes(std::vector<float>& rgba, std::vector<uint8_t>& baked, int w, int h,
                               int texels) {
  std::size_t filled = 0;
  for (int pass = 0; pass < texels; ++pass) {
    std::vector<uint8_t> fresh(baked.size(), 0);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        if (baked[i]) continue;
        float sum[4] = {0, 0, 0, 0};
        int k = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
            const std::size_t j = static_cast<std::size_t>(yy) * w + xx;
            if (!baked[j]) continue;
            for (int c = 0; c < 4; ++c) sum[c] += rgba[j * 4 + c];
            ++k;
          }
        }
        if (k == 0) continue;
        for (int c = 0; c < 4; ++c) rgba[i * 4 + c] = sum[c] / k;
        fresh[i] = 1;
      }
    }
    for (std::size_t i = 0; i < baked.size(); ++i) {
      if (fresh[i]) baked[i] = 1, ++filled;
    }
  }
  return filled;
}

TEST(AtlasStream, FrontierDilationEqualsFullImagePasses) {
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 24; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 70), h = 1 + static_cast<int>(rng() % 50);
    const double density = (trial % 4) * 0.02 + (trial == 5 ? 1.0 : 0.0);
    const int texels = static_cast<int>(rng() % 12);
    std::vector<float> rgba(static_cast<std::size_t>(w) * h * 4, -3.f);
    std::vector<uint8_t> baked(static_cast<std::size_t>(w) * h, 0);
    std::uniform_real_distribution<float> value(0, 1);
    for (std::size_t i = 0; i < baked.size(); ++i) {
      if (std::uniform_real_distribution<double>(0, 1)(rng) < density) {
        baked[i] = 1;
        for (int c = 0; c < 4; ++c) rgba[i * 4 + c] = value(rng);
      }
    }
    std::vector<float> ref_rgba = rgba;
    std::vector<uint8_t> ref_baked = baked;
    const std::size_t ref_filled = dilate_full_passes(ref_rgba, ref_baked, w, h, texels);
    for (int threads : {1, 2}) {
      ThreadLimit limit(threads);
      std::vector<float> got_rgba = rgba;
      std::vector<uint8_t> got_baked = baked;
      EXPECT_EQ(dilate(got_rgba, got_baked, w, h, texels), ref_filled) << trial;
      EXPECT_EQ(got_baked, ref_baked) << trial;
      EXPECT_EQ(got_rgba, ref_rgba) << trial;
    }
  }
}

}  // namespace
}  // namespace texbake
