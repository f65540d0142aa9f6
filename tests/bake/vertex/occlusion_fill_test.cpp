// Harmonic fill: exact on linear data (linear functions are discrete-harmonic
// on the regular grid triangulation: a vertex's six neighbours' offsets sum to
// zero with equal weights), the discrete equation holds (checked directly),
// maximum principle, unanchored components fall back and are counted; the
// multigrid solver of large components agrees with the direct one (on a grid
// and on the shadows of the bunny and the 832k armadillo seen from a sphere
// proxy's centre), independently of the thread count.
#include "bake/vertex/occlusion_fill.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/vertex/laplace_multigrid.h"
#include "mesh_io/read_mesh.h"
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

// ---- The multigrid path (FillSolverOptions::direct_rows) -----------------

const FillSolverOptions kDirect{static_cast<std::size_t>(-1), 0};
// Multigrid for every component: to a tight tolerance (the solver converges
// to the exact solution), and to the default one (what `bake` gets).
const FillSolverOptions kMultigridTight{0, 1e-10};
const FillSolverOptions kMultigrid{0, FillSolverOptions{}.relative_tolerance};

// The largest difference between two fills over the unknown vertices.
double max_difference(const std::vector<Rgba>& a, const std::vector<Rgba>& b,
                      const std::vector<uint8_t>& unknown) {
  double worst = 0;
  for (std::size_t v = 0; v < a.size(); ++v) {
    if (!unknown[v]) continue;
    for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(double(a[v][c]) - b[v][c]));
  }
  return worst;
}

// Random known colours in [0.05, 0.95], zero where unknown.
std::vector<Rgba> random_known(const std::vector<uint8_t>& unknown, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(0.05f, 0.95f);
  std::vector<Rgba> colors(unknown.size());
  for (std::size_t v = 0; v < colors.size(); ++v) {
    colors[v] = unknown[v] ? Rgba{0, 0, 0, 0} : Rgba{dist(rng), dist(rng), dist(rng), dist(rng)};
  }
  return colors;
}

// A 150 x 150 cell grid, unknown inside a disc of radius 0.4 and inside a
// thin ring around it (two components, 15k unknowns).
struct DiscCase {
  MeshData mesh;
  std::vector<uint8_t> unknown;
};
DiscCase disc_case() {
  DiscCase d;
  test::append_grid(d.mesh, 150, 150, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0};
  });
  test::faces_from_triangles(d.mesh);
  for (const Float3& p : d.mesh.positions) {
    const double r = std::hypot(p.x - 0.5, p.y - 0.5);
    d.unknown.push_back(r < 0.4 || (r > 0.42 && r < 0.46) ? 1 : 0);
  }
  return d;
}

TEST(OcclusionFill, MultigridReproducesLinearColours) {
  const DiscCase d = disc_case();
  auto linear = [](const Float3& p) {
    return Rgba{static_cast<float>(0.1 + 0.5 * p.x), static_cast<float>(0.9 - 0.7 * p.y),
                static_cast<float>(0.2 + 0.3 * p.x + 0.4 * p.y), 0.75f};
  };
  std::vector<Rgba> colors(d.mesh.positions.size());
  for (std::size_t v = 0; v < colors.size(); ++v) {
    colors[v] = d.unknown[v] ? Rgba{0, 0, 0, 0} : linear(d.mesh.positions[v]);
  }
  Expected<FillResult> r = fill_harmonic(d.mesh, colors, d.unknown, never_called, kMultigridTight);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->filled, static_cast<std::size_t>(std::count(d.unknown.begin(), d.unknown.end(), 1)));
  double worst = 0;
  for (std::size_t v = 0; v < colors.size(); ++v) {
    const Rgba want = linear(d.mesh.positions[v]);
    for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(double(colors[v][c]) - want[c]));
  }
  EXPECT_LT(worst, 1e-6);
}

TEST(OcclusionFill, MultigridAgreesWithTheDirectSolveOnAGrid) {
  const DiscCase d = disc_case();
  std::vector<Rgba> direct = random_known(d.unknown, 7), multigrid = direct;
  ASSERT_TRUE(fill_harmonic(d.mesh, direct, d.unknown, never_called, kDirect));
  ASSERT_TRUE(fill_harmonic(d.mesh, multigrid, d.unknown, never_called, kMultigridTight));
  EXPECT_LT(max_difference(direct, multigrid, d.unknown), 1e-6);
}

TEST(OcclusionFill, MultigridIdenticalWithOneAndTwoThreads) {
  const DiscCase d = disc_case();
  std::vector<Rgba> one = random_known(d.unknown, 11), two = one;
  {
    ThreadLimit limit(1);
    ASSERT_TRUE(fill_harmonic(d.mesh, one, d.unknown, never_called, kMultigridTight));
  }
  {
    ThreadLimit limit(2);
    ASSERT_TRUE(fill_harmonic(d.mesh, two, d.unknown, never_called, kMultigridTight));
  }
  EXPECT_EQ(one, two);
}

// The fill builds a large component's matrix straight in the breadth-first
// order its solver wants, from the couplings (no matrix in row order, no
// renumbered copy): it must be the very system solve_laplace_multigrid
// solves when given the Laplacian assembled here independently, entry by
// entry with Eigen's triplets, and the right-hand side summed in triangle
// order. The same system gives the same bits.
TEST(OcclusionFill, MultigridFillSolvesTheLaplacianAssembledByHand) {
  DiscCase d = disc_case();
  for (std::size_t v = 0; v < d.unknown.size(); ++v) {
    const Float3& p = d.mesh.positions[v];
    d.unknown[v] = std::hypot(p.x - 0.5, p.y - 0.5) < 0.4 ? 1 : 0;  // one component
  }
  const std::vector<Rgba> known = random_known(d.unknown, 5);
  std::vector<int> row(d.unknown.size(), -1);
  int rows = 0;
  for (std::size_t v = 0; v < d.unknown.size(); ++v) {
    if (d.unknown[v]) row[v] = rows++;
  }
  std::vector<Eigen::Triplet<double>> entries;
  ColorColumns b = ColorColumns::Zero(rows, 4);
  for (const auto& tri : d.mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t u = tri[k], w = tri[(k + 1) % 3];
      if (row[u] >= 0 && row[w] >= 0) {
        entries.emplace_back(row[u], row[w], -1.0);
        entries.emplace_back(row[w], row[u], -1.0);
        entries.emplace_back(row[u], row[u], 1.0);
        entries.emplace_back(row[w], row[w], 1.0);
      } else if (row[u] >= 0) {
        entries.emplace_back(row[u], row[u], 1.0);
        for (int c = 0; c < 4; ++c) b(row[u], c) += known[w][c];
      } else if (row[w] >= 0) {
        entries.emplace_back(row[w], row[w], 1.0);
        for (int c = 0; c < 4; ++c) b(row[w], c) += known[u][c];
      }
    }
  }
  LaplaceMatrix laplacian(rows, rows);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  ColorColumns x;
  ASSERT_TRUE(solve_laplace_multigrid(laplacian, b, x, kMultigrid.relative_tolerance));

  std::vector<Rgba> filled = known;
  ASSERT_TRUE(fill_harmonic(d.mesh, filled, d.unknown, never_called, kMultigrid));
  ASSERT_GT(rows, 10000);
  for (std::size_t v = 0; v < d.unknown.size(); ++v) {
    if (!d.unknown[v]) continue;
    for (int c = 0; c < 4; ++c) ASSERT_EQ(filled[v][c], static_cast<float>(x(row[v], c))) << v;
  }
}

// The vertices of `mesh` whose ray away from the centre of its bounding box
// hits the mesh: the shadows of a sphere proxy there, as `bake` tests them.
std::vector<uint8_t> shadowed_from_centre(const MeshData& mesh) {
  Float3 lo = mesh.positions[0], hi = lo;
  for (const Float3& p : mesh.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const Vec3 centre{(lo.x + hi.x) / 2.0, (lo.y + hi.y) / 2.0, (lo.z + hi.z) / 2.0};
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kLow);
  EXPECT_TRUE(scene);
  std::vector<Vec3> points, dirs;
  for (const Float3& p : mesh.positions) {
    points.push_back({p.x, p.y, p.z});
    const Vec3 d{p.x - centre.x, p.y - centre.y, p.z - centre.z};
    dirs.push_back(d / length(d));
  }
  const std::vector<uint8_t> visible = compute_visibility(*scene, points, dirs);
  std::vector<uint8_t> unknown(visible.size());
  for (std::size_t v = 0; v < visible.size(); ++v) unknown[v] = visible[v] ? 0 : 1;
  return unknown;
}

// On real shadows, at the default tolerance: the largest difference stays
// below a third of one 8-bit level (1e-4 in linear light, times 12.92, the
// sRGB encoding's steepest slope, times 255 = 0.33). Measured: 7.2e-6 on
// the 832k armadillo.
void expect_multigrid_matches_direct(const MeshData& mesh) {
  const std::vector<uint8_t> unknown = shadowed_from_centre(mesh);
  const auto count = std::count(unknown.begin(), unknown.end(), 1);
  ASSERT_GT(count, 1000) << "too few shadowed vertices for a meaningful comparison";
  std::vector<Rgba> direct = random_known(unknown, 3), multigrid = direct;
  auto keep = [](uint32_t) { return Rgba{0.5f, 0.5f, 0.5f, 1}; };
  ASSERT_TRUE(fill_harmonic(mesh, direct, unknown, keep, kDirect));
  ASSERT_TRUE(fill_harmonic(mesh, multigrid, unknown, keep, kMultigrid));
  EXPECT_LT(max_difference(direct, multigrid, unknown), 1e-4);
}

MeshData data_mesh(const char* file) {
  Expected<LoadedMesh> loaded = read_mesh(std::string(TEXBAKE_DATA_DIR) + "/" + file);
  EXPECT_TRUE(loaded) << loaded.error().message;
  return std::move(loaded->mesh);
}

TEST(OcclusionFillData, MultigridAgreesWithTheDirectSolveOnTheBunny) {
  expect_multigrid_matches_direct(data_mesh("bunny00.off"));
}

TEST(OcclusionFillData, MultigridAgreesWithTheDirectSolveOnTheArmadillo832k) {
  expect_multigrid_matches_direct(test::subdivide(test::subdivide(data_mesh("armadillo.off"))));
}

// Issue #28 item 14: a mesh split at seams (here the extreme, flat-shaded
// case: every triangle its own three vertices, as Blender writes a flat
// GLB) is filled as the welded mesh is. Its graph, welded by position, is
// the same graph with the same edge weights, so every copy gets its
// point's colour in the welded fill (to rounding: the rows are numbered
// in another order); none is left unfilled where the welded mesh fills.
// Without the weld every triangle of three shadowed vertices was a
// component of its own with no known vertex: all of them fell back.
// A copy marked unknown of a point whose other copies are known takes
// their colour.
TEST(OcclusionFillData, FlatSplitMeshFillsAsTheWeldedMesh) {
  const MeshData welded = data_mesh("bunny00.off");
  const std::vector<uint8_t> unknown = shadowed_from_centre(welded);
  ASSERT_GT(std::count(unknown.begin(), unknown.end(), 1), 1000);
  std::vector<Rgba> expected = random_known(unknown, 5);
  auto fallback = [](uint32_t) { return Rgba{-1, -1, -1, -1}; };  // marks a fallback
  Expected<FillResult> w = fill_harmonic(welded, expected, unknown, fallback, kDirect);
  ASSERT_TRUE(w);

  MeshData split;
  std::vector<uint32_t> source;
  for (const auto& tri : welded.triangles) {
    const auto first = static_cast<uint32_t>(split.positions.size());
    for (uint32_t v : tri) split.positions.push_back(welded.positions[v]), source.push_back(v);
    split.triangles.push_back({first, first + 1, first + 2});
  }
  test::faces_from_triangles(split);
  std::vector<uint8_t> split_unknown(source.size());
  std::vector<Rgba> colors(source.size());
  const std::vector<Rgba> known = random_known(unknown, 5);
  for (std::size_t c = 0; c < source.size(); ++c) {
    split_unknown[c] = unknown[source[c]];
    colors[c] = known[source[c]];
  }
  // One copy of a known point (the first known vertex's first copy) marked unknown.
  const auto marked = static_cast<std::size_t>(
      std::find(split_unknown.begin(), split_unknown.end(), 0) - split_unknown.begin());
  split_unknown[marked] = 1;
  colors[marked] = {0, 0, 0, 0};

  Expected<FillResult> f = fill_harmonic(split, colors, split_unknown, fallback, kDirect);
  ASSERT_TRUE(f);
  std::size_t copies_unfilled = 0;
  for (std::size_t c = 0; c < source.size(); ++c) {
    if (unknown[source[c]] && expected[source[c]][0] == -1) ++copies_unfilled;
  }
  EXPECT_EQ(f->unfilled, copies_unfilled);  // only where the welded mesh falls back too
  EXPECT_EQ(f->filled + f->unfilled,
            static_cast<std::size_t>(std::count(split_unknown.begin(), split_unknown.end(), 1)));
  double worst = 0;
  for (std::size_t c = 0; c < source.size(); ++c) {
    for (int k = 0; k < 4; ++k) {
      worst = std::max(worst, std::abs(double(colors[c][k]) - expected[source[c]][k]));
    }
  }
  EXPECT_LT(worst, 1e-5);
  EXPECT_EQ(colors[marked], known[source[marked]]);
}

}  // namespace
}  // namespace texbake
