// Harmonic fill: exact on linear data (linear functions are discrete-harmonic
// on the regular grid triangulation: a vertex's six neighbours' offsets sum to
// zero with equal weights), the discrete equation holds (checked directly),
// maximum principle, unanchored components fall back and are counted.
#include "bake/vertex/occlusion_fill.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "tests/bake/test_meshes.h"

namespace texbake {
namespace {

constexpr int kCells = 16;

MeshData grid() {
  MeshData mesh;
  test::append_grid(mesh, kCells, kCells, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0};
  });
  test::faces_from_triangles(mesh);
  return mesh;
}

uint32_t id(int i, int j) {
  return static_cast<uint32_t>(j * (kCells + 1) + i);
}

// Unknown: an L-shaped interior region (not touching the border).
std::vector<uint8_t> l_region() {
  std::vector<uint8_t> unknown((kCells + 1) * (kCells + 1), 0);
  for (int j = 3; j <= 12; ++j) {
    for (int i = 2; i <= 13; ++i) {
      if (i <= 6 || j <= 6) unknown[id(i, j)] = 1;
    }
  }
  return unknown;
}

Rgba never_called(uint32_t) {
  ADD_FAILURE() << "fallback called for an anchored component";
  return {0, 0, 0, 0};
}

TEST(OcclusionFill, ReproducesLinearColoursExactly) {
  const MeshData mesh = grid();
  const std::vector<uint8_t> unknown = l_region();
  auto linear = [](double x, double y) {
    return Rgba{static_cast<float>(0.1 + 0.5 * x), static_cast<float>(0.9 - 0.7 * y),
                static_cast<float>(0.2 + 0.3 * x + 0.4 * y), 1.0f};
  };
  std::vector<Rgba> colors(mesh.positions.size());
  for (std::size_t v = 0; v < colors.size(); ++v) {
    colors[v] = unknown[v] ? Rgba{0, 0, 0, 0} : linear(mesh.positions[v].x, mesh.positions[v].y);
  }
  Expected<FillResult> r = fill_harmonic(mesh, colors, unknown, never_called);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->unfilled, 0u);
  EXPECT_EQ(r->filled, static_cast<std::size_t>(std::count(unknown.begin(), unknown.end(), 1)));
  for (std::size_t v = 0; v < colors.size(); ++v) {
    const Rgba want = linear(mesh.positions[v].x, mesh.positions[v].y);
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(colors[v][c], want[c], 1e-5) << "vertex " << v;
  }
}

TEST(OcclusionFill, SatisfiesTheDiscreteLaplaceEquationAndMaximumPrinciple) {
  const MeshData mesh = grid();
  const std::vector<uint8_t> unknown = l_region();
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> dist(0.2f, 0.8f);
  std::vector<Rgba> colors(mesh.positions.size());
  for (std::size_t v = 0; v < colors.size(); ++v) {
    colors[v] = unknown[v] ? Rgba{0, 0, 0, 0} : Rgba{dist(rng), dist(rng), dist(rng), dist(rng)};
  }
  const std::vector<Rgba> before = colors;
  Expected<FillResult> r = fill_harmonic(mesh, colors, unknown, never_called);
  ASSERT_TRUE(r);
  // Weighted neighbour sums from the triangles, independently of the solver.
  std::vector<std::array<double, 4>> sum(colors.size(), {0, 0, 0, 0});
  std::vector<double> weight(colors.size(), 0);
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      for (int e : {1, 2}) {
        const uint32_t a = t[k], b = t[(k + e) % 3];
        weight[a] += 1;
        for (int c = 0; c < 4; ++c) sum[a][c] += colors[b][c];
      }
    }
  }
  float lo = 1, hi = 0;  // range of the known values bordering the region
  for (std::size_t v = 0; v < colors.size(); ++v) {
    if (!unknown[v]) {
      EXPECT_EQ(colors[v], before[v]) << "known vertex " << v << " changed";
      continue;
    }
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(colors[v][c], sum[v][c] / weight[v], 1e-5) << "vertex " << v;
    }
  }
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      if (unknown[a] != unknown[b]) {
        const uint32_t known = unknown[a] ? b : a;
        for (int c = 0; c < 4; ++c)
          lo = std::min(lo, colors[known][c]), hi = std::max(hi, colors[known][c]);
      }
    }
  }
  for (std::size_t v = 0; v < colors.size(); ++v) {
    if (!unknown[v]) continue;
    for (int c = 0; c < 4; ++c) {
      EXPECT_GE(colors[v][c], lo - 1e-6f);
      EXPECT_LE(colors[v][c], hi + 1e-6f);
    }
  }
}

TEST(OcclusionFill, ComponentsWithoutKnownVerticesFallBackAndAreCounted) {
  // Two separate triangles and a lone vertex in no triangle.
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}, {9, 9, 9}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  test::faces_from_triangles(mesh);
  std::vector<Rgba> colors = {{0.2f, 0.4f, 0.6f, 1}, {0.4f, 0.4f, 0.6f, 1}, {0, 0, 0, 0},
                              {0, 0, 0, 0},          {0, 0, 0, 0},          {0, 0, 0, 0},
                              {0, 0, 0, 0}};
  const std::vector<uint8_t> unknown = {0, 0, 1, 1, 1, 1, 1};
  std::vector<uint32_t> asked;
  auto fallback = [&](uint32_t v) {
    asked.push_back(v);
    return Rgba{0.5f, 0.25f, static_cast<float>(v) / 10, 1};
  };
  Expected<FillResult> r = fill_harmonic(mesh, colors, unknown, fallback);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->filled, 1u);
  EXPECT_EQ(r->unfilled, 4u);
  EXPECT_EQ(asked, (std::vector<uint32_t>{3, 4, 5, 6}));
  // Vertex 2's neighbours are 0 and 1 (each edge in one triangle): their mean.
  EXPECT_NEAR(colors[2][0], 0.3f, 1e-6);
  EXPECT_NEAR(colors[2][1], 0.4f, 1e-6);
  for (uint32_t v : {3u, 4u, 5u, 6u}) EXPECT_FLOAT_EQ(colors[v][2], v / 10.0f);
}

TEST(OcclusionFill, NothingUnknownChangesNothing) {
  const MeshData mesh = grid();
  std::vector<Rgba> colors(mesh.positions.size(), Rgba{0.3f, 0.3f, 0.3f, 1});
  const std::vector<Rgba> before = colors;
  Expected<FillResult> r =
      fill_harmonic(mesh, colors, std::vector<uint8_t>(colors.size(), 0), never_called);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->filled, 0u);
  EXPECT_EQ(r->unfilled, 0u);
  EXPECT_EQ(colors, before);
}

}  // namespace
}  // namespace texbake
