// read_mesh: every input format, polygons, non-manifold input, vertex order,
// attributes. Expected values are worked out by hand from the small inline
// files (or from the data README for the shared meshes).
#include "mesh_io/read_mesh.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>

#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

using test::fresh_temp_dir;
using test::write_text;
namespace fs = std::filesystem;

class ReadMesh : public ::testing::Test {
 protected:
  fs::path dir = fresh_temp_dir("read");
  void TearDown() override { fs::remove_all(dir); }

  LoadedMesh load(const std::string& name, const std::string& text) {
    Expected<LoadedMesh> m = read_mesh(write_text(dir / name, text));
    EXPECT_TRUE(m.has_value()) << (m ? "" : m.error().message);
    return m ? std::move(*m) : LoadedMesh{};
  }
};

double triangle_area(const MeshData& m, const std::array<uint32_t, 3>& t) {
  const Float3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
  return 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
}

TEST_F(ReadMesh, EdgeSharedByThreeTrianglesKeepsAllThreeFaces) {
  // Edge 0-1 is shared by three triangles (a "book" of three pages).
  auto m = load("book.off",
                "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 -1 0\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  EXPECT_EQ(m.mesh.face_count(), 3u);
  EXPECT_EQ(m.mesh.triangles.size(), 3u);
  EXPECT_EQ(m.issues.non_manifold_edges, 1u);
  EXPECT_EQ(m.issues.degenerate_triangles, 0u);
  const std::vector<uint32_t> expected = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  EXPECT_EQ(m.mesh.face_vertices, expected);
}

TEST_F(ReadMesh, VertexOrderAndCountKeptWithUnreferencedVertices) {
  auto m = load("unref.off", "OFF\n5 1 0\n9 9 9\n0 0 0\n7 7 7\n1 0 0\n0 1 0\n3 1 3 4\n");
  ASSERT_EQ(m.mesh.vertex_count(), 5u);
  EXPECT_EQ(m.mesh.positions[0].x, 9.f);
  EXPECT_EQ(m.mesh.positions[2].y, 7.f);
  EXPECT_EQ(m.mesh.positions[3].x, 1.f);
  EXPECT_EQ(m.issues.unreferenced_vertices, 2u);
  ASSERT_EQ(m.mesh.triangles.size(), 1u);
  EXPECT_EQ(m.mesh.triangles[0], (std::array<uint32_t, 3>{1, 3, 4}));
}

TEST_F(ReadMesh, QuadIsTriangulatedAndKeptAsOneFace) {
  auto m = load("quad.off", "OFF\n4 1 0\n0 0 0\n2 0 0\n2 1 0\n0 1 0\n4 0 1 2 3\n");
  EXPECT_EQ(m.mesh.face_count(), 1u);
  ASSERT_EQ(m.mesh.triangles.size(), 2u);
  double area = 0;
  for (const auto& t : m.mesh.triangles) area += triangle_area(m.mesh, t);
  EXPECT_DOUBLE_EQ(area, 2.0);
  EXPECT_EQ(m.mesh.triangle_face, (std::vector<uint32_t>{0, 0}));
}

TEST_F(ReadMesh, NonConvexPolygonIsEarClippedWithoutOverlap) {
  // An L-shaped hexagon made of three unit squares: area 3. A fan from
  // vertex 0 would cover the notch (area 4 would show as overlap/outside).
  auto m = load("l.obj", "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n");
  ASSERT_EQ(m.mesh.triangles.size(), 4u);
  double area = 0;
  for (const auto& t : m.mesh.triangles) {
    area += triangle_area(m.mesh, t);
    // Every triangle keeps the polygon's counter-clockwise orientation (+z).
    const Float3 a = m.mesh.positions[t[0]], b = m.mesh.positions[t[1]], c = m.mesh.positions[t[2]];
    EXPECT_GT((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x), 0);
  }
  EXPECT_DOUBLE_EQ(area, 3.0);
}

TEST_F(ReadMesh, AllDegenerateMeshLoadsWithEveryTriangleCounted) {
  Expected<LoadedMesh> m = read_mesh(test::bad_dir() / "all_degenerate.off");
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->mesh.face_count(), 2u);
  EXPECT_TRUE(m->mesh.triangles.empty());
  EXPECT_EQ(m->issues.degenerate_triangles, 2u);
}

TEST_F(ReadMesh, ObjWithUvsNormalsColoursAndMaterial) {
  write_text(dir / "m.mtl", "newmtl paint\nKd 1 1 1\nmap_Kd tex/paint.png\n");
  auto m = load("m.obj",
                "mtllib m.mtl\n"
                "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 0.25 0.5 0.75\n"
                "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                "usemtl paint\nf 1/1/1 2/2/1 3/3/1 4/4/1\n");
  ASSERT_EQ(m.mesh.vertex_count(), 4u);
  EXPECT_EQ(m.mesh.face_count(), 1u);
  EXPECT_EQ(m.mesh.triangles.size(), 2u);
  ASSERT_TRUE(m.mesh.has_uvs());
  ASSERT_EQ(m.mesh.corner_uv.size(), 4u);
  EXPECT_EQ(m.mesh.uvs[m.mesh.corner_uv[2]].u, 1.f);
  EXPECT_EQ(m.mesh.uvs[m.mesh.corner_uv[2]].v, 1.f);
  EXPECT_EQ(m.mesh.uvs[m.mesh.corner_uv[3]].u, 0.f);
  EXPECT_EQ(m.mesh.uvs[m.mesh.corner_uv[3]].v, 1.f);
  ASSERT_EQ(m.mesh.corner_normal.size(), 4u);
  EXPECT_EQ(m.mesh.normals[m.mesh.corner_normal[1]].z, 1.f);
  ASSERT_TRUE(m.mesh.has_vertex_colors());
  EXPECT_EQ(m.mesh.vertex_colors[1], (std::array<float, 4>{0, 1, 0, 1}));
  EXPECT_EQ(m.mesh.vertex_colors[3], (std::array<float, 4>{0.25f, 0.5f, 0.75f, 1}));
  EXPECT_EQ(fs::path(m.mesh.texture_path), (dir / "tex" / "paint.png").lexically_normal());
  // Every corner has its vt: the table is the file's four, no (0, 0) added
  // for corners without one (it used to end every OBJ written back).
  EXPECT_EQ(m.mesh.uvs.size(), 4u);
}

TEST_F(ReadMesh, ObjCornersWithoutUvShareOneAddedZeroUv) {
  auto m = load("partial.obj",
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.5 0.5\n"
                "f 1/1 2/1 3/1\nf 1 3 4\n");
  ASSERT_TRUE(m.mesh.has_uvs());
  ASSERT_EQ(m.mesh.corner_uv.size(), 6u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(m.mesh.uvs[m.mesh.corner_uv[c]].u, 0.5f) << c;
    EXPECT_EQ(m.mesh.uvs[m.mesh.corner_uv[c]].v, 0.5f) << c;
  }
  // The bare face's corners share one added (0, 0), and it is the only one.
  for (int c = 3; c < 6; ++c) EXPECT_EQ(m.mesh.corner_uv[c], m.mesh.corner_uv[3]) << c;
  EXPECT_EQ(m.mesh.uvs[m.mesh.corner_uv[3]].u, 0.f);
  EXPECT_EQ(m.mesh.uvs[m.mesh.corner_uv[3]].v, 0.f);
  std::size_t zeros = 0;
  for (const Float2& uv : m.mesh.uvs) zeros += (uv.u == 0.f && uv.v == 0.f) ? 1 : 0;
  EXPECT_EQ(zeros, 1u);
}

TEST_F(ReadMesh, ObjNegativeIndicesAreRelative) {
  // -1 is the last vertex defined so far: f -3 -2 -1 is f 1 2 3 here.
  auto m = load("rel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n");
  EXPECT_EQ(m.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST_F(ReadMesh, PlyAsciiFloatColoursKeptExactly) {
  auto m = load("c.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nproperty float red\nproperty float green\nproperty float blue\n"
                "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                "0 0 0 0.5 0.25 1\n1 0 0 0 0 0\n0 1 0 1 1 1\n3 0 1 2\n");
  ASSERT_TRUE(m.mesh.has_vertex_colors());
  EXPECT_EQ(m.mesh.vertex_colors[0], (std::array<float, 4>{0.5f, 0.25f, 1, 1}));
}

// Binary big-endian PLY with double coordinates, uchar colours with alpha, a
// quad and an extra element, assembled by hand.
TEST_F(ReadMesh, PlyBinaryBigEndianWithColoursAndQuad) {
  std::string s =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property uchar alpha\nelement face 1\nproperty list uchar uint vertex_indices\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  auto be = [&](const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) s += static_cast<const char*>(p)[n - 1 - i];
  };
  const double xyz[4][3] = {{0, 0, 0}, {3, 0, 0}, {3, 2, 0}, {0, 2, 0}};
  const unsigned char rgba[4][4] = {
      {255, 0, 0, 255}, {0, 255, 0, 128}, {0, 0, 255, 0}, {51, 102, 153, 255}};
  for (int v = 0; v < 4; ++v) {
    for (double c : xyz[v]) be(&c, 8);
    for (unsigned char c : rgba[v]) s += static_cast<char>(c);
  }
  s += static_cast<char>(4);
  for (uint32_t i : {0u, 1u, 2u, 3u}) be(&i, 4);
  for (int32_t i : {0, 1}) be(&i, 4);
  auto m = load("be.ply", s);
  ASSERT_EQ(m.mesh.vertex_count(), 4u);
  EXPECT_EQ(m.mesh.positions[2].x, 3.f);
  EXPECT_EQ(m.mesh.positions[2].y, 2.f);
  EXPECT_EQ(m.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(m.mesh.triangles.size(), 2u);
  EXPECT_EQ(m.mesh.vertex_colors[1][3], 128 / 255.f);
  EXPECT_EQ(m.mesh.vertex_colors[3][0], 51 / 255.f);
  EXPECT_EQ(m.mesh.vertex_colors[3][2], 153 / 255.f);
}

TEST_F(ReadMesh, StlAsciiAndBinaryMergeCorners) {
  const std::string ascii =
      "solid sq\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 "
      "0\nendloop\n"
      "endfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 "
      "0\nendloop\n"
      "endfacet\nendsolid sq\n";
  auto a = load("a.stl", ascii);
  EXPECT_EQ(a.mesh.face_count(), 2u);
  EXPECT_EQ(a.mesh.vertex_count(), 4u);  // STL repeats corners; OpenMesh merges equal ones
  EXPECT_EQ(a.mesh.triangles.size(), 2u);

  std::string bin(80, '\0');
  auto put = [&](const void* p, std::size_t n) { bin.append(static_cast<const char*>(p), n); };
  const uint32_t count = 2;
  put(&count, 4);
  const float tris[2][12] = {{0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0},
                             {0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1, 0}};
  for (const auto& t : tris) {
    put(t, 48);
    bin += std::string(2, '\0');
  }
  auto b = load("b.stl", bin);
  EXPECT_EQ(b.mesh.face_count(), 2u);
  EXPECT_EQ(b.mesh.vertex_count(), 4u);
  EXPECT_EQ(b.mesh.triangles.size(), 2u);
}

// Shared data: counts from data/README.md.
TEST(ReadMeshData, BunnyCountsMatchTheReadme) {
  Expected<LoadedMesh> m = read_mesh(fs::path(TEXBAKE_DATA_DIR) / "bunny00.off");
  ASSERT_TRUE(m.has_value()) << m.error().message;
  EXPECT_EQ(m->mesh.vertex_count(), 37706u);
  EXPECT_EQ(m->mesh.face_count(), 75408u);
  EXPECT_EQ(m->mesh.triangles.size() + m->issues.degenerate_triangles, 75408u);
}

TEST(ReadMeshData, SuzanneQuadsWithUvs) {
  const fs::path path = fs::path(TEXBAKE_DATA_DIR) / "suzanne_uv.obj";
  // Count faces and expected triangles independently from the text.
  std::istringstream text(test::read_bytes(path));
  std::string line;
  std::size_t faces = 0, fan_triangles = 0, v_lines = 0;
  while (std::getline(text, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "v") ++v_lines;
    if (key != "f") continue;
    std::size_t corners = 0;
    for (std::string tok; ls >> tok;) ++corners;
    ++faces;
    fan_triangles += corners - 2;
  }
  Expected<LoadedMesh> m = read_mesh(path);
  ASSERT_TRUE(m.has_value()) << m.error().message;
  EXPECT_EQ(m->mesh.vertex_count(), v_lines);
  EXPECT_EQ(m->mesh.face_count(), faces);
  EXPECT_EQ(m->mesh.triangles.size() + m->issues.degenerate_triangles, fan_triangles);
  EXPECT_TRUE(m->mesh.has_uvs());
  EXPECT_EQ(m->mesh.corner_uv.size(), m->mesh.face_vertices.size());
}

// A mesh big enough for every block and vertex range of triangulate_faces'
// parallel passes (16384 faces, 1024 vertices): a 150 x 150 grid of quads,
// most split in two triangles, some kept as quads, some given a repeated
// corner, plus "fins" (a triangle on an existing edge) that make edges of 3
// and 4 faces, and unreferenced vertices; vertex numbers shuffled so that
// edges join far-apart ranges.
MeshData big_mixed_mesh() {
  constexpr uint32_t n = 150;
  std::mt19937 rng(7);
  const uint32_t grid = (n + 1) * (n + 1), extra = 3000, unused = 50;
  std::vector<uint32_t> perm(grid + extra + unused);
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), rng);
  MeshData m;
  m.positions.resize(perm.size());
  auto at = [&](uint32_t i, uint32_t j) { return perm[j * (n + 1) + i]; };
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i) m.positions[at(i, j)] = {float(i), float(j), 0.f};
  for (uint32_t k = 0; k < extra + unused; ++k)
    m.positions[perm[grid + k]] = {float(k % 97), float(k % 89), 1.f + float(k % 7)};
  m.face_offsets = {0};
  auto face = [&](std::initializer_list<uint32_t> vs) {
    m.face_vertices.insert(m.face_vertices.end(), vs);
    m.face_offsets.push_back(static_cast<uint32_t>(m.face_vertices.size()));
  };
  std::vector<std::pair<uint32_t, uint32_t>> edges;  // grid edges, for the fins
  for (uint32_t j = 0; j < n; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      const uint32_t kind = (i * 7 + j * 3) % 11;
      if (kind == 0) {
        face({a, b, c, d});  // convex quad: fanned
      } else if (kind == 1) {
        face({a, b, b});  // repeated corner: degenerate
        face({a, c, d});
      } else if (kind == 2) {
        face({a, b});  // two corners: degenerate, its edge still counts
        face({a, b, c});
        face({a, c, d});
      } else {
        face({a, b, c});
        face({a, c, d});
      }
      edges.emplace_back(a, b);
    }
  }
  for (uint32_t k = 0; k < extra; ++k) {
    const auto& [a, b] = edges[(k * 7919u) % edges.size()];
    face({b, a, perm[grid + k]});
  }
  return m;
}

TEST(TriangulateFaces, BigMeshMatchesAOneByOneTriangulationAndAnEdgeMap) {
  MeshData m = big_mixed_mesh();
  ASSERT_GT(m.face_count(), 2u * 16384u);
  // Expected, face by face: triangles in order; quads (convex here) fanned
  // from their first corner; repeated vertices and faces under three corners
  // skipped and counted. The fins stand at z > 0 over grid edges, so none
  // is degenerate.
  std::vector<std::array<uint32_t, 3>> corners;
  std::vector<uint32_t> faces;
  std::size_t degenerate = 0;
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const uint32_t first = m.face_offsets[f], count = m.face_offsets[f + 1] - first;
    if (count < 3) {
      ++degenerate;
      continue;
    }
    for (uint32_t k = 1; k + 1 < count; ++k) {
      const std::array<uint32_t, 3> t{first, first + k, first + k + 1};
      const uint32_t a = m.face_vertices[t[0]], b = m.face_vertices[t[1]],
                     c = m.face_vertices[t[2]];
      if (a == b || b == c || a == c) {
        ++degenerate;
      } else {
        corners.push_back(t);
        faces.push_back(f);
      }
    }
  }
  std::map<std::pair<uint32_t, uint32_t>, int> edge_faces;
  std::vector<bool> used(m.vertex_count(), false);
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const uint32_t b = m.face_offsets[f], e = m.face_offsets[f + 1];
    for (uint32_t c = b; c < e; ++c) {
      const uint32_t v0 = m.face_vertices[c], v1 = m.face_vertices[c + 1 < e ? c + 1 : b];
      used[v0] = true;
      if (v0 != v1) ++edge_faces[{std::min(v0, v1), std::max(v0, v1)}];
    }
  }
  const auto non_manifold = static_cast<std::size_t>(std::count_if(
      edge_faces.begin(), edge_faces.end(), [](const auto& e) { return e.second > 2; }));
  ASSERT_GT(non_manifold, 1000u);  // fins and two-corner faces on grid edges

  for (int threads : {1, 2, 3, 8}) {
    MeshData run = m;
    tbb::task_arena arena(threads);
    const MeshIssues issues = arena.execute([&] { return triangulate_faces(run); });
    SCOPED_TRACE(threads);
    EXPECT_EQ(issues.degenerate_triangles, degenerate);
    EXPECT_EQ(issues.unreferenced_vertices, 50u);
    EXPECT_EQ(issues.unreferenced_vertices,
              static_cast<std::size_t>(std::count(used.begin(), used.end(), false)));
    EXPECT_EQ(issues.non_manifold_edges, non_manifold);
    ASSERT_EQ(run.triangle_corners, corners);
    EXPECT_EQ(run.triangle_face, faces);
    ASSERT_EQ(run.triangles.size(), corners.size());
    for (std::size_t t = 0; t < corners.size(); ++t) {
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(run.triangles[t][k], m.face_vertices[corners[t][k]]) << t;
    }
  }
}

// The usual binary PLY face list (uchar count, int or uint indices, this
// machine's byte order) has its own loop: the same faces as the general
// loop reads from the big-endian and ushort-count forms of the same file.
TEST_F(ReadMesh, BinaryPlyFaceListsReadTheSameInEveryForm) {
  // Without its faces of two corners (the reader's size check before
  // allocating counts three indices a face).
  const MeshData src = [] {
    const MeshData big = big_mixed_mesh();
    MeshData m;
    m.positions = big.positions;
    m.face_offsets = {0};
    for (std::size_t f = 0; f < big.face_count(); ++f) {
      if (big.face_offsets[f + 1] - big.face_offsets[f] < 3) continue;
      m.face_vertices.insert(m.face_vertices.end(), big.face_vertices.begin() + big.face_offsets[f],
                             big.face_vertices.begin() + big.face_offsets[f + 1]);
      m.face_offsets.push_back(static_cast<uint32_t>(m.face_vertices.size()));
    }
    return m;
  }();
  auto write = [&](const MeshData& mesh, const std::string& name, bool big, const char* count,
                   const char* index) {
    const fs::path path = dir / name;
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat " << (big ? "binary_big_endian" : "binary_little_endian")
        << " 1.0\nelement vertex " << mesh.vertex_count()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
        << mesh.face_count() << "\nproperty list " << count << " " << index
        << " vertex_indices\nend_header\n";
    auto put = [&](const void* p, std::size_t size) {
      char bytes[4];
      std::memcpy(bytes, p, size);
      if (big) std::reverse(bytes, bytes + size);
      out.write(bytes, static_cast<std::streamsize>(size));
    };
    for (const Float3& p : mesh.positions) put(&p.x, 4), put(&p.y, 4), put(&p.z, 4);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
      if (std::strcmp(count, "uchar") == 0) {
        const auto k = static_cast<uint8_t>(e - b);
        put(&k, 1);
      } else {
        const auto k = static_cast<uint16_t>(e - b);
        put(&k, 2);
      }
      for (uint32_t c = b; c < e; ++c) put(&mesh.face_vertices[c], 4);
    }
    return path;
  };
  for (const auto& [name, big, count, index] : {std::tuple{"le_int.ply", false, "uchar", "int"},
                                                {"le_uint.ply", false, "uchar", "uint"},
                                                {"be_int.ply", true, "uchar", "int"},
                                                {"le_ushort.ply", false, "ushort", "int"}}) {
    SCOPED_TRACE(name);
    Expected<LoadedMesh> m = read_mesh(write(src, name, big, count, index));
    ASSERT_TRUE(m.has_value()) << m.error().message;
    EXPECT_EQ(m->mesh.face_offsets, src.face_offsets);
    EXPECT_EQ(m->mesh.face_vertices, src.face_vertices);
    ASSERT_EQ(m->mesh.vertex_count(), src.vertex_count());
    EXPECT_EQ(m->mesh.positions[123].x, src.positions[123].x);
  }
  // An index past the vertices, read as int and as uint.
  MeshData bad = src;
  bad.face_vertices[7] = static_cast<uint32_t>(src.vertex_count());
  const auto face_of_7 = std::upper_bound(src.face_offsets.begin(), src.face_offsets.end(), 7u) -
                         src.face_offsets.begin() - 1;
  const std::string message = "face " + std::to_string(face_of_7) + " refers to vertex " +
                              std::to_string(src.vertex_count()) + " but there are " +
                              std::to_string(src.vertex_count());
  for (const char* index : {"int", "uint"}) {
    Expected<LoadedMesh> m =
        read_mesh(write(bad, std::string("bad_") + index + ".ply", false, "uchar", index));
    ASSERT_FALSE(m.has_value());
    EXPECT_NE(m.error().message.find(message), std::string::npos) << m.error().message;
  }

  // Every other bad or odd case gives the fast loop's file (uchar count)
  // the general loop's outcome (ushort count), message for message: indices
  // of -1 and 2^31 as int and uint, a file cut inside a list and just after
  // a count, and an empty face.
  auto outcome = [&](const fs::path& path) {
    Expected<LoadedMesh> m = read_mesh(path);
    if (m) return std::string("ok ") + std::to_string(m->mesh.face_vertices.size());
    const std::string& e = m.error().message;
    return e.substr(e.find(".ply: ") + 6);  // without the file's name
  };
  auto cut = [](const fs::path& path, std::uintmax_t bytes) {
    fs::resize_file(path, fs::file_size(path) - bytes);
    return path;
  };
  for (const char* index : {"int", "uint"}) {
    for (uint32_t value : {0xFFFFFFFFu, 0x80000000u}) {
      bad.face_vertices[7] = value;
      const std::string name = std::string(index) + std::to_string(value);
      const std::string fast = outcome(write(bad, name + "_c.ply", false, "uchar", index));
      EXPECT_EQ(fast, outcome(write(bad, name + "_s.ply", false, "ushort", index)));
      EXPECT_NE(fast.find("refers to vertex " +
                          std::to_string(std::strcmp(index, "int") == 0
                                             ? static_cast<long long>(static_cast<int32_t>(value))
                                             : static_cast<long long>(value))),
                std::string::npos)
          << fast;
    }
    // The last face is a triangle: 2 bytes off cuts its last index, 12 its
    // whole list (the count read, no index).
    for (std::uintmax_t bytes : {2u, 12u}) {
      const std::string name = std::string("cut") + index + std::to_string(bytes);
      const std::string fast = cut(write(src, name + "_c.ply", false, "uchar", index), bytes);
      const std::string fast_outcome = outcome(fast);
      EXPECT_EQ(fast_outcome,
                outcome(cut(write(src, name + "_s.ply", false, "ushort", index), bytes)));
      EXPECT_NE(fast_outcome.find("truncated: the file ends in face " +
                                  std::to_string(src.face_count() - 1) + " of " +
                                  std::to_string(src.face_count())),
                std::string::npos)
          << fast_outcome;
    }
  }
  ASSERT_EQ(src.face_offsets[src.face_count()] - src.face_offsets[src.face_count() - 1], 3u);
  MeshData with_empty = src;
  with_empty.face_offsets.insert(with_empty.face_offsets.begin() + 5, with_empty.face_offsets[5]);
  Expected<LoadedMesh> empty_fast =
      read_mesh(write(with_empty, "empty_c.ply", false, "uchar", "int"));
  Expected<LoadedMesh> empty_general =
      read_mesh(write(with_empty, "empty_s.ply", false, "ushort", "int"));
  ASSERT_TRUE(empty_fast.has_value()) << empty_fast.error().message;
  ASSERT_TRUE(empty_general.has_value()) << empty_general.error().message;
  EXPECT_EQ(empty_fast->mesh.face_offsets, with_empty.face_offsets);
  EXPECT_EQ(empty_general->mesh.face_offsets, with_empty.face_offsets);
  EXPECT_EQ(empty_fast->issues.degenerate_triangles, empty_general->issues.degenerate_triangles);
}

}  // namespace
}  // namespace texbake
