// STL (issue #12 item 2): ASCII STL parsed strictly (every keyword in order,
// every number a finite decimal float; errors name the file and line), binary
// STL checked for its size and for non-finite corners. Expected values are
// worked out by hand from the small generated files; coordinates are written
// in the file as decimal text and compared with the same decimal literals
// rounded to float by the compiler.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "mesh_io/read_mesh.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using test::write_text;

// One facet; its lines are numbered in the comments of the tests below.
std::string facet(const std::string& a, const std::string& b, const std::string& c) {
  return "  facet normal 0 0 1\n    outer loop\n      vertex " + a + "\n      vertex " + b +
         "\n      vertex " + c + "\n    endloop\n  endfacet\n";
}

class ReadStl : public ::testing::Test {
 protected:
  fs::path dir = test::fresh_temp_dir("stl");
  void TearDown() override { fs::remove_all(dir); }

  // The message of the error read_mesh gives for `bytes` saved as `name`;
  // checks that it is kParse and starts with the file's path.
  std::string error_of(const std::string& name, const std::string& bytes) {
    const fs::path path = write_text(dir / name, bytes);
    Expected<LoadedMesh> m = read_mesh(path);
    EXPECT_FALSE(m.has_value()) << name << " was accepted";
    if (m) return {};
    EXPECT_EQ(m.error().code, ErrorCode::kParse) << m.error().message;
    EXPECT_EQ(m.error().message.rfind(path.string() + ": ", 0), 0u) << m.error().message;
    return m.error().message.substr(path.string().size() + 2);
  }
  LoadedMesh load(const std::string& name, const std::string& bytes) {
    Expected<LoadedMesh> m = read_mesh(write_text(dir / name, bytes));
    EXPECT_TRUE(m.has_value()) << (m ? "" : m.error().message);
    return m ? std::move(*m) : LoadedMesh{};
  }
};

void expect_position(const Float3& p, float x, float y, float z) {
  EXPECT_EQ(p.x, x);
  EXPECT_EQ(p.y, y);
  EXPECT_EQ(p.z, z);
}

TEST_F(ReadStl, AsciiCoordinatesAreReadExactly) {
  // Three facets on four corners, written in different decimal forms; "-0"
  // is the same corner as "0" (OpenMesh's merge rule, kept), vertices are
  // numbered in order of first appearance.
  const LoadedMesh m =
      load("good.stl", "solid good part\n" + facet("0.5 -1.25 3e2", "0.1 +2 .5", "0 0 -0") +
                           facet("0.1 +2 .5", "0.5 -1.25 3e2", "1.E1 -0 0") +
                           facet("-0 0 0", "1.E1 0 0", "0.5 -1.25 300") + "endsolid good part\n");
  ASSERT_EQ(m.mesh.vertex_count(), 4u);
  expect_position(m.mesh.positions[0], 0.5f, -1.25f, 300.f);
  expect_position(m.mesh.positions[1], 0.1f, 2.f, 0.5f);
  expect_position(m.mesh.positions[2], 0.f, 0.f, 0.f);
  expect_position(m.mesh.positions[3], 10.f, 0.f, 0.f);
  EXPECT_EQ(m.mesh.face_offsets, (std::vector<uint32_t>{0, 3, 6, 9}));
  EXPECT_EQ(m.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 1, 0, 3, 2, 3, 0}));
  EXPECT_EQ(m.mesh.triangles.size(), 3u);
  EXPECT_FALSE(m.mesh.has_uvs());
  EXPECT_TRUE(m.mesh.normals.empty());
}

TEST_F(ReadStl, AsciiKeywordsInAnyCaseCrlfAndSeveralSolids) {
  const LoadedMesh m = load("mixed.stl",
                            "SOLID a\r\nFACET NORMAL 0 0 1\r\nOUTER LOOP\r\nVERTEX 0 0 0\r\n"
                            "VERTEX 1 0 0\r\nVERTEX 0 1 0\r\nENDLOOP\r\nENDFACET\r\nENDSOLID a\r\n"
                            "solid b\n" +
                                facet("1 0 0", "1 1 0", "0 1 0") + "endsolid b\n");
  ASSERT_EQ(m.mesh.vertex_count(), 4u);
  expect_position(m.mesh.positions[3], 1.f, 1.f, 0.f);
  EXPECT_EQ(m.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
}

TEST_F(ReadStl, SolidNamedOuterIsNotATriangle) {
  // OpenMesh's reader started a triangle at any line containing "outer".
  const LoadedMesh m =
      load("outer.stl", "solid outer_shell\n" + facet("0 0 0", "2 0 0", "0 3 0") + "endsolid\n");
  ASSERT_EQ(m.mesh.vertex_count(), 3u);
  expect_position(m.mesh.positions[1], 2.f, 0.f, 0.f);
  expect_position(m.mesh.positions[2], 0.f, 3.f, 0.f);
  EXPECT_EQ(m.mesh.face_count(), 1u);
}

TEST_F(ReadStl, AsciiTriangleRepeatingACornerIsDropped) {
  // As OpenMesh's reader does: the second facet has corner (0,0,0) twice.
  const LoadedMesh m = load("rep.stl", "solid\n" + facet("0 0 0", "1 0 0", "0 1 0") +
                                           facet("0 0 0", "1 1 0", "0 0 0") + "endsolid\n");
  EXPECT_EQ(m.mesh.face_count(), 1u);
  EXPECT_EQ(m.mesh.vertex_count(), 4u);  // (1,1,0) is still a vertex, unreferenced
  EXPECT_EQ(m.issues.unreferenced_vertices, 1u);
}

// Lines of "solid s\n" + facet(...): 1 solid, 2 facet normal, 3 outer loop,
// 4-6 vertex, 7 endloop, 8 endfacet; a second facet starts at line 9.
TEST_F(ReadStl, NanCoordinateNamesTheLine) {
  EXPECT_EQ(error_of("nan.stl", "solid s\n" + facet("0 0 0", "1 nan 0", "0 1 0") + "endsolid\n"),
            "line 5: facet 0: vertex coordinate 'nan' is not a finite decimal number within "
            "float range");
}

TEST_F(ReadStl, GarbageCoordinateNamesTheLine) {
  EXPECT_EQ(error_of("zz.stl", "solid s\n" + facet("0 0 0", "1 0 0", "0 1 0") +
                                   facet("0 0 0", "1 0 0", "0 1 zz") + "endsolid\n"),
            "line 13: facet 1: vertex coordinate 'zz' is not a finite decimal number within "
            "float range");
}

TEST_F(ReadStl, CoordinateAboveFloatRangeNamesTheLine) {
  // 1e39 is above FLT_MAX (3.4028235e38, which is accepted).
  EXPECT_EQ(error_of("big.stl", "solid s\n" + facet("1e39 0 0", "1 0 0", "0 1 0") + "endsolid\n"),
            "line 4: facet 0: vertex coordinate '1e39' is not a finite decimal number within "
            "float range");
  const LoadedMesh m =
      load("max.stl", "solid s\n" + facet("3.4028235e38 0 0", "1 0 0", "0 1 0") + "endsolid\n");
  ASSERT_EQ(m.mesh.vertex_count(), 3u);
  EXPECT_EQ(m.mesh.positions[0].x, 3.4028235e38f);
}

TEST_F(ReadStl, HexAndInfinityAreNotDecimalNumbers) {
  EXPECT_EQ(error_of("hex.stl", "solid s\n" + facet("0x1p3 0 0", "1 0 0", "0 1 0") + "endsolid\n"),
            "line 4: facet 0: vertex coordinate '0x1p3' is not a finite decimal number within "
            "float range");
  EXPECT_EQ(error_of("inf.stl", "solid s\nfacet normal inf 0 0\n"),
            "line 2: facet 0: facet normal component 'inf' is not a finite decimal number within "
            "float range");
}

TEST_F(ReadStl, TruncatedFileNamesTheLastLine) {
  // Cut after the second vertex line of the only facet.
  const std::string whole = "solid s\n" + facet("0 0 0", "1 0 0", "0 1 0");
  EXPECT_EQ(error_of("cut.stl", whole.substr(0, whole.find("vertex 0 1 0"))),
            "line 5: facet 0: truncated: the file ends before 'vertex'");
  // Cut in the middle of a vertex's numbers.
  EXPECT_EQ(error_of("cut2.stl", whole.substr(0, whole.find("1 0 0") + 3)),
            "line 5: facet 0: truncated: the file ends before a vertex coordinate");
  // Complete facets but no endsolid.
  EXPECT_EQ(error_of("noend.stl", whole), "line 8: truncated: the file ends before 'endsolid'");
}

TEST_F(ReadStl, MissingVertexLineNamesTheLine) {
  const std::string text =
      "solid s\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n"
      "      vertex 1 0 0\n    endloop\n  endfacet\nendsolid\n";
  EXPECT_EQ(error_of("two.stl", text),
            "line 6: facet 0: expected 'vertex' (a facet has 3 vertices), got 'endloop'");
}

TEST_F(ReadStl, WrongKeywordsNameTheLine) {
  EXPECT_EQ(error_of("a.stl", "solid s\n  facet 0 0 1\n"),
            "line 2: facet 0: expected 'normal' after 'facet', got '0'");
  EXPECT_EQ(error_of("b.stl", "solid s\n" + facet("0 0 0", "1 0 0", "0 1 0 0") + "endsolid\n"),
            "line 6: facet 0: expected 'endloop' after the third vertex, got '0'");
  EXPECT_EQ(error_of("c.stl", "solid s\nvertex 0 0 0\n"),
            "line 2: expected 'facet' or 'endsolid', got 'vertex'");
  EXPECT_EQ(error_of("d.stl", "solid s\nendsolid s\nleftover\n"),
            "line 3: expected 'solid' or the end of the file after 'endsolid', got 'leftover'");
}

TEST_F(ReadStl, AsciiWithoutFacetsHasNoFaces) {
  EXPECT_EQ(error_of("empty.stl", "solid empty\nendsolid empty\n"), "the mesh has no faces");
}

// --- binary -----------------------------------------------------------------

std::string binary_stl(const std::string& header, const std::vector<std::array<float, 9>>& tris) {
  std::string bin = header;
  bin.resize(80, '\0');
  const uint32_t count = static_cast<uint32_t>(tris.size());
  for (int i = 0; i < 4; ++i) bin += static_cast<char>((count >> (8 * i)) & 0xff);
  for (const auto& t : tris) {
    const float normal[3] = {0, 0, 1};
    for (float f : normal) {
      uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int i = 0; i < 4; ++i) bin += static_cast<char>((u >> (8 * i)) & 0xff);
    }
    for (float f : t) {
      uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int i = 0; i < 4; ++i) bin += static_cast<char>((u >> (8 * i)) & 0xff);
    }
    bin += std::string(2, '\0');
  }
  return bin;
}

TEST_F(ReadStl, BinaryWhoseHeaderStartsWithSolid) {
  // Exactly 84 + 50 bytes: binary, whatever the header says.
  const LoadedMesh m =
      load("solid_header.stl", binary_stl("solid exported", {{0, 0, 0, 0.25f, 0, 0, 0, 4, -1}}));
  ASSERT_EQ(m.mesh.vertex_count(), 3u);
  expect_position(m.mesh.positions[1], 0.25f, 0.f, 0.f);
  expect_position(m.mesh.positions[2], 0.f, 4.f, -1.f);
}

TEST_F(ReadStl, BinaryNonFiniteCornerIsRejected) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(error_of("nan.stl",
                     binary_stl("", {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 1, 0, 0, 0, nan, 0}})),
            "binary STL triangle 1 vertex 2 has a non-finite coordinate (nan)");
  EXPECT_EQ(error_of("inf.stl", binary_stl("", {{0, 0, -inf, 1, 0, 0, 0, 1, 0}})),
            "binary STL triangle 0 vertex 0 has a non-finite coordinate (-inf)");
}

TEST_F(ReadStl, BinarySizeMustMatchTheCount) {
  const std::string two =
      binary_stl("", {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}});  // 184 bytes
  EXPECT_EQ(error_of("short.stl", two.substr(0, 183)),
            "truncated binary STL: header declares 2 triangles (184 bytes), file has 183 bytes");
  EXPECT_EQ(error_of("long.stl", two + "x"),
            "binary STL header declares 2 triangles (184 bytes), file has 185 bytes (data after "
            "the triangles, or not an STL file; an ASCII STL starts with 'solid')");
  // A header starting with "solid" does not make a short binary file ASCII.
  const std::string named = binary_stl("solid x", {{0, 0, 0, 1, 0, 0, 0, 1, 0}});
  EXPECT_EQ(error_of("named_short.stl", named.substr(0, 120)),
            "truncated binary STL: header declares 1 triangles (134 bytes), file has 120 bytes");
  EXPECT_EQ(error_of("tiny.stl", "hello\n"),
            "truncated binary STL (6 bytes; an ASCII STL starts with 'solid')");
}

}  // namespace
}  // namespace texbake
