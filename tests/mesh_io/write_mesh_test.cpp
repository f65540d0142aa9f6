// write_mesh: the binary PLY is read back by an independent parser written
// here (not texbake's reader) with exact colours; ASCII PLY and OBJ round trip
// through read_mesh; faces stay the input's polygons.
#include "mesh_io/write_mesh.h"

#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <string>

#include "mesh_io/read_mesh.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

// A unit square (quad) plus a triangle on top and one unreferenced vertex.
MeshData sample_mesh() {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 1.75f, -0.125f}, {7, 8, 9}};
  m.face_offsets = {0, 4, 7};
  m.face_vertices = {0, 1, 2, 3, 3, 2, 4};
  triangulate_faces(m);
  return m;
}

// Colours with their hand-rounded bytes: round(c * 255), clamped.
const std::vector<std::array<float, 4>> kColours = {
    {0.0f, 1.0f, 0.2f, 1}, {0.5f, 0.998f, 1.5f, 1}, {-0.1f, 0.25f, 0.75f, 1}, {0.1f, 0.3f, 0.9f, 1},
    {1, 1, 1, 1},          {0.4f, 0.6f, 0.8f, 1}};
const uint8_t kBytes[6][3] = {{0, 255, 51},  {128, 254, 255}, {0, 64, 191},
                              {26, 77, 230}, {255, 255, 255}, {102, 153, 204}};

// Independent minimal reader for texbake's binary PLY layout: checks the
// header line by line, then decodes the records by hand.
struct PlainPly {
  std::vector<std::string> header;
  std::vector<std::array<float, 3>> xyz;
  std::vector<std::vector<uint8_t>> colour;
  std::vector<std::vector<int32_t>> faces;
};

PlainPly parse_binary_ply(const std::string& bytes, std::size_t colour_channels) {
  PlainPly out;
  const std::size_t end = bytes.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  std::istringstream h(bytes.substr(0, end));
  std::size_t nv = 0, nf = 0;
  for (std::string line; std::getline(h, line);) {
    out.header.push_back(line);
    std::sscanf(line.c_str(), "element vertex %zu", &nv);
    std::sscanf(line.c_str(), "element face %zu", &nf);
  }
  const char* p = bytes.data() + end + std::strlen("end_header\n");
  for (std::size_t v = 0; v < nv; ++v) {
    std::array<float, 3> q;
    std::memcpy(q.data(), p, 12);  // little-endian floats on this (x86-64) machine
    p += 12;
    out.xyz.push_back(q);
    out.colour.emplace_back(p, p + colour_channels);
    p += colour_channels;
  }
  for (std::size_t f = 0; f < nf; ++f) {
    const uint8_t n = static_cast<uint8_t>(*p++);
    std::vector<int32_t> idx(n);
    std::memcpy(idx.data(), p, 4 * n);
    p += 4 * n;
    out.faces.push_back(idx);
  }
  EXPECT_EQ(p, bytes.data() + bytes.size()) << "bytes left after the last face";
  return out;
}

class WriteMesh : public ::testing::Test {
 protected:
  fs::path dir = test::fresh_temp_dir("write");
  void TearDown() override { fs::remove_all(dir); }
};

TEST_F(WriteMesh, BinaryPlyReadBackIndependentlyWithExactColours) {
  MeshData m = sample_mesh();
  MeshWriteOptions opt;
  opt.vertex_colors = kColours;
  ASSERT_TRUE(write_mesh(dir / "out.ply", m, opt).has_value());
  const PlainPly ply = parse_binary_ply(test::read_bytes(dir / "out.ply"), 3);
  const std::vector<std::string> header = {"ply",
                                           "format binary_little_endian 1.0",
                                           "comment written by texbake",
                                           "element vertex 6",
                                           "property float x",
                                           "property float y",
                                           "property float z",
                                           "property uchar red",
                                           "property uchar green",
                                           "property uchar blue",
                                           "element face 2",
                                           "property list uchar int vertex_indices"};
  EXPECT_EQ(ply.header, header);
  ASSERT_EQ(ply.xyz.size(), 6u);
  for (std::size_t v = 0; v < 6; ++v) {
    EXPECT_EQ(ply.xyz[v][0], m.positions[v].x);
    EXPECT_EQ(ply.xyz[v][1], m.positions[v].y);
    EXPECT_EQ(ply.xyz[v][2], m.positions[v].z);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(ply.colour[v][k], kBytes[v][k]) << "vertex " << v << " channel " << k;
  }
  EXPECT_EQ(ply.faces, (std::vector<std::vector<int32_t>>{{0, 1, 2, 3}, {3, 2, 4}}));
}

TEST_F(WriteMesh, AlphaWrittenOnlyWhenSomeVertexIsNotOpaque) {
  MeshData m = sample_mesh();
  m.vertex_colors = kColours;
  m.vertex_colors[4][3] = 0.5f;  // round(127.5) = 128
  ASSERT_TRUE(write_mesh(dir / "a.ply", m).has_value());
  const PlainPly ply = parse_binary_ply(test::read_bytes(dir / "a.ply"), 4);
  EXPECT_EQ(ply.header[10], "property uchar alpha");
  EXPECT_EQ(ply.colour[4][3], 128);
  EXPECT_EQ(ply.colour[0][3], 255);
}

TEST_F(WriteMesh, PlyWithoutColoursRoundTripsThroughReadMesh) {
  const MeshData m = sample_mesh();
  for (bool ascii : {false, true}) {
    MeshWriteOptions opt;
    opt.ascii = ascii;
    const fs::path path = dir / (ascii ? "a.ply" : "b.ply");
    ASSERT_TRUE(write_mesh(path, m, opt).has_value());
    if (ascii) {
      EXPECT_EQ(test::read_bytes(path).substr(0, 21), "ply\nformat ascii 1.0\n");
    }
    Expected<LoadedMesh> r = read_mesh(path);
    ASSERT_TRUE(r.has_value()) << r.error().message;
    ASSERT_EQ(r->mesh.vertex_count(), m.vertex_count());
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
      EXPECT_EQ(r->mesh.positions[v].x, m.positions[v].x);
      EXPECT_EQ(r->mesh.positions[v].y, m.positions[v].y);
      EXPECT_EQ(r->mesh.positions[v].z, m.positions[v].z);
    }
    EXPECT_EQ(r->mesh.face_offsets, m.face_offsets);
    EXPECT_EQ(r->mesh.face_vertices, m.face_vertices);
    EXPECT_FALSE(r->mesh.has_vertex_colors());
    EXPECT_EQ(r->issues.unreferenced_vertices, 1u);
  }
}

TEST_F(WriteMesh, AsciiPlyColoursRoundTrip) {
  MeshData m = sample_mesh();
  m.vertex_colors = kColours;
  MeshWriteOptions opt;
  opt.ascii = true;
  ASSERT_TRUE(write_mesh(dir / "c.ply", m, opt).has_value());
  Expected<LoadedMesh> r = read_mesh(dir / "c.ply");
  ASSERT_TRUE(r.has_value()) << r.error().message;
  for (std::size_t v = 0; v < 6; ++v) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r->mesh.vertex_colors[v][k], kBytes[v][k] / 255.f);
  }
}

TEST_F(WriteMesh, ObjWithColoursUvsAndNormalsRoundTrips) {
  MeshData m = sample_mesh();
  m.vertex_colors = kColours;
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.25f}};
  m.corner_uv = {0, 1, 2, 3, 3, 2, 4};
  m.normals = {{0, 0, 1}, {0, 0.6f, 0.8f}};
  m.corner_normal = {0, 0, 0, 0, 1, 1, 1};
  ASSERT_TRUE(write_mesh(dir / "m.obj", m).has_value());
  // The colour text is the 8-bit value / 255: check one line by hand.
  std::istringstream text(test::read_bytes(dir / "m.obj"));
  std::string line;
  while (std::getline(text, line) && line.rfind("v ", 0) != 0) {
  }
  EXPECT_EQ(line, "v 0 0 0 0 1 0.2");
  Expected<LoadedMesh> r = read_mesh(dir / "m.obj");
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(r->mesh.vertex_count(), 6u);
  EXPECT_EQ(r->mesh.face_offsets, m.face_offsets);
  EXPECT_EQ(r->mesh.face_vertices, m.face_vertices);
  for (std::size_t v = 0; v < 4; ++v) {  // vertex 5 is unreferenced: OBJ reader leaves it white
    EXPECT_EQ(r->mesh.positions[v].x, m.positions[v].x);
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(r->mesh.vertex_colors[v][k], kBytes[v][k] / 255.f);
  }
  ASSERT_EQ(r->mesh.corner_uv.size(), 7u);
  for (std::size_t c = 0; c < 7; ++c) {
    EXPECT_EQ(r->mesh.uvs[r->mesh.corner_uv[c]].u, m.uvs[m.corner_uv[c]].u);
    EXPECT_EQ(r->mesh.uvs[r->mesh.corner_uv[c]].v, m.uvs[m.corner_uv[c]].v);
    EXPECT_EQ(r->mesh.normals[r->mesh.corner_normal[c]].y, m.normals[m.corner_normal[c]].y);
  }
}

TEST_F(WriteMesh, ObjMaterialNamesTheTexture) {
  MeshData m = sample_mesh();
  m.uvs = {{0, 0}};
  m.corner_uv.assign(7, 0);
  MeshWriteOptions opt;
  opt.obj_material_texture = "atlas.png";
  ASSERT_TRUE(write_mesh(dir / "t.obj", m, opt).has_value());
  EXPECT_NE(test::read_bytes(dir / "t.mtl").find("map_Kd atlas.png\n"), std::string::npos);
  Expected<LoadedMesh> r = read_mesh(dir / "t.obj");
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(fs::path(r->mesh.texture_path), (dir / "atlas.png").lexically_normal());
}

TEST_F(WriteMesh, UnknownExtensionAndWrongColourCountAreErrors) {
  MeshData m = sample_mesh();
  Status s = write_mesh(dir / "x.stl", m);
  ASSERT_FALSE(s.has_value());
  EXPECT_EQ(s.error().code, ErrorCode::kUnsupported);
  // GLB has writers of its own: the error names them.
  Status glb = write_mesh(dir / "x.GLB", m);
  ASSERT_FALSE(glb.has_value());
  EXPECT_EQ(glb.error().code, ErrorCode::kUnsupported);
  EXPECT_NE(glb.error().message.find("write_vertex_color_glb"), std::string::npos);
  EXPECT_NE(glb.error().message.find("write_textured_mesh"), std::string::npos);
  std::vector<std::array<float, 4>> two(2);
  MeshWriteOptions opt;
  opt.vertex_colors = two;
  EXPECT_FALSE(write_mesh(dir / "x.ply", m, opt).has_value());
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(ColourToByte, RoundsToNearestAndClamps) {
  EXPECT_EQ(colour_to_byte(0.f), 0);
  EXPECT_EQ(colour_to_byte(1.f), 255);
  EXPECT_EQ(colour_to_byte(127.4f / 255.f), 127);
  EXPECT_EQ(colour_to_byte(127.6f / 255.f), 128);
  EXPECT_EQ(colour_to_byte(-3.f), 0);
  EXPECT_EQ(colour_to_byte(2.f), 255);
  EXPECT_EQ(colour_to_byte(std::nanf("")), 0);
}

}  // namespace
}  // namespace texbake
