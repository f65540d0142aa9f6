// The per-vertex target (SPEC section 4) on meshes built from each proxy's
// forward map, with expected colours computed independently: an image that is
// an analytic function of pixel position, the test's own bilinear sampler, and
// a dense quadrature of the vertex's share of its triangles.
#include "bake/engine/bake_vertex.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "bake/util/parallel.h"
#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

// ---- Images. --------------------------------------------------------------

struct TestImage {
  int width = 0, height = 0;
  std::vector<float> pixels;
  ImageView view() const { return {width, height, pixels.data()}; }
};

template <class F>
TestImage make_image(int w, int h, F texel) {
  TestImage img{w, h, std::vector<float>(static_cast<std::size_t>(w) * h * 4)};
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const Rgba c = texel(x, y);
      for (int k = 0; k < 4; ++k) img.pixels[(static_cast<std::size_t>(y) * w + x) * 4 + k] = c[k];
    }
  }
  return img;
}

// R = (x + 0.5) / W, G = (y + 0.5) / H: bilinear interpolation reproduces it
// exactly, so at (u, v) (SPEC section 1: x = uW - 0.5, y = (1 - v)H - 0.5)
// the colour is R = u, G = 1 - v wherever u, v stay half a texel inside.
TestImage ramp_image(int w = 64, int h = 32) {
  return make_image(w, h, [&](int x, int y) {
    return Rgba{(x + 0.5f) / w, (y + 0.5f) / h, 0.25f, 1.0f};
  });
}

// Detail finer than the test meshes, so the area filter visibly averages.
TestImage stripe_image(int w = 64, int h = 32) {
  const double two_pi = 2 * std::numbers::pi;
  return make_image(w, h, [&](int x, int y) {
    return Rgba{static_cast<float>(0.5 + 0.4 * std::sin(two_pi * x / 8)),
                static_cast<float>(0.5 + 0.4 * std::cos(two_pi * y / 6)),
                static_cast<float>(0.3 + 0.2 * std::sin(two_pi * (x + y) / 10)), 1.0f};
  });
}

// The test's own bilinear sampler, written from SPEC section 1.
Rgba reference_bilinear(const TestImage& img, double u, double v, bool repeat_u) {
  const double x = u * img.width - 0.5, y = (1 - v) * img.height - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  auto fold_x = [&](double i) {
    if (repeat_u) return static_cast<int>(i - img.width * std::floor(i / img.width));
    return static_cast<int>(std::clamp(i, 0.0, img.width - 1.0));
  };
  auto fold_y = [&](double i) { return static_cast<int>(std::clamp(i, 0.0, img.height - 1.0)); };
  const int xs[2] = {fold_x(x0), fold_x(x0 + 1)}, ys[2] = {fold_y(y0), fold_y(y0 + 1)};
  const double wx[2] = {1 - (x - x0), x - x0}, wy[2] = {1 - (y - y0), y - y0};
  Rgba out{0, 0, 0, 0};
  for (int k = 0; k < 4; ++k) {
    double sum = 0;
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) {
        sum += wx[i] * wy[j] *
               img.pixels[(static_cast<std::size_t>(ys[j]) * img.width + xs[i]) * 4 + k];
      }
    }
    out[k] = static_cast<float>(sum);
  }
  return out;
}

// ---- Proxies and meshes on them. -------------------------------------------

struct ProxyCase {
  std::string name;
  ProxyParams params;
  bool repeat_u;  // SPEC section 1: sphere, cylinder, cone, disk wrap u
};

std::vector<ProxyCase> proxy_cases() {
  return {
      {"sphere", SphereParams{{0, 0, 0}, 2.0, {0, 0, 1}, Vec3{1, 0, 0}}, true},
      {"cylinder", CylinderParams{{0, 0, -1}, {0, 0, 1}, Vec3{1, 0, 0}, 1.5, 3.0}, true},
      {"cone", ConeParams{{0, 0, 2}, {0, 0, 1}, Vec3{1, 0, 0}, 2.0, 1.0}, true},
      {"disk", DiskParams{{0, 0, 0}, {0, 0, 1}, Vec3{1, 0, 0}, 2.0}, true},
      {"quad", QuadParams{{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{2.2, 1.5, 0}, Vec3{-0.1, 1.4, 0}}},
       false},
      {"plane", PlaneParams{{0, 0, 0}, {2, 0, 0}, {0, 1, 0}}, false},
  };
}

// A cells x cells grid over (u, v) in [lo, hi]^2, each vertex placed on the
// proxy by its forward map; uv[v] records the (u, v) each vertex was built from.
struct ProxyMesh {
  MeshData mesh;
  std::vector<UV> uv;
};

ProxyMesh mesh_on(const Proxy& proxy, int cells, double lo = 0.1, double hi = 0.9) {
  ProxyMesh pm;
  test::append_grid(pm.mesh, cells, cells, [&](double s, double t) {
    const UV uv{lo + (hi - lo) * s, lo + (hi - lo) * t};
    pm.uv.push_back(uv);
    const Vec3 p = forward_map(proxy, uv);
    return Float3{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  });
  test::faces_from_triangles(pm.mesh);
  return pm;
}

Vec3 vec(const Float3& p) {
  return {p.x, p.y, p.z};
}

// The mean colour over vertex v's share of its triangles (the barycentric
// region where v's weight is the largest: the quad v, edge midpoints,
// centroid), by the midpoint rule on n^2 equal sub-triangles per triangle.
Rgba area_average(const MeshData& mesh, uint32_t v, const Proxy& proxy, const TestImage& img,
                  bool repeat_u, int n = 48) {
  double sum[4] = {0, 0, 0, 0}, weight = 0;
  for (const auto& tri : mesh.triangles) {
    const int at = tri[0] == v ? 0 : tri[1] == v ? 1 : tri[2] == v ? 2 : -1;
    if (at < 0) continue;
    const Vec3 a = vec(mesh.positions[v]), b = vec(mesh.positions[tri[(at + 1) % 3]]),
               c = vec(mesh.positions[tri[(at + 2) % 3]]);
    const double w = 0.5 * length(cross(b - a, c - a)) / (n * n);
    auto add = [&](double bb, double bc) {
      const double ba = 1 - bb - bc;
      if (ba < bb || ba < bc) return;
      const MapResult m = inverse_map(proxy, a * ba + b * bb + c * bc);
      const Rgba col = reference_bilinear(img, m.uv.u, m.uv.v, repeat_u);
      for (int k = 0; k < 4; ++k) sum[k] += w * col[k];
      weight += w;
    };
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        add((i + 1.0 / 3) / n, (j + 1.0 / 3) / n);
        if (i + j < n - 1) add((i + 2.0 / 3) / n, (j + 2.0 / 3) / n);
      }
    }
  }
  Rgba out;
  for (int k = 0; k < 4; ++k) out[k] = static_cast<float>(sum[k] / weight);
  return out;
}

VertexBakeOptions bilinear_options() {
  VertexBakeOptions o;
  o.filter = VertexFilter::kBilinear;
  return o;
}

// ---- Filters on every proxy. ------------------------------------------------

TEST(BakeVertex, BilinearOnEveryProxyGivesTheAnalyticColour) {
  const TestImage img = ramp_image();
  for (const ProxyCase& pc : proxy_cases()) {
    SCOPED_TRACE(pc.name);
    Expected<Proxy> proxy = make_proxy(pc.params);
    ASSERT_TRUE(proxy) << proxy.error().message;
    const ProxyMesh pm = mesh_on(*proxy, 8);
    Expected<VertexBakeResult> r = bake_vertex(pm.mesh, img.view(), *proxy, bilinear_options());
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->colors.size(), pm.mesh.positions.size());
    // Convex patches seen from outside: nothing shadows itself.
    EXPECT_EQ(r->counts.occluded, 0u);
    EXPECT_EQ(r->counts.outside, 0u);
    EXPECT_EQ(r->counts.samples, pm.mesh.positions.size());
    for (std::size_t v = 0; v < r->colors.size(); ++v) {
      EXPECT_NEAR(r->colors[v][0], pm.uv[v].u, 2e-5) << "vertex " << v;
      EXPECT_NEAR(r->colors[v][1], 1 - pm.uv[v].v, 2e-5) << "vertex " << v;
      EXPECT_FLOAT_EQ(r->colors[v][2], 0.25f);
      EXPECT_FLOAT_EQ(r->colors[v][3], 1.0f);
    }
  }
}

TEST(BakeVertex, AreaFilterConvergesToTheAreaAverageOnEveryProxy) {
  const TestImage img = stripe_image();
  for (const ProxyCase& pc : proxy_cases()) {
    SCOPED_TRACE(pc.name);
    Expected<Proxy> proxy = make_proxy(pc.params);
    ASSERT_TRUE(proxy);
    const ProxyMesh pm = mesh_on(*proxy, 6);
    VertexBakeOptions options;  // area filter by default
    options.samples = 1024;
    Expected<VertexBakeResult> area = bake_vertex(pm.mesh, img.view(), *proxy, options);
    ASSERT_TRUE(area);
    Expected<VertexBakeResult> point = bake_vertex(pm.mesh, img.view(), *proxy, bilinear_options());
    ASSERT_TRUE(point);
    EXPECT_EQ(area->counts.samples, 1024 * pm.mesh.positions.size());
    double largest_filter_effect = 0;
    for (uint32_t v = 0; v < pm.mesh.positions.size(); ++v) {
      const Rgba want = area_average(pm.mesh, v, *proxy, img, pc.repeat_u);
      for (int k = 0; k < 3; ++k) {
        // 1024 stratified samples vs the quadrature: both within ~1e-3.
        EXPECT_NEAR(area->colors[v][k], want[k], 4e-3) << "vertex " << v << " channel " << k;
        largest_filter_effect =
            std::max(largest_filter_effect, std::abs(double(point->colors[v][k]) - want[k]));
      }
    }
    // The average really differs from the point sample on this image.
    EXPECT_GT(largest_filter_effect, 0.05);
  }
}

TEST(BakeVertex, AreaFilterWithDefaultSamplesIsCloseToTheAreaAverage) {
  const TestImage img = stripe_image();
  Expected<Proxy> proxy = make_proxy(SphereParams{{0, 0, 0}, 2.0, {0, 0, 1}, Vec3{1, 0, 0}});
  ASSERT_TRUE(proxy);
  const ProxyMesh pm = mesh_on(*proxy, 6);
  Expected<VertexBakeResult> r = bake_vertex(pm.mesh, img.view(), *proxy, VertexBakeOptions{});
  Expected<VertexBakeResult> point = bake_vertex(pm.mesh, img.view(), *proxy, bilinear_options());
  ASSERT_TRUE(r);
  ASSERT_TRUE(point);
  EXPECT_EQ(r->counts.samples, 16 * pm.mesh.positions.size());
  double area_error = 0, point_error = 0;
  for (uint32_t v = 0; v < pm.mesh.positions.size(); ++v) {
    const Rgba want = area_average(pm.mesh, v, *proxy, img, true);
    for (int k = 0; k < 3; ++k) {
      area_error += std::abs(double(r->colors[v][k]) - want[k]);
      point_error += std::abs(double(point->colors[v][k]) - want[k]);
    }
  }
  const double n = 3.0 * pm.mesh.positions.size();
  // Stripes of amplitude 0.4 with about two periods across a vertex's share:
  // 16 stratified samples (measured mean error 0.020) are far closer to the
  // true average than one sample at the vertex (measured 0.17).
  EXPECT_LT(area_error / n, 0.03);
  EXPECT_LT(area_error, 0.5 * point_error);
}

// A hand-checked case: a 2 x 2 image on a plane over [0,1]^2, one vertex at
// the centre (u, v) = (0.5, 0.5), i.e. pixel position (0.5, 0.5): the mean of
// the four texels.
TEST(BakeVertex, BilinearAtTheCentreOfA2x2ImageIsTheMeanOfItsTexels) {
  TestImage img{2,
                2,
                {0.0f, 0.2f, 1.0f, 1.0f, /**/ 1.0f, 0.6f, 0.0f, 1.0f,  //
                 0.4f, 0.2f, 0.2f, 0.5f, /**/ 0.2f, 0.0f, 0.6f, 0.5f}};
  Expected<Proxy> proxy = make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  ASSERT_TRUE(proxy);
  MeshData mesh;
  mesh.positions = {{0.5f, 0.5f, 0}, {0.9f, 0.5f, 0}, {0.5f, 0.9f, 0}};
  mesh.triangles = {{0, 1, 2}};
  test::faces_from_triangles(mesh);
  Expected<VertexBakeResult> r = bake_vertex(mesh, img.view(), *proxy, bilinear_options());
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->colors[0][0], 0.4f, 1e-6);
  EXPECT_NEAR(r->colors[0][1], 0.25f, 1e-6);
  EXPECT_NEAR(r->colors[0][2], 0.45f, 1e-6);
  EXPECT_NEAR(r->colors[0][3], 0.75f, 1e-6);
  // (0.9, 0.5): x = 1.3 -> clamped to column 1; y = 0.5: mean of its two texels.
  EXPECT_NEAR(r->colors[1][0], 0.6f, 1e-6);
  EXPECT_NEAR(r->colors[1][1], 0.3f, 1e-6);
}

// ---- Occlusion (SPEC section 3). -------------------------------------------

// A 20 x 20 cell grid on z = 0 over [0,1]^2, a box floating over it, and a
// plane projector looking down (d = +z): exactly the 25 grid vertices strictly
// inside the box's footprint are shadowed (tests/bake/visibility_test.cpp).
struct ShadowScene {
  static constexpr int kCells = 20;
  MeshData mesh;
  uint32_t box_first = 0;
  Proxy proxy = *make_proxy(PlaneParams{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}});
  ShadowScene() {
    test::append_grid(mesh, kCells, kCells, [](double s, double t) {
      return Float3{static_cast<float>(s), static_cast<float>(t), 0};
    });
    box_first = test::append_box(mesh, {0.32f, 0.22f, 0.3f}, {0.58f, 0.48f, 0.5f});
    test::faces_from_triangles(mesh);
  }
  static bool in_shadow(int i, int j) {
    const double x = i * 0.05, y = j * 0.05;
    return x > 0.32 && x < 0.58 && y > 0.22 && y < 0.48;
  }
  static uint32_t id(int i, int j) { return static_cast<uint32_t>(j * (kCells + 1) + i); }
};

TEST(BakeVertex, FillGivesShadowedVerticesTheSmoothExtensionOfTheirVisibleNeighbours) {
  ShadowScene s;
  const TestImage img = ramp_image(256, 256);
  Expected<VertexBakeResult> r = bake_vertex(s.mesh, img.view(), s.proxy, bilinear_options());
  ASSERT_TRUE(r) << r.error().message;
  // 25 grid vertices, plus the box's bottom face whose corners graze its sides.
  EXPECT_GE(r->counts.occluded, 25u);
  EXPECT_LE(r->counts.occluded, 29u);
  EXPECT_EQ(r->counts.unfilled, 0u);
  EXPECT_EQ(r->counts.filled, r->counts.occluded);
  float lo_r = 1, hi_r = 0, lo_g = 1, hi_g = 0;  // visible vertices bordering the shadow
  for (int j = 0; j <= ShadowScene::kCells; ++j) {
    for (int i = 0; i <= ShadowScene::kCells; ++i) {
      if (ShadowScene::in_shadow(i, j)) continue;
      bool borders = false;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) borders |= ShadowScene::in_shadow(i + di, j + dj);
      }
      if (!borders) continue;
      const Rgba& c = r->colors[ShadowScene::id(i, j)];
      lo_r = std::min(lo_r, c[0]), hi_r = std::max(hi_r, c[0]);
      lo_g = std::min(lo_g, c[1]), hi_g = std::max(hi_g, c[1]);
    }
  }
  for (int j = 0; j <= ShadowScene::kCells; ++j) {
    for (int i = 0; i <= ShadowScene::kCells; ++i) {
      const Rgba& c = r->colors[ShadowScene::id(i, j)];
      // The ramp is linear in (x, y), and linear functions are harmonic on
      // this grid: shadowed vertices get exactly the projected ramp back.
      EXPECT_NEAR(c[0], std::clamp(i * 0.05, 0.5 / 256, 1 - 0.5 / 256), 1e-5) << i << "," << j;
      EXPECT_NEAR(c[1], std::clamp(1 - j * 0.05, 0.5 / 256, 1 - 0.5 / 256), 1e-5) << i << "," << j;
      if (ShadowScene::in_shadow(i, j)) {
        EXPECT_GE(c[0], lo_r);
        EXPECT_LE(c[0], hi_r);
        EXPECT_GE(c[1], lo_g);
        EXPECT_LE(c[1], hi_g);
      }
    }
  }
}

TEST(BakeVertex, FillIsSmoothWhereTheProjectionIsNot) {
  // A checkerboard image: the projected colours under the box jump, the
  // filled ones must not: every shadowed vertex is within the range of the
  // visible vertices around the shadow and is the mean of its neighbours.
  ShadowScene s;
  const TestImage img = make_image(13, 13, [](int x, int y) {
    const float c = (x + y) % 2 ? 0.9f : 0.1f;
    return Rgba{c, 1 - c, 0.5f, 1};
  });
  Expected<VertexBakeResult> r = bake_vertex(s.mesh, img.view(), s.proxy, bilinear_options());
  ASSERT_TRUE(r);
  for (int j = 1; j < ShadowScene::kCells; ++j) {
    for (int i = 1; i < ShadowScene::kCells; ++i) {
      if (!ShadowScene::in_shadow(i, j)) continue;
      // Neighbours in the grid triangulation: 4-neighbourhood + one diagonal pair.
      const int nb[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}};
      double mean = 0;
      for (const auto& d : nb) mean += r->colors[ShadowScene::id(i + d[0], j + d[1])][0] / 6.0;
      EXPECT_NEAR(r->colors[ShadowScene::id(i, j)][0], mean, 1e-5) << i << "," << j;
      EXPECT_GT(r->colors[ShadowScene::id(i, j)][0], 0.1f);
      EXPECT_LT(r->colors[ShadowScene::id(i, j)][0], 0.9f);
    }
  }
}

TEST(BakeVertex, VisibilityAllAndOccludedProjectGiveTheProjectedColours) {
  ShadowScene s;
  const TestImage img = ramp_image(256, 256);
  VertexBakeOptions all = bilinear_options();
  all.visibility = Visibility::kAll;
  VertexBakeOptions project = bilinear_options();
  project.occluded = OccludedMode::kProject;
  Expected<VertexBakeResult> a = bake_vertex(s.mesh, img.view(), s.proxy, all);
  Expected<VertexBakeResult> p = bake_vertex(s.mesh, img.view(), s.proxy, project);
  ASSERT_TRUE(a);
  ASSERT_TRUE(p);
  EXPECT_EQ(a->counts.occluded, 0u);
  EXPECT_GE(p->counts.occluded, 25u);
  EXPECT_EQ(p->counts.filled, 0u);
  for (uint32_t v = 0; v < s.mesh.positions.size(); ++v) {
    const double u = s.mesh.positions[v].x, vv = s.mesh.positions[v].y;
    EXPECT_NEAR(a->colors[v][0], std::clamp(u, 0.5 / 256, 1 - 0.5 / 256), 1e-5) << v;
    EXPECT_NEAR(a->colors[v][1], std::clamp(1 - vv, 0.5 / 256, 1 - 0.5 / 256), 1e-5) << v;
    EXPECT_EQ(a->colors[v], p->colors[v]) << v;
  }
}

TEST(BakeVertex, OccludedColourGoesToExactlyTheShadowedVertices) {
  ShadowScene s;
  const TestImage img = ramp_image();
  VertexBakeOptions o = bilinear_options();
  o.occluded = OccludedMode::kColor;
  o.occluded_color = {1, 0, 1, 0.5f};
  Expected<VertexBakeResult> r = bake_vertex(s.mesh, img.view(), s.proxy, o);
  ASSERT_TRUE(r);
  for (int j = 0; j <= ShadowScene::kCells; ++j) {
    for (int i = 0; i <= ShadowScene::kCells; ++i) {
      const bool magenta = r->colors[ShadowScene::id(i, j)] == Rgba{1, 0, 1, 0.5f};
      EXPECT_EQ(magenta, ShadowScene::in_shadow(i, j)) << i << "," << j;
    }
  }
  for (int k = 4; k < 8; ++k) {  // the box's top face is lit
    EXPECT_NE(r->colors[s.box_first + k], (Rgba{1, 0, 1, 0.5f}));
  }
}

TEST(BakeVertex, OutputDoesNotDependOnTheThreadCount) {
  const TestImage img = stripe_image();
  Expected<Proxy> proxy = make_proxy(SphereParams{{0, 0, 0}, 3.0, {0, 0, 1}, Vec3{1, 0, 0}});
  ASSERT_TRUE(proxy);
  // A closed sphere mesh plus the shadow scene's grid and box inside it: many
  // chunks, occluded vertices to fill.
  MeshData mesh = test::uv_sphere({0, 0, 0}, 1.0, 40, 80);
  test::append_grid(mesh, 60, 60, [](double s, double t) {
    return Float3{static_cast<float>(0.4 * s - 0.2), static_cast<float>(0.4 * t - 0.2), 1.2f};
  });
  test::append_box(mesh, {-0.1f, -0.1f, 1.3f}, {0.1f, 0.1f, 1.4f});
  test::faces_from_triangles(mesh);
  for (VertexFilter filter : {VertexFilter::kArea, VertexFilter::kBilinear}) {
    VertexBakeOptions o;
    o.filter = filter;
    std::vector<Rgba> one, two;
    VertexBakeCounts c1, c2;
    {
      ThreadLimit limit(1);
      Expected<VertexBakeResult> r = bake_vertex(mesh, img.view(), *proxy, o);
      ASSERT_TRUE(r);
      one = r->colors, c1 = r->counts;
    }
    {
      ThreadLimit limit(2);
      Expected<VertexBakeResult> r = bake_vertex(mesh, img.view(), *proxy, o);
      ASSERT_TRUE(r);
      two = r->colors, c2 = r->counts;
    }
    EXPECT_EQ(one, two);
    EXPECT_EQ(c1.samples, c2.samples);
    EXPECT_EQ(c1.occluded, c2.occluded);
    EXPECT_GT(c1.occluded, 0u);  // the grid shadows the sphere's top
  }
}

// ---- Colour space, outside, odd vertices. -------------------------------------

TEST(BakeVertex, LinearAveragesInLinearLight) {
  // Black and white texels; the vertex sits halfway between their centres.
  const TestImage img{2, 1, {0, 0, 0, 1, 1, 1, 1, 1}};
  Expected<Proxy> proxy = make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  ASSERT_TRUE(proxy);
  MeshData mesh;
  mesh.positions = {{0.5f, 0.5f, 0}, {0.6f, 0.5f, 0}, {0.5f, 0.6f, 0}};
  mesh.triangles = {{0, 1, 2}};
  test::faces_from_triangles(mesh);
  VertexBakeOptions o = bilinear_options();
  Expected<VertexBakeResult> plain = bake_vertex(mesh, img.view(), *proxy, o);
  o.linear = true;
  Expected<VertexBakeResult> linear = bake_vertex(mesh, img.view(), *proxy, o);
  ASSERT_TRUE(plain);
  ASSERT_TRUE(linear);
  EXPECT_NEAR(plain->colors[0][0], 0.5f, 1e-6);
  // sRGB encoding of linear 0.5 (IEC 61966-2-1): 1.055 * 0.5^(1/2.4) - 0.055.
  const double expected = 1.055 * std::pow(0.5, 1 / 2.4) - 0.055;  // 0.735357
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(linear->colors[0][k], expected, 1e-5);
  EXPECT_FLOAT_EQ(linear->colors[0][3], 1.0f);  // alpha is never converted
}

TEST(BakeVertex, OutsideClampColourAndPlaneRepeat) {
  const TestImage img = ramp_image();
  Expected<Proxy> proxy = make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  ASSERT_TRUE(proxy);
  MeshData mesh;  // vertex 0 inside, 1 at u = 1.25, 2 at v = -0.5
  mesh.positions = {{0.25f, 0.5f, 0}, {1.25f, 0.5f, 0}, {0.25f, -0.5f, 0}};
  mesh.triangles = {{0, 1, 2}};
  test::faces_from_triangles(mesh);
  VertexBakeOptions o = bilinear_options();
  o.visibility = Visibility::kAll;
  Expected<VertexBakeResult> clamp = bake_vertex(mesh, img.view(), *proxy, o);
  ASSERT_TRUE(clamp);
  EXPECT_EQ(clamp->counts.outside, 2u);
  EXPECT_NEAR(clamp->colors[1][0], 1 - 0.5 / 64, 1e-6);  // last column's centre
  EXPECT_NEAR(clamp->colors[2][1], 1 - 0.5 / 32, 1e-6);  // bottom row (v < 0)
  o.outside = OutsideMode::kColor;
  o.outside_color = {0, 1, 0, 1};
  Expected<VertexBakeResult> color = bake_vertex(mesh, img.view(), *proxy, o);
  ASSERT_TRUE(color);
  EXPECT_EQ(color->colors[1], (Rgba{0, 1, 0, 1}));
  EXPECT_EQ(color->colors[2], (Rgba{0, 1, 0, 1}));
  EXPECT_NEAR(color->colors[0][0], 0.25f, 1e-6);
  o.plane_wrap = WrapMode::kRepeat;
  Expected<VertexBakeResult> repeat = bake_vertex(mesh, img.view(), *proxy, o);
  ASSERT_TRUE(repeat);
  EXPECT_EQ(repeat->counts.outside, 0u);
  EXPECT_NEAR(repeat->colors[1][0], 0.25f, 1e-6);     // u = 1.25 tiles to 0.25
  EXPECT_NEAR(repeat->colors[2][1], 1 - 0.5f, 1e-6);  // v = -0.5 tiles to 0.5
}

TEST(BakeVertex, UnreferencedVerticesSampleAtThemselvesAndKeepTheirPlace) {
  const TestImage img = ramp_image();
  Expected<Proxy> proxy = make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  ASSERT_TRUE(proxy);
  MeshData mesh;
  mesh.positions = {{0.7f, 0.3f, 0}, {0.2f, 0.2f, 0}, {0.4f, 0.2f, 0}, {0.2f, 0.4f, 0}};
  mesh.triangles = {{1, 2, 3}};  // vertex 0 is in no triangle
  test::faces_from_triangles(mesh);
  Expected<VertexBakeResult> r = bake_vertex(mesh, img.view(), *proxy, VertexBakeOptions{});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->colors.size(), 4u);
  EXPECT_NEAR(r->colors[0][0], 0.7f, 1e-6);
  EXPECT_NEAR(r->colors[0][1], 0.7f, 1e-6);
  // Vertex 1's share is the corner quad of its triangle, right of and above it.
  EXPECT_GT(r->colors[1][0], 0.2f);
  EXPECT_LT(r->colors[1][0], 0.2f + 0.2f / 2);
  EXPECT_EQ(r->counts.samples, 1u + 3 * 16);
}

TEST(BakeVertex, VertexWithoutMappingIsFilledFromItsNeighbours) {
  // A fan around the sphere's centre: the centre vertex has no mapping
  // (SPEC section 2) and takes the harmonic value: the mean of its ring.
  const TestImage img = ramp_image();
  Expected<Proxy> proxy = make_proxy(SphereParams{{0, 0, 0}, 1.0, {0, 0, 1}, Vec3{1, 0, 0}});
  ASSERT_TRUE(proxy);
  MeshData mesh;
  mesh.positions.push_back({0, 0, 0});
  constexpr int kRing = 6;
  for (int k = 0; k < kRing; ++k) {
    const double a = 2 * std::numbers::pi * (k + 0.5) / kRing;
    mesh.positions.push_back(
        {static_cast<float>(0.8 * std::cos(a)), static_cast<float>(0.6 * std::sin(a)), 0.3f});
    mesh.triangles.push_back({0, 1u + k, 1u + (k + 1) % kRing});
  }
  test::faces_from_triangles(mesh);
  VertexBakeOptions o = bilinear_options();
  o.visibility = Visibility::kAll;
  Expected<VertexBakeResult> r = bake_vertex(mesh, img.view(), *proxy, o);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->counts.undefined, 1u);
  EXPECT_EQ(r->counts.filled, 1u);
  for (int c = 0; c < 4; ++c) {
    double mean = 0;
    for (int k = 1; k <= kRing; ++k) mean += r->colors[k][c] / kRing;
    EXPECT_NEAR(r->colors[0][c], mean, 1e-6);
  }
}

TEST(BakeVertex, ComponentWithNoVisibleVertexGetsTheProjectedColourAndIsCounted) {
  // A small square entirely under a large plate: nothing of it sees the projector.
  const TestImage img = ramp_image();
  Expected<Proxy> proxy = make_proxy(PlaneParams{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}});
  ASSERT_TRUE(proxy);
  MeshData mesh;
  test::append_grid(mesh, 2, 2, [](double s, double t) {
    return Float3{static_cast<float>(0.4 + 0.2 * s), static_cast<float>(0.4 + 0.2 * t), 0};
  });
  test::append_grid(mesh, 1, 1, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0.5f};
  });
  test::faces_from_triangles(mesh);
  Expected<VertexBakeResult> r = bake_vertex(mesh, img.view(), *proxy, bilinear_options());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->counts.occluded, 9u);
  EXPECT_EQ(r->counts.unfilled, 9u);
  for (uint32_t v = 0; v < 9; ++v) {
    EXPECT_NEAR(r->colors[v][0], mesh.positions[v].x, 1e-5) << v;
    EXPECT_NEAR(r->colors[v][1], 1 - mesh.positions[v].y, 1e-5) << v;
  }
}

}  // namespace
}  // namespace texbake
