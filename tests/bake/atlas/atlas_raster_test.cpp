// Atlas rasterisation: conservative coverage, per-sample triangles and
// barycentrics, determinism, bad input.
#include "bake/atlas/atlas_raster.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "bake/util/parallel.h"
#include "tests/bake/atlas/atlas_test_util.h"

namespace texbake {
namespace {

using test::make_flat_uv_soup;

// Seeded random triangles with UVs partly outside [0, 1] (clipped coverage),
// some large, some smaller than a texel, one degenerate (zero UV area).
std::vector<Float2> random_uv_triangles(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> centre(-0.05f, 1.05f), size(0.002f, 0.3f), unit(-1.f, 1.f);
  std::vector<Float2> uv;
  for (int t = 0; t < count; ++t) {
    const float cx = centre(rng), cy = centre(rng), s = size(rng);
    for (int k = 0; k < 3; ++k) uv.push_back({cx + s * unit(rng), cy + s * unit(rng)});
  }
  // Degenerate: a segment.
  uv.push_back({0.2f, 0.3f});
  uv.push_back({0.6f, 0.5f});
  uv.push_back({0.4f, 0.4f});
  return uv;
}

// Every texel that a bilinear lookup from any point of any triangle reads
// (floor(x), floor(x)+1 by floor(y), floor(y)+1 at SPEC section 1's pixel
// position) is covered. Points: uniform inside, on the edges, and within
// half a texel inside of the edges.
TEST(AtlasRaster, CoversEveryTexelABilinearLookupReads) {
  for (int size : {17, 64, 100}) {
    const MeshData mesh = make_flat_uv_soup(random_uv_triangles(60, 7 + size));
    auto raster = rasterize_atlas(mesh, {size, 1});
    ASSERT_TRUE(raster) << raster.error().message;
    const std::vector<uint8_t> mask = coverage_mask(*raster);
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> unit(0, 1);
    std::size_t checked = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Float2 a = triangle_uv(mesh, t, 0), b = triangle_uv(mesh, t, 1),
                   c = triangle_uv(mesh, t, 2);
      const double cu = (a.u + b.u + c.u) / 3, cv = (a.v + b.v + c.v) / 3;
      for (int i = 0; i < 3000; ++i) {
        double r1 = unit(rng), r2 = unit(rng);
        if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
        double u = a.u + r1 * (b.u - a.u) + r2 * (c.u - a.u);
        double v = a.v + r1 * (b.v - a.v) + r2 * (c.v - a.v);
        if (i % 3 == 1) {
          // On an edge.
          const Float2 p = i % 2 ? a : b, q = i % 2 ? c : a;
          const double s = unit(rng);
          u = p.u + s * (q.u - p.u);
          v = p.v + s * (q.v - p.v);
        } else if (i % 3 == 2) {
          // Pull an edge point towards the centroid by at most half a texel.
          const Float2 p = b, q = c;
          const double s = unit(rng);
          double eu = p.u + s * (q.u - p.u), ev = p.v + s * (q.v - p.v);
          const double du = cu - eu, dv = cv - ev, len = std::hypot(du, dv);
          const double step = std::min(len, 0.5 / size) * unit(rng);
          if (len > 0) eu += du / len * step, ev += dv / len * step;
          u = eu, v = ev;
        }
        const double x = u * size - 0.5, y = (1 - v) * size - 0.5;
        const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) {
            const int tx = x0 + dx, ty = y0 + dy;
            if (tx < 0 || ty < 0 || tx >= size || ty >= size) continue;
            ++checked;
            ASSERT_TRUE(mask[ty * size + tx]) << "size " << size << " triangle " << t << " uv ("
                                              << u << ", " << v << ") texel " << tx << "," << ty;
          }
        }
      }
    }
    EXPECT_GT(checked, 100000u);
  }
}

// Independent second method for the exact coverage set: the square
// [i-1, i+1] x [j-1, j+1] meets the triangle iff a triangle corner lies in
// the square, a square corner lies in the triangle, or an edge of one crosses
// an edge of the other.
bool square_meets_triangle(double cx, double cy, const double (&px)[3], const double (&py)[3]) {
  for (int k = 0; k < 3; ++k) {
    if (std::abs(px[k] - cx) <= 1 && std::abs(py[k] - cy) <= 1) return true;
  }
  auto orient = [](double ax, double ay, double bx, double by, double qx, double qy) {
    return (bx - ax) * (qy - ay) - (by - ay) * (qx - ax);
  };
  const double sx[4] = {cx - 1, cx + 1, cx + 1, cx - 1}, sy[4] = {cy - 1, cy - 1, cy + 1, cy + 1};
  for (int s = 0; s < 4; ++s) {
    const double o0 = orient(px[0], py[0], px[1], py[1], sx[s], sy[s]);
    const double o1 = orient(px[1], py[1], px[2], py[2], sx[s], sy[s]);
    const double o2 = orient(px[2], py[2], px[0], py[0], sx[s], sy[s]);
    if ((o0 >= 0 && o1 >= 0 && o2 >= 0) || (o0 <= 0 && o1 <= 0 && o2 <= 0)) return true;
  }
  for (int k = 0; k < 3; ++k) {
    const double ax = px[k], ay = py[k], bx = px[(k + 1) % 3], by = py[(k + 1) % 3];
    for (int s = 0; s < 4; ++s) {
      const double cx2 = sx[s], cy2 = sy[s], dx2 = sx[(s + 1) % 4], dy2 = sy[(s + 1) % 4];
      const double d1 = orient(ax, ay, bx, by, cx2, cy2), d2 = orient(ax, ay, bx, by, dx2, dy2);
      const double d3 = orient(cx2, cy2, dx2, dy2, ax, ay), d4 = orient(cx2, cy2, dx2, dy2, bx, by);
      if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0))) return true;
    }
  }
  return false;
}

TEST(AtlasRaster, CoverageEqualsBruteForceSquareTriangleTest) {
  const int size = 40;
  const MeshData mesh = make_flat_uv_soup(random_uv_triangles(25, 99));
  auto raster = rasterize_atlas(mesh, {size, 2});
  ASSERT_TRUE(raster);
  const std::vector<uint8_t> mask = coverage_mask(*raster);
  std::size_t covered = 0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      bool expect = false;
      for (std::size_t t = 0; t < mesh.triangles.size() && !expect; ++t) {
        double px[3], py[3];
        for (int k = 0; k < 3; ++k) {
          const Float2 q = triangle_uv(mesh, t, k);
          px[k] = double(q.u) * size - 0.5;
          py[k] = (1 - double(q.v)) * size - 0.5;
        }
        expect = square_meets_triangle(x, y, px, py);
      }
      covered += expect;
      EXPECT_EQ(mask[y * size + x] != 0, expect) << "texel " << x << "," << y;
    }
  }
  EXPECT_EQ(raster->texels.size(), covered);
  EXPECT_TRUE(std::is_sorted(raster->texels.begin(), raster->texels.end()));
}

// One triangle uv (0,0), (1,0), (0,1) in a 4 x 4 atlas, 1 sample at the texel
// centre. In pixel space its corners are (-0.5, 3.5), (3.5, 3.5), (-0.5, -0.5)
// and it is the region x >= -0.5, y <= 3.5, y >= x.
TEST(AtlasRaster, HandWorkedTriangle) {
  const MeshData mesh = make_flat_uv_soup({{0, 0}, {1, 0}, {0, 1}});
  auto raster = rasterize_atlas(mesh, {4, 1});
  ASSERT_TRUE(raster);
  const std::vector<uint8_t> mask = coverage_mask(*raster);
  // Texel (x, y) is covered iff the square [x-1, x+1] x [y-1, y+1] reaches
  // y >= x, i.e. x - 1 <= y + 1: all but (3, 0).
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_EQ(mask[y * 4 + x], (x == 3 && y == 0) ? 0 : 1);
  ASSERT_EQ(raster->texels.size(), 15u);
  // Texel (2, 0) (index 2): centre (2, 0) lies outside; the nearest triangle
  // point is (1, 1) on y = x, i.e. uv (1.5/4, 1 - 1.5/4) = (0.375, 0.625),
  // whose barycentrics are (b1, b2) = (u, v).
  EXPECT_EQ(raster->texels[2], 2u);
  EXPECT_NEAR(raster->sample_b1[2], 0.375, 1e-6);
  EXPECT_NEAR(raster->sample_b2[2], 0.625, 1e-6);
  // Texel (0, 3) (bottom-left, index 12 -> 11th covered): centre uv
  // (0.125, 0.125) is inside: b = (0.125, 0.125).
  EXPECT_EQ(raster->texels[11], 12u);
  EXPECT_NEAR(raster->sample_b1[11], 0.125, 1e-6);
  EXPECT_NEAR(raster->sample_b2[11], 0.125, 1e-6);
  // Border samples: texels whose centre is off y >= x: (1,0), (2,0), (2,1), (3,1), (3,2).
  EXPECT_EQ(raster->border_samples, 5u);
}

// Inside samples reproduce their own position from (triangle, b1, b2);
// border samples land on their triangle (b in [0, 1]) no farther than any
// other triangle's corners. Overlap is resolved by the lowest index.
TEST(AtlasRaster, SamplesMapBackToTheirPositions) {
  // Two overlapping triangles: 0 and 1 cover the middle; 1 also a strip alone.
  const MeshData mesh = make_flat_uv_soup({{0.1f, 0.1f},
                                           {0.7f, 0.1f},
                                           {0.1f, 0.7f},  // 0
                                           {0.2f, 0.2f},
                                           {0.9f, 0.2f},
                                           {0.2f, 0.9f}});  // 1
  const int size = 32, spt = 4;
  auto raster = rasterize_atlas(mesh, {size, spt});
  ASSERT_TRUE(raster);
  for (std::size_t k = 0; k < raster->texels.size(); ++k) {
    const int x = raster->texels[k] % size, y = raster->texels[k] / size;
    for (int s = 0; s < spt; ++s) {
      const std::size_t i = k * spt + s;
      const SampleOffset o = sample_offset(s, spt);
      const double su = (x + o.dx + 0.5) / size, sv = 1 - (y + o.dy + 0.5) / size;
      const uint32_t t = raster->sample_triangle[i];
      const double b1 = raster->sample_b1[i], b2 = raster->sample_b2[i];
      ASSERT_GE(b1, -1e-6);
      ASSERT_GE(b2, -1e-6);
      ASSERT_LE(b1 + b2, 1 + 1e-6);
      const Float2 a = triangle_uv(mesh, t, 0), b = triangle_uv(mesh, t, 1),
                   c = triangle_uv(mesh, t, 2);
      const double u = a.u + b1 * (b.u - a.u) + b2 * (c.u - a.u);
      const double v = a.v + b1 * (b.v - a.v) + b2 * (c.v - a.v);
      const bool in0 = su >= 0.1 && sv >= 0.1 && su + sv <= 0.8;
      const bool in1 = su >= 0.2 && sv >= 0.2 && su + sv <= 1.1;
      if (in0 || in1) {
        EXPECT_EQ(t, in0 ? 0u : 1u);
        EXPECT_NEAR(u, su, 1e-6);
        EXPECT_NEAR(v, sv, 1e-6);
      } else {
        // Clamped onto a triangle edge: within 1.5 texels (a corner of the
        // dilated square) of the sample.
        EXPECT_LE(std::hypot(u - su, v - sv) * size, 1.5 * std::sqrt(2.0) + 1e-6);
      }
    }
  }
}

TEST(AtlasRaster, SampleOffsetsAreStratified) {
  EXPECT_EQ(sample_offset(0, 1).dx, 0);
  EXPECT_EQ(sample_offset(0, 1).dy, 0);
  // 4 = 2 x 2: the centres of the quarter cells.
  EXPECT_DOUBLE_EQ(sample_offset(0, 4).dx, -0.25);
  EXPECT_DOUBLE_EQ(sample_offset(0, 4).dy, -0.25);
  EXPECT_DOUBLE_EQ(sample_offset(3, 4).dx, 0.25);
  EXPECT_DOUBLE_EQ(sample_offset(3, 4).dy, 0.25);
  // 2: Hammersley x = 1/4, 3/4 (minus 1/2); y = 0, 1/2 shifted by 1/4.
  EXPECT_DOUBLE_EQ(sample_offset(0, 2).dx, -0.25);
  EXPECT_DOUBLE_EQ(sample_offset(1, 2).dx, 0.25);
  EXPECT_DOUBLE_EQ(sample_offset(0, 2).dy, -0.25);
  EXPECT_DOUBLE_EQ(sample_offset(1, 2).dy, 0.25);
  for (int n : {3, 5, 7, 9, 16, 17}) {
    for (int s = 0; s < n; ++s) {
      const SampleOffset o = sample_offset(s, n);
      EXPECT_GT(o.dx, -0.5);
      EXPECT_LT(o.dx, 0.5);
      EXPECT_GT(o.dy, -0.5);
      EXPECT_LT(o.dy, 0.5);
    }
  }
}

TEST(AtlasRaster, IndependentOfThreadCount) {
  const MeshData mesh = make_flat_uv_soup(random_uv_triangles(300, 5));
  AtlasRaster one, two;
  {
    ThreadLimit limit(1);
    one = std::move(rasterize_atlas(mesh, {200, 3}).value());
  }
  {
    ThreadLimit limit(2);
    two = std::move(rasterize_atlas(mesh, {200, 3}).value());
  }
  EXPECT_EQ(one.texels, two.texels);
  EXPECT_EQ(one.sample_triangle, two.sample_triangle);
  EXPECT_EQ(one.sample_b1, two.sample_b1);
  EXPECT_EQ(one.sample_b2, two.sample_b2);
  EXPECT_EQ(one.border_samples, two.border_samples);
}

// AtlasBands::check: prepare's errors without its tables, and whether the
// bands will hold anything (a bake skips its scene and fill when not).
TEST(AtlasRaster, CheckGivesPreparesErrorsAndWhetherAnyRowIsReached) {
  const AtlasRasterOptions options{8, 1};
  bool covers = false;
  const MeshData inside = make_flat_uv_soup({{0.2f, 0.2f}, {0.8f, 0.2f}, {0.2f, 0.8f}});
  ASSERT_TRUE(AtlasBands::check(inside, options, &covers));
  EXPECT_TRUE(covers);
  // Far above and below the unit square: no row of the atlas, however dilated.
  for (float v0 : {2.0f, -1.5f}) {
    const MeshData outside = make_flat_uv_soup({{0.2f, v0}, {0.8f, v0}, {0.2f, v0 + 0.5f}});
    covers = true;
    ASSERT_TRUE(AtlasBands::check(outside, options, &covers));
    EXPECT_FALSE(covers) << v0;
    Expected<AtlasBands> bands = AtlasBands::prepare(outside, options);
    ASSERT_TRUE(bands);
    EXPECT_TRUE(bands->empty());
  }
  // Outside in u only: rows are reached (the columns are the raster's business).
  const MeshData right = make_flat_uv_soup({{1.5f, 0.2f}, {1.9f, 0.2f}, {1.5f, 0.8f}});
  ASSERT_TRUE(AtlasBands::check(right, options, &covers));
  EXPECT_TRUE(covers);
  // The errors are prepare's.
  MeshData nan_uv = inside;
  nan_uv.uvs[1].u = std::nanf("");
  Status s = AtlasBands::check(nan_uv, options);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kParse);
  EXPECT_EQ(s.error().message, AtlasBands::prepare(nan_uv, options).error().message);
  s = AtlasBands::check(inside, {8, 0});
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("--samples"), std::string::npos);
}

TEST(AtlasRaster, BadInputIsRejected) {
  const MeshData mesh = make_flat_uv_soup({{0, 0}, {1, 0}, {0, 1}});
  for (int size : {0, -3, kMaxAtlasSize + 1}) {
    auto r = rasterize_atlas(mesh, {size, 1});
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
    EXPECT_NE(r.error().message.find("--size"), std::string::npos);
  }
  auto r = rasterize_atlas(mesh, {8, 0});
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("--samples"), std::string::npos);

  MeshData no_uv = mesh;
  no_uv.uvs.clear();
  no_uv.corner_uv.clear();
  r = rasterize_atlas(no_uv, {8, 1});
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("no UV"), std::string::npos);

  MeshData nan_uv = mesh;
  nan_uv.uvs[1].u = std::nanf("");
  r = rasterize_atlas(nan_uv, {8, 1});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, ErrorCode::kParse);
  EXPECT_NE(r.error().message.find("triangle 0"), std::string::npos);

  MeshData bad_index = mesh;
  bad_index.corner_uv[2] = 17;
  r = rasterize_atlas(bad_index, {8, 1});
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("out of range"), std::string::npos);
}

}  // namespace
}  // namespace texbake
