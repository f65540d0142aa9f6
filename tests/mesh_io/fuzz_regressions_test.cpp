// Inputs the fuzzers (tests/fuzz) found, and the reader checks written for
// them (issue #7). Every file under tests/fuzz/regressions/ is replayed; the
// hand-made cases pin down the error each fixed problem now gives. Expected
// values come from the file contents, worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "mesh_io/proxy_json.h"
#include "mesh_io/read_mesh.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using test::write_text;

fs::path regressions_dir() {
  return fs::path(TEXBAKE_SOURCE_DIR) / "tests" / "fuzz" / "regressions";
}

class FuzzRegression : public ::testing::Test {
 protected:
  fs::path dir = test::fresh_temp_dir("fuzzreg");
  void TearDown() override { fs::remove_all(dir); }

  // The error read_mesh gives for `text` saved as `name`; fails if it loads.
  Error error_of(const std::string& name, const std::string& text) {
    const fs::path path = write_text(dir / name, text);
    Expected<LoadedMesh> m = read_mesh(path);
    EXPECT_FALSE(m.has_value()) << name << " was accepted";
    if (m) return {};
    EXPECT_NE(m.error().message.find(path.string()), std::string::npos) << m.error().message;
    return m.error();
  }
  LoadedMesh load(const std::string& name, const std::string& text) {
    Expected<LoadedMesh> m = read_mesh(write_text(dir / name, text));
    EXPECT_TRUE(m.has_value()) << (m ? "" : m.error().message);
    return m ? std::move(*m) : LoadedMesh{};
  }
};

// The saved fuzzer inputs, each with the error it must now give.
struct SavedInput {
  const char* file;  // under tests/fuzz/regressions/
  const char* says;
};

TEST(FuzzRegressionFiles, EachSavedMeshInputGivesItsError) {
  const SavedInput cases[] = {
      // OpenMesh asserted on "/1/2"; this one stops earlier, at the first
      // corner's texture index (no vt in the file).
      {"fuzz_mesh_obj/empty_vertex_index_assert.obj",
       "line 2: texture coordinate index 1 is out of range (0 in the file"},
      // 15 bytes, no newline: OpenMesh read uninitialised counts (2 GB).
      {"fuzz_mesh_off/uninitialised_counts_oom.off", "line 1: not an OFF file"},
      // "element vert... 1899460386" without properties: a loop of 1.9e9
      // empty records ran for minutes. The count token ends in "]000y".
      {"fuzz_mesh_ply/propertyless_element_huge_count.ply", "line 4: bad element line"},
      // A list length of 9.4e42 converted to size_t (UBSan; introduced and
      // caught during this work, never on main).
      {"fuzz_mesh_ply/list_length_1e42_ubsan.ply",
       "line 18: bad list length '9444444444444444444444444444444444444444444'"},
      // A list property in the vertex element: values read past the end.
      {"fuzz_mesh_ply/vertex_list_overread.ply", "truncated: the file ends in vertex "},
  };
  for (const SavedInput& c : cases) {
    const fs::path path = regressions_dir() / c.file;
    ASSERT_TRUE(fs::exists(path)) << path;
    Expected<LoadedMesh> m = read_mesh(path);
    ASSERT_FALSE(m.has_value()) << c.file;
    EXPECT_EQ(m.error().code, ErrorCode::kParse) << m.error().message;
    EXPECT_NE(m.error().message.find(c.says), std::string::npos) << m.error().message;
  }
}

// Every saved input (also ones added later) is read without crashing, and a
// rejection names the file.
TEST(FuzzRegressionFiles, EverySavedInputIsReadOrRejectedCleanly) {
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(regressions_dir())) {
    if (!entry.is_regular_file()) continue;
    const fs::path& p = entry.path();
    const std::string target = p.parent_path().filename().string();
    ++files;
    if (target.rfind("fuzz_mesh_", 0) == 0) {
      Expected<LoadedMesh> m = read_mesh(p);
      if (!m) {
        EXPECT_NE(m.error().message.find(p.string()), std::string::npos);
      }
    } else if (target == "fuzz_proxy_json") {
      Expected<Proxy> proxy = proxy_from_json(test::read_bytes(p), p.string());
      if (!proxy) {
        EXPECT_EQ(proxy.error().message.rfind(p.string(), 0), 0u);
      }
    }
  }
  EXPECT_GE(files, 4);
}

// --- OBJ: corners OpenMesh would misread (checked before it runs) ---------

TEST_F(FuzzRegression, ObjCornerWithoutVertexIndex) {
  const Error e = error_of("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf /1 2 3\n");
  EXPECT_NE(e.message.find("line 5: face corner '/1' has no vertex index"), std::string::npos)
      << e.message;
}

TEST_F(FuzzRegression, ObjCornerPartNotAnInteger) {
  const Error e = error_of("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1/n 2 3\n");
  EXPECT_NE(e.message.find("line 5: normal index 'n' is not an integer"), std::string::npos)
      << e.message;
  const Error e2 = error_of("b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//x 2 3\n");
  EXPECT_NE(e2.message.find("line 5: normal index 'x' is not an integer"), std::string::npos)
      << e2.message;
  const Error e3 = error_of("c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2.5 3\n");
  EXPECT_NE(e3.message.find("line 4: face index '2.5' is not an integer"), std::string::npos)
      << e3.message;
}

TEST_F(FuzzRegression, ObjIndexPastIntRange) {
  const Error e = error_of("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n");
  EXPECT_NE(e.message.find("line 4: face index 99999999999 is out of range (3 in the file"),
            std::string::npos)
      << e.message;
}

TEST_F(FuzzRegression, ObjTextureAndNormalIndicesInRange) {
  const Error vt = error_of("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n");
  EXPECT_NE(vt.message.find("line 5: texture coordinate index 2 is out of range (1 in the file"),
            std::string::npos)
      << vt.message;
  // Relative: -2 with one vn so far.
  const Error vn = error_of("b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//-2 2//1 3//1\n");
  EXPECT_NE(vn.message.find("line 5: normal index -2 is out of range (1 so far"), std::string::npos)
      << vn.message;
  // A valid file with every corner form loads: 1 vt, 1 vn shared.
  const LoadedMesh m = load("ok.obj",
                            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0.5 0.25\nvn 0 0 1\n"
                            "f 1/1/1 2//1 3/1\nf -3/-1/-1 4 -2\n");
  EXPECT_EQ(m.mesh.face_count(), 2u);
  EXPECT_EQ(m.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
}

TEST_F(FuzzRegression, ObjNormalLineThatDoesNotParse) {
  // OpenMesh skips such a line but counts it for relative indices.
  const Error e = error_of("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 nan 1\nf 1 2 3\n");
  EXPECT_NE(e.message.find("line 4: normal coordinate 'nan' is not a finite number"),
            std::string::npos)
      << e.message;
}

TEST_F(FuzzRegression, ObjHexFloatOpenMeshCannotRead) {
  // strtod reads 0x1p3 (= 8), OpenMesh's istream does not and skips the line.
  const Error e = error_of("a.obj", "v 0x1p3 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\n");
  EXPECT_NE(e.message.find("has 4 vertex lines but 3 vertices could be read"), std::string::npos)
      << e.message;
}

TEST_F(FuzzRegression, ObjMaterialLibraryThatIsNotAFile) {
  fs::create_directories(dir / "lib.mtl");
  const Error e = error_of("a.obj", "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_NE(e.message.find("line 1: material library 'lib.mtl' is not a regular file"),
            std::string::npos)
      << e.message;
  // A missing library is only a missing texture (OpenMesh warns): loads.
  EXPECT_EQ(
      load("b.obj", "mtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").mesh.face_count(), 1u);
}

// --- OFF: our own ASCII parser, binary OFF walked before OpenMesh ----------

TEST_F(FuzzRegression, OffCommentsAndCountsOnTheKeywordLine) {
  // OpenMesh ignored counts on the OFF line and choked on comments.
  const LoadedMesh m = load("a.off",
                            "OFF 4 2 0 # counts here\n# a comment\n0 0 0\n\n1 0 0  # x\n"
                            "1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  EXPECT_EQ(m.mesh.vertex_count(), 4u);
  EXPECT_EQ(m.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(m.mesh.positions[2].x, 1.f);
  EXPECT_EQ(m.mesh.positions[2].y, 1.f);
}

TEST_F(FuzzRegression, OffNormalsAndColours) {
  // NOFF: normals per vertex; COFF: integer colours / 255, float ones as is.
  const LoadedMesh n =
      load("n.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 1 0\n0 1 0 1 0 0\n3 0 1 2\n");
  ASSERT_EQ(n.mesh.normals.size(), 3u);
  EXPECT_EQ(n.mesh.normals[1].y, 1.f);
  EXPECT_EQ(n.mesh.corner_normal, (std::vector<uint32_t>{0, 1, 2}));
  const LoadedMesh c =
      load("c.off", "COFF\n3 1 0\n0 0 0 255 0 51 255\n1 0 0 0.5 0.25 1.0\n0 1 0 7\n3 0 1 2\n");
  ASSERT_EQ(c.mesh.vertex_colors.size(), 3u);
  EXPECT_EQ(c.mesh.vertex_colors[0], (std::array<float, 4>{1, 0, 51 / 255.f, 1}));
  EXPECT_EQ(c.mesh.vertex_colors[1], (std::array<float, 4>{0.5f, 0.25f, 1, 1}));
  EXPECT_EQ(c.mesh.vertex_colors[2], (std::array<float, 4>{1, 1, 1, 1}));  // colour-map index
}

TEST_F(FuzzRegression, OffKeywordAndHeaderErrors) {
  EXPECT_NE(error_of("a.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
                .message.find("line 1: not an OFF file (expected the keyword 'OFF', got '3')"),
            std::string::npos);
  EXPECT_NE(error_of("b.off", "4OFF\n3 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n")
                .message.find("4D and n-dimensional OFF are not supported"),
            std::string::npos);
  EXPECT_NE(error_of("c.off", "OFF\nthree 1 0\n").message.find("line 2: expected 'vertices faces"),
            std::string::npos);
  // A lying header is rejected before allocating: 10^9 vertices need >= 6 GB.
  EXPECT_NE(error_of("d.off", "OFF\n1000000000 1 0\n0 0 0\n3 0 0 0\n")
                .message.find("more than the file can hold"),
            std::string::npos);
  EXPECT_NE(error_of("e.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n")
                .message.find("line 6: face has fewer indices than its count"),
            std::string::npos);
}

std::string le32(uint32_t v) {
  std::string s(4, '\0');
  for (int i = 0; i < 4; ++i) s[i] = static_cast<char>((v >> (8 * i)) & 0xff);
  return s;
}
std::string le_float(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return le32(u);
}

TEST_F(FuzzRegression, BinaryOffIsWalkedBeforeOpenMeshReadsIt) {
  std::string verts;
  for (float x : {0.f, 0.f, 0.f, 2.f, 0.f, 0.f, 0.f, 3.f, 0.f}) verts += le_float(x);
  const std::string head = "OFF BINARY\n" + le32(3) + le32(1) + le32(0);
  const LoadedMesh m = load("ok.off", head + verts + le32(3) + le32(0) + le32(1) + le32(2));
  ASSERT_EQ(m.mesh.vertex_count(), 3u);
  EXPECT_EQ(m.mesh.positions[1].x, 2.f);
  EXPECT_EQ(m.mesh.positions[2].y, 3.f);
  EXPECT_EQ(m.mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_NE(error_of("idx.off", head + verts + le32(3) + le32(0) + le32(1) + le32(3))
                .message.find("face 0 refers to vertex 3 but there are 3 vertices"),
            std::string::npos);
  EXPECT_NE(error_of("short.off", head + verts + le32(4) + le32(0) + le32(1) + le32(2))
                .message.find("truncated binary OFF: face 0 declares 4 corners"),
            std::string::npos);
  EXPECT_NE(error_of("lying.off", "OFF BINARY\n" + le32(1u << 30) + le32(1) + le32(0) + verts)
                .message.find("more than the file can hold"),
            std::string::npos);
}

// --- PLY --------------------------------------------------------------------

TEST_F(FuzzRegression, PlyVertexElementWithAListIsBoundsChecked) {
  // Binary vertex records with a list have no fixed size: the last vertex's
  // z is missing (the fuzzer's input read 4 bytes past the end).
  std::string data = std::string("ply\nformat binary_little_endian 1.0\nelement vertex 2\n") +
                     "property float x\nproperty float y\nproperty list uchar int extra\n" +
                     "property float z\nend_header\n";
  // Vertex 0: x y, a list of 3 ints, z; vertex 1: x y, an empty list, no z.
  // 34 bytes: enough for the up-front minimum (2 x 13), short of vertex 1's z.
  data += le_float(0.f) + le_float(1.f) + std::string(1, '\3') + le32(7) + le32(8) + le32(9) +
          le_float(2.f);
  data += le_float(3.f) + le_float(4.f) + std::string(1, '\0');
  const Error e = error_of("a.ply", data);
  EXPECT_NE(e.message.find("truncated: the file ends in vertex 1 of 2"), std::string::npos)
      << e.message;
}

TEST_F(FuzzRegression, PlyElementWithoutPropertiesCostsNothing) {
  // 4e9 records of nothing: read (and skipped) at once, the mesh loads.
  const LoadedMesh m =
      load("a.ply",
           "ply\nformat ascii 1.0\nelement nothing 4000000000\n"
           "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
           "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(m.mesh.vertex_count(), 3u);
  EXPECT_EQ(m.mesh.face_count(), 1u);
}

// --- work limits: polygons ----------------------------------------------------

std::string many(const std::string& item, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += item;
  return s;
}

TEST_F(FuzzRegression, PolygonsAboveTheCornerLimitAreRejected) {
  // 16385 corners: one above kMaxFaceCorners (OpenMesh's OBJ reader is
  // O(n^2) per face; a 2 MB face line would take minutes).
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  EXPECT_NE(error_of("a.obj", tri + "f" + many(" 1", 16385) + "\n")
                .message.find("line 4: face has 16385 corners; texbake reads polygons of at most "
                              "16384"),
            std::string::npos);
  EXPECT_NE(error_of("b.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n16385" + many(" 0", 16385) + "\n")
                .message.find("line 6: face has 16385 corners"),
            std::string::npos);
  EXPECT_NE(error_of("c.ply",
                     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                     "y\nproperty float z\nelement face 1\nproperty list int int "
                     "vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n16385" +
                         many(" 0", 16385) + "\n")
                .message.find("line 13: face 0 has 16385 corners"),
            std::string::npos);
  // At the limit: read (all corners the same vertex: degenerate, no triangle).
  const Error e = error_of("d.obj", tri + "f" + many(" 1", 16384) + "\n");
  EXPECT_NE(e.message.find("no faces"), std::string::npos) << e.message;
}

TEST_F(FuzzRegression, LargeNonConvexPolygonIsFannedNotEarClipped) {
  // A 1000-corner star (alternating radius 1 and 0.5: non-convex) is above
  // kMaxEarClipCorners: fanned from corner 0, n - 2 triangles, every corner
  // kept, no degenerate triangle (corner 0 sees every other corner of the star
  // at a distinct angle).
  const int n = 1000;
  std::string text = "OFF\n" + std::to_string(n) + " 1 0\n";
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, r = i % 2 ? 0.5 : 1.0;
    text += std::to_string(r * std::cos(a)) + " " + std::to_string(r * std::sin(a)) + " 0\n";
  }
  text += std::to_string(n);
  for (int i = 0; i < n; ++i) text += " " + std::to_string(i);
  const LoadedMesh m = load("star.off", text + "\n");
  ASSERT_EQ(m.mesh.triangles.size(), static_cast<std::size_t>(n - 2));
  for (int i = 0; i < n - 2; ++i) {
    EXPECT_EQ(m.mesh.triangles[i], (std::array<uint32_t, 3>{0, uint32_t(i + 1), uint32_t(i + 2)}));
  }
}

// --- proxy JSON ---------------------------------------------------------------

TEST(FuzzRegressionJson, WrittenProxyReadsBackToWithinAnUlp) {
  // The fuzzer's input: pole [2,0,1]. Reading normalises and orthogonalises
  // the equator; reading the written unit vectors again may move one by an
  // ulp (0.4472135954999579 -> 0.447213595499958), never more.
  const std::string text =
      test::read_bytes(regressions_dir() / "fuzz_proxy_json" / "pole_renormalised_ulp.json");
  Expected<Proxy> once = proxy_from_json(text);
  ASSERT_TRUE(once.has_value()) << once.error().message;
  const std::string written = proxy_to_json(*once);
  Expected<Proxy> twice = proxy_from_json(written);
  ASSERT_TRUE(twice.has_value()) << twice.error().message;
  const nlohmann::json a = nlohmann::json::parse(written),
                       b = nlohmann::json::parse(proxy_to_json(*twice));
  ASSERT_EQ(a["kind"], b["kind"]);
  for (const char* key : {"center", "pole", "equator"}) {
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(a[key][i].get<double>(), b[key][i].get<double>(), 1e-15) << key << i;
  }
  // The pole is (2,0,1)/sqrt(5); the equator (1,0,0) made perpendicular:
  // (1,0,-2)/sqrt(5).
  EXPECT_NEAR(a["pole"][0].get<double>(), 2 / std::sqrt(5.0), 1e-15);
  EXPECT_NEAR(a["equator"][2].get<double>(), -2 / std::sqrt(5.0), 1e-15);
}

}  // namespace
}  // namespace texbake
