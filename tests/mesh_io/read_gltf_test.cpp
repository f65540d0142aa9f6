// glTF 2.0 input (read_mesh on .glb / .gltf, mesh_io/read_gltf.cpp): the
// GLBs texbake writes read back equal (vertex colours, and an atlas with its
// embedded PNG), hand-written .gltf files with node transforms checked by
// hand, and bad inputs as errors naming the file and what is wrong.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh_io/image_io.h"
#include "mesh_io/mesh_texture.h"
#include "mesh_io/read_mesh.h"
#include "mesh_io/write_textured.h"
#include "tests/bake/test_meshes.h"
#include "tests/mesh_io/colour_testing.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using colour_testing::srgb_encode;

// Little-endian bytes of a glTF buffer built in the test.
struct Bin {
  std::string bytes;
  std::size_t floats(std::initializer_list<float> v) {
    const std::size_t at = bytes.size();
    for (float f : v) bytes.append(reinterpret_cast<const char*>(&f), 4);
    return at;
  }
  std::size_t u16(std::initializer_list<uint16_t> v) {
    const std::size_t at = bytes.size();
    for (uint16_t x : v) bytes.append(reinterpret_cast<const char*>(&x), 2);
    while (bytes.size() % 4) bytes.push_back('\0');
    return at;
  }
  std::size_t u8(std::initializer_list<uint8_t> v) {
    const std::size_t at = bytes.size();
    for (uint8_t x : v) bytes.push_back(static_cast<char>(x));
    while (bytes.size() % 4) bytes.push_back('\0');
    return at;
  }
};

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t n = uint8_t(in[i]) << 16 | uint8_t(in[i + 1]) << 8 | uint8_t(in[i + 2]);
    for (int s : {18, 12, 6, 0}) out.push_back(k[(n >> s) & 63]);
  }
  if (i + 1 == in.size()) {
    const uint32_t n = uint8_t(in[i]) << 16;
    out += std::string{k[n >> 18], k[(n >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const uint32_t n = uint8_t(in[i]) << 16 | uint8_t(in[i + 1]) << 8;
    out += std::string{k[n >> 18], k[(n >> 12) & 63], k[(n >> 6) & 63], '='};
  }
  return out;
}

class ReadGltfTest : public ::testing::Test {
 protected:
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_ = test::fresh_temp_dir("read-gltf");

  // An error of `code` whose message names `file` and contains `what`.
  void expect_error(const fs::path& file, ErrorCode code, const std::string& what) {
    Expected<LoadedMesh> m = read_mesh(file);
    ASSERT_FALSE(m) << file;
    EXPECT_EQ(m.error().code, code) << m.error().message;
    EXPECT_NE(m.error().message.find(file.string()), std::string::npos) << m.error().message;
    EXPECT_NE(m.error().message.find(what), std::string::npos) << m.error().message;
  }

  // The one-triangle .gltf of the bad-input tests: POSITION (bufferView 0,
  // 36 bytes), indices (bufferView 1, ushort 0 1 2) in "tri.bin"; `patch`
  // replaces text of the JSON.
  fs::path bad_gltf(const std::string& from = "", const std::string& to = "",
                    const std::string& name = "bad.gltf") {
    Bin bin;
    bin.floats({0, 0, 0, 1, 0, 0, 0, 1, 0});
    bin.u16({0, 1, 2});
    test::write_text(dir_ / "tri.bin", bin.bytes);
    std::string json = R"({"asset": {"version": "2.0"},
 "buffers": [{"uri": "tri.bin", "byteLength": 44}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                 {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
               {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
 "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0})";
    if (!from.empty()) {
      const auto at = json.find(from);
      EXPECT_NE(at, std::string::npos) << from;
      if (at != std::string::npos) json.replace(at, from.size(), to);
    }
    return test::write_text(dir_ / name, json);
  }
};

// A mesh of 8-bit sRGB colours (k / 255) written by write_vertex_color_glb
// (COLOR_0 = srgb_to_linear, float VEC4) reads back with the same vertices
// in order, the same triangles and the colours within float rounding of
// the curves (each 8-bit value exactly after rounding to 8 bits).
TEST_F(ReadGltfTest, VertexColourGlbRoundTrip) {
  MeshData mesh = test::uv_sphere({1, 2, 3}, 2, 6, 12);
  test::faces_from_triangles(mesh);
  std::vector<Rgba> colors(mesh.vertex_count());
  for (std::size_t v = 0; v < colors.size(); ++v) {
    colors[v] = {float((v * 37) % 256) / 255.f, float((v * 91 + 5) % 256) / 255.f,
                 float((v * 13 + 200) % 256) / 255.f, float((v * 7) % 256) / 255.f};
  }
  for (Vec3 up : {Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
    SCOPED_TRACE(up.z);
    const fs::path glb = dir_ / "colours.glb";
    ASSERT_TRUE(write_vertex_color_glb(glb, mesh, colors, up));
    Expected<LoadedMesh> read = read_mesh(glb);
    ASSERT_TRUE(read) << read.error().message;
    const MeshData& m = read->mesh;
    // No input normals: one glTF vertex per input vertex.
    ASSERT_EQ(m.vertex_count(), mesh.vertex_count());
    ASSERT_EQ(m.face_count(), mesh.face_count());
    EXPECT_EQ(m.face_vertices, mesh.face_vertices);
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
      const Float3 p = mesh.positions[v], q = m.positions[v];
      if (up.y == 1) {  // no node matrix: the mesh's own positions
        EXPECT_EQ(q.x, p.x);
        EXPECT_EQ(q.y, p.y);
        EXPECT_EQ(q.z, p.z);
      } else {  // +Z up: the node turns (x, y, z) to (x, z, -y), exactly
        EXPECT_EQ(q.x, p.x);
        EXPECT_EQ(q.y, p.z);
        EXPECT_EQ(q.z, -p.y);
      }
      ASSERT_TRUE(m.has_vertex_colors());
      for (int k = 0; k < 4; ++k) {
        EXPECT_NEAR(m.vertex_colors[v][k], colors[v][k], 2e-6) << v << " " << k;
        EXPECT_EQ(std::lround(m.vertex_colors[v][k] * 255), std::lround(colors[v][k] * 255));
      }
    }
    // NORMAL is always written: per corner, unit.
    ASSERT_EQ(m.corner_normal.size(), m.face_vertices.size());
    for (const Float3& n : m.normals) {
      EXPECT_NEAR(std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z), 1.0, 1e-6);
    }
    EXPECT_FALSE(m.has_uvs());
    EXPECT_FALSE(m.has_texture());
    EXPECT_EQ(read->issues.other_material_primitives, 0u);
  }
}

// An atlas GLB (write_textured_mesh): per corner the same position and the
// same UV (written t = 1 - v, read v = 1 - t), the embedded PNG decodes to
// the atlas's 8-bit values.
TEST_F(ReadGltfTest, AtlasGlbRoundTrip) {
  MeshData mesh;
  test::append_grid(mesh, 3, 2, [](double s, double t) { return Float3{float(s), float(t), 0}; });
  test::faces_from_triangles(mesh);
  for (std::size_t c = 0; c < mesh.face_vertices.size(); ++c) {
    const Float3 p = mesh.positions[mesh.face_vertices[c]];
    // A UV per corner (seams where a vertex's corners differ).
    mesh.uvs.push_back({0.1f + 0.8f * p.x + 0.01f * float(c % 3), 0.2f + 0.7f * p.y});
    mesh.corner_uv.push_back(static_cast<uint32_t>(c));
  }
  triangulate_faces(mesh);
  const int w = 5, h = 3;
  std::vector<float> atlas(w * h * 4);
  for (int i = 0; i < w * h * 4; ++i) atlas[i] = float((i * 29 + 3) % 256) / 255.f;
  for (int i = 0; i < w * h; ++i) atlas[i * 4 + 3] = 1.f;
  TexturedWriteOptions wo;
  wo.up = {0, 1, 0};
  const fs::path glb = dir_ / "atlas.glb";
  ASSERT_TRUE(write_textured_mesh(glb, mesh, {w, h, atlas.data()}, wo));

  Expected<LoadedMesh> read = read_mesh(glb);
  ASSERT_TRUE(read) << read.error().message;
  const MeshData& m = read->mesh;
  ASSERT_EQ(m.face_count(), mesh.triangles.size());  // a face per written triangle
  ASSERT_TRUE(m.has_uvs());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t c_in = mesh.triangle_corners[t][k];
      const uint32_t c_out = m.face_offsets[t] + k;
      const Float3 p = mesh.positions[mesh.face_vertices[c_in]];
      const Float3 q = m.positions[m.face_vertices[c_out]];
      EXPECT_EQ(q.x, p.x);
      EXPECT_EQ(q.y, p.y);
      EXPECT_EQ(q.z, p.z);
      const Float2 a = mesh.uvs[mesh.corner_uv[c_in]], b = m.uvs[m.corner_uv[c_out]];
      EXPECT_EQ(b.u, a.u);
      EXPECT_NEAR(b.v, a.v, 1.2e-7);  // 1 - (1 - v) in float
    }
  }
  EXPECT_TRUE(m.texture_path.empty());
  ASSERT_FALSE(m.texture_bytes.empty());
  EXPECT_EQ(m.texture_mime_type, "image/png");
  EXPECT_TRUE(m.texture_is_srgb);
  ASSERT_TRUE(m.base_color_factor);
  EXPECT_EQ(*m.base_color_factor, (std::array<float, 4>{1, 1, 1, 1}));
  Expected<Image> tex = read_mesh_texture(m);
  ASSERT_TRUE(tex) << tex.error().message;
  ASSERT_EQ(tex->width, w);
  ASSERT_EQ(tex->height, h);
  EXPECT_EQ(tex->color_space, ColorSpace::kSrgb);
  for (int i = 0; i < w * h * 4; ++i) {
    EXPECT_EQ(std::lround(tex->pixels[i] * 255), std::lround(atlas[i] * 255)) << i;
  }
}

// A hand-written .gltf: external .bin and .png (its URI percent-encoded),
// a parent node translated by (1, 2, 3) over a child rotated 90 degrees
// about Z and scaled by 2. World = T R S, worked by hand:
//   (0, 0, 0) -> (1, 2, 3); (1, 0, 0) -> S (2, 0, 0) -> R (0, 2, 0) -> (1, 4, 3);
//   (0, 1, 0) -> (0, 2, 0) -> (-2, 0, 0) -> (-1, 2, 3).
// Normal (1, 0, 0) -> R (0, 1, 0) (the uniform scale drops out).
// TEXCOORD_0 (s, t) -> (s, 1 - t).
TEST_F(ReadGltfTest, HandWrittenGltfWithNodeTransforms) {
  Bin bin;
  const std::size_t pos = bin.floats({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t nrm = bin.floats({1, 0, 0, 1, 0, 0, 1, 0, 0});
  const std::size_t uv = bin.floats({0, 0, 1, 0, 0.25f, 1});
  const std::size_t idx = bin.u16({0, 1, 2});
  test::write_text(dir_ / "tri.bin", bin.bytes);
  const std::vector<float> rgb = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1};
  ASSERT_TRUE(write_image(dir_ / "tex image.png", {2, 2, rgb.data()}));
  const std::string json = R"({"asset": {"version": "2.0"},
 "buffers": [{"uri": "tri.bin", "byteLength": )" +
                           std::to_string(bin.bytes.size()) + R"(}],
 "bufferViews": [{"buffer": 0, "byteOffset": )" +
                           std::to_string(pos) + R"(, "byteLength": 36},
                 {"buffer": 0, "byteOffset": )" +
                           std::to_string(nrm) + R"(, "byteLength": 36},
                 {"buffer": 0, "byteOffset": )" +
                           std::to_string(uv) + R"(, "byteLength": 24},
                 {"buffer": 0, "byteOffset": )" +
                           std::to_string(idx) + R"(, "byteLength": 6}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
               {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
               {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
               {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}],
 "images": [{"uri": "tex%20image.png"}],
 "textures": [{"source": 0}],
 "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                         "baseColorFactor": [0.5, 0.25, 1, 0.75]}}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                             "indices": 3, "material": 0}]}],
 "nodes": [{"translation": [1, 2, 3], "children": [1]},
           {"rotation": [0, 0, 0.70710678118654752, 0.70710678118654752],
            "scale": [2, 2, 2], "mesh": 0}],
 "scenes": [{"nodes": [0]}], "scene": 0})";
  const fs::path file = test::write_text(dir_ / "hand.gltf", json);
  Expected<LoadedMesh> read = read_mesh(file);
  ASSERT_TRUE(read) << read.error().message;
  const MeshData& m = read->mesh;
  ASSERT_EQ(m.vertex_count(), 3u);
  ASSERT_EQ(m.face_count(), 1u);
  EXPECT_EQ(m.face_vertices, (std::vector<uint32_t>{0, 1, 2}));
  const std::array<std::array<double, 3>, 3> want = {{{1, 2, 3}, {1, 4, 3}, {-1, 2, 3}}};
  for (int v = 0; v < 3; ++v) {
    EXPECT_NEAR(m.positions[v].x, want[v][0], 1e-6) << v;
    EXPECT_NEAR(m.positions[v].y, want[v][1], 1e-6) << v;
    EXPECT_NEAR(m.positions[v].z, want[v][2], 1e-6) << v;
    const Float3 n = m.normals[m.corner_normal[v]];
    EXPECT_NEAR(n.x, 0, 1e-6);
    EXPECT_NEAR(n.y, 1, 1e-6);
    EXPECT_NEAR(n.z, 0, 1e-6);
  }
  const std::array<Float2, 3> uvs = {{{0, 1}, {1, 1}, {0.25f, 0}}};
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(m.uvs[m.corner_uv[c]].u, uvs[c].u);
    EXPECT_EQ(m.uvs[m.corner_uv[c]].v, uvs[c].v);
  }
  EXPECT_EQ(fs::path(m.texture_path), (dir_ / "tex image.png").lexically_normal());
  EXPECT_TRUE(m.texture_bytes.empty());
  ASSERT_TRUE(m.base_color_factor);
  EXPECT_EQ(*m.base_color_factor, (std::array<float, 4>{0.5f, 0.25f, 1, 0.75f}));
  Expected<Image> tex = read_mesh_texture(m);
  ASSERT_TRUE(tex) << tex.error().message;
  ASSERT_EQ(tex->width, 2);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(tex->pixels[i], rgb[i]) << i;
  EXPECT_FALSE(m.has_vertex_colors());
}

// Non-indexed primitives in a self-contained .gltf (data: URI buffer and
// image) under a mirroring node matrix (x -> -x, translation (0, 0, 5)):
// the corners of each triangle come in order, swapped 2 <-> 3 to keep the
// winding; COLOR_0 normalised unsigned bytes (VEC4) are linear 0, 128/255,
// 1: sRGB-encoded on reading (IEC 61966-2-1). A second primitive with
// another material and no COLOR_0 is white and counted.
TEST_F(ReadGltfTest, NonIndexedMirroredWithByteColoursAndDataUris) {
  Bin bin;
  const std::size_t pos = bin.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1});
  const std::size_t col = bin.u8(
      {0, 128, 255, 255, 255, 0, 0, 128, 0, 0, 0, 0, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255});
  const std::vector<float> px = {0.2f, 0.4f, 0.6f, 1};
  Expected<std::vector<unsigned char>> png = encode_image({1, 1, px.data()}, ".png");
  ASSERT_TRUE(png);
  const std::string png_b64 = base64(std::string(png->begin(), png->end()));
  const std::string json = R"({"asset": {"version": "2.0"},
 "buffers": [{"uri": "data:application/octet-stream;base64,)" +
                           base64(bin.bytes) + R"(", "byteLength": )" +
                           std::to_string(bin.bytes.size()) + R"(}],
 "bufferViews": [{"buffer": 0, "byteOffset": )" +
                           std::to_string(pos) + R"(, "byteLength": 72},
                 {"buffer": 0, "byteOffset": )" +
                           std::to_string(col) + R"(, "byteLength": 24}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
               {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"},
               {"bufferView": 1, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC4"}],
 "images": [{"uri": "data:image/png;base64,)" +
                           png_b64 + R"("}],
 "textures": [{"source": 0}],
 "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}, {}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 2}, "material": 0},
                            {"attributes": {"POSITION": 1}, "material": 1}]}],
 "nodes": [{"matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1], "mesh": 0}],
 "scenes": [{"nodes": [0]}]})";
  const fs::path file = test::write_text(dir_ / "mirrored.gltf", json);
  Expected<LoadedMesh> read = read_mesh(file);
  ASSERT_TRUE(read) << read.error().message;
  const MeshData& m = read->mesh;
  ASSERT_EQ(m.vertex_count(), 6u);
  ASSERT_EQ(m.face_count(), 2u);
  EXPECT_EQ(m.face_vertices, (std::vector<uint32_t>{0, 2, 1, 3, 5, 4}));
  const std::array<std::array<float, 3>, 6> want = {
      {{0, 0, 5}, {-1, 0, 5}, {0, 1, 5}, {0, 0, 6}, {-1, 0, 6}, {0, 1, 6}}};
  for (int v = 0; v < 6; ++v) {
    EXPECT_EQ(m.positions[v].x, want[v][0]) << v;
    EXPECT_EQ(m.positions[v].y, want[v][1]) << v;
    EXPECT_EQ(m.positions[v].z, want[v][2]) << v;
  }
  ASSERT_TRUE(m.has_vertex_colors());
  const double mid = srgb_encode(128 / 255.0);
  const std::array<std::array<double, 4>, 3> cols = {
      {{0, mid, 1, 1}, {1, 0, 0, 128 / 255.0}, {0, 0, 0, 0}}};
  for (int v = 0; v < 3; ++v) {
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(m.vertex_colors[v][k], cols[v][k], 1e-5) << v << k;
  }
  for (int v = 3; v < 6; ++v) {
    EXPECT_EQ(m.vertex_colors[v], (std::array<float, 4>{1, 1, 1, 1}));
  }
  EXPECT_EQ(read->issues.other_material_primitives, 1u);
  EXPECT_FALSE(m.has_uvs());
  EXPECT_EQ(m.texture_mime_type, "image/png");
  Expected<Image> tex = read_mesh_texture(m);
  ASSERT_TRUE(tex) << tex.error().message;
  ASSERT_EQ(tex->width, 1);
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(std::lround(tex->pixels[k] * 255), std::lround(px[k] * 255));
  EXPECT_NE(mesh_texture_label(m).find("mirrored.gltf: image 0 (embedded image/png"),
            std::string::npos);
}

// A GLB of an independent writer (tests/data/gltf/make_box_open3d.py,
// Open3D 0.16): its create_box(1, 2, 3) vertices in Open3D's order, 12
// triangles all facing out of the box (closed, so each triangle's normal
// points away from the centre (0.5, 1, 1.5)), and COLOR_0 (i / 7, 0.5,
// 1 - i / 7) as linear light, sRGB-encoded on reading.
TEST_F(ReadGltfTest, Open3dBoxReadsWithOutwardTrianglesAndColours) {
  const fs::path glb = fs::path(TEXBAKE_SOURCE_DIR) / "tests" / "data" / "gltf" / "box_open3d.glb";
  Expected<LoadedMesh> read = read_mesh(glb);
  ASSERT_TRUE(read) << read.error().message;
  const MeshData& m = read->mesh;
  const std::array<std::array<float, 3>, 8> want = {
      {{0, 0, 0}, {1, 0, 0}, {0, 0, 3}, {1, 0, 3}, {0, 2, 0}, {1, 2, 0}, {0, 2, 3}, {1, 2, 3}}};
  ASSERT_EQ(m.vertex_count(), 8u);
  for (int v = 0; v < 8; ++v) {
    EXPECT_EQ(m.positions[v].x, want[v][0]) << v;
    EXPECT_EQ(m.positions[v].y, want[v][1]) << v;
    EXPECT_EQ(m.positions[v].z, want[v][2]) << v;
  }
  ASSERT_EQ(m.triangles.size(), 12u);
  for (const auto& t : m.triangles) {
    const Float3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
    const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
    const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
    const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    const double cx = (a.x + b.x + c.x) / 3 - 0.5, cy = (a.y + b.y + c.y) / 3 - 1,
                 cz = (a.z + b.z + c.z) / 3 - 1.5;
    EXPECT_GT(nx * cx + ny * cy + nz * cz, 0) << t[0] << " " << t[1] << " " << t[2];
  }
  ASSERT_TRUE(m.has_vertex_colors());
  for (int v = 0; v < 8; ++v) {
    const std::array<double, 3> lin = {v / 7.0, 0.5, 1 - v / 7.0};
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(m.vertex_colors[v][k], srgb_encode(lin[k]), 1e-5) << v << " " << k;
    }
    EXPECT_EQ(m.vertex_colors[v][3], 1.f);
  }
  EXPECT_FALSE(m.has_uvs());
  EXPECT_TRUE(m.corner_normal.empty());
}

TEST_F(ReadGltfTest, ValidBaseFileReads) {
  Expected<LoadedMesh> m = read_mesh(bad_gltf());
  ASSERT_TRUE(m) << m.error().message;
  EXPECT_EQ(m->mesh.face_count(), 1u);
  EXPECT_FALSE(m->mesh.base_color_factor);  // no material
}

// Two nodes using mesh 0 (the second translated by (0, 0, 1)): the mesh is
// read twice, in node order. Without scenes every mesh is read once,
// untransformed.
TEST_F(ReadGltfTest, InstancesAndFilesWithoutScene) {
  Expected<LoadedMesh> two = read_mesh(bad_gltf(
      R"("nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}])",
      R"("nodes": [{"mesh": 0}, {"mesh": 0, "translation": [0, 0, 1]}], "scenes": [{"nodes": [0, 1]}])"));
  ASSERT_TRUE(two) << two.error().message;
  ASSERT_EQ(two->mesh.vertex_count(), 6u);
  EXPECT_EQ(two->mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  for (int v = 0; v < 6; ++v) EXPECT_EQ(two->mesh.positions[v].z, v < 3 ? 0.f : 1.f) << v;
  EXPECT_EQ(two->mesh.positions[4].x, 1.f);

  Expected<LoadedMesh> none =
      read_mesh(bad_gltf(R"("nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0)",
                         R"("nodes": [{"mesh": 0, "translation": [5, 5, 5]}])"));
  ASSERT_TRUE(none) << none.error().message;
  ASSERT_EQ(none->mesh.vertex_count(), 3u);
  EXPECT_EQ(none->mesh.positions[1].x, 1.f);  // the node (not in any scene) is not applied
  EXPECT_EQ(none->mesh.positions[1].z, 0.f);
}

// KHR_mesh_quantization: normalised shorts (32767 -> 1) with a byteStride
// of 8, unsigned byte indices.
TEST_F(ReadGltfTest, QuantizedPositionsAndByteIndices) {
  const fs::path file = fs::path(TEXBAKE_SOURCE_DIR) / "tests" / "fuzz" / "corpus" /
                        "fuzz_mesh_gltf" / "quantized_noscene.gltf";
  Expected<LoadedMesh> m = read_mesh(file);
  ASSERT_TRUE(m) << m.error().message;
  ASSERT_EQ(m->mesh.vertex_count(), 3u);
  EXPECT_EQ(m->mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(m->mesh.positions[1].x, 1.f);
  EXPECT_EQ(m->mesh.positions[2].y, 1.f);
  EXPECT_EQ(m->mesh.positions[2].x, 0.f);
}

TEST_F(ReadGltfTest, UnsupportedFeaturesAreNamed) {
  expect_error(
      bad_gltf(R"({"asset": {"version": "2.0"},)",
               R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_texture_transform"],
 "extensionsRequired": ["KHR_texture_transform"],)"),
      ErrorCode::kParse, "requires the extension KHR_texture_transform");
  expect_error(bad_gltf(R"("count": 3, "type": "VEC3"})",
                        R"("count": 3, "type": "VEC3", "sparse": {"count": 1,
   "indices": {"bufferView": 1, "componentType": 5123},
   "values": {"bufferView": 0}}})"),
               ErrorCode::kParse, "is sparse");
  expect_error(bad_gltf(R"("scene": 0)", R"("scene": 3)"), ErrorCode::kParse,
               "the default scene 3 does not exist");
  expect_error(bad_gltf(R"("version": "2.0")", R"("version": "1.0")"), ErrorCode::kParse, "1.0");
}

TEST_F(ReadGltfTest, TruncatedAndCorruptGlb) {
  MeshData mesh = test::uv_sphere({0, 0, 0}, 1, 4, 8);
  test::faces_from_triangles(mesh);
  const fs::path good = dir_ / "good.glb";
  ASSERT_TRUE(write_vertex_color_glb(good, mesh, std::vector<Rgba>(mesh.vertex_count())));
  const std::string bytes = test::read_bytes(good);
  for (std::size_t n : {std::size_t{4}, std::size_t{11}, std::size_t{16}, std::size_t{40},
                        bytes.size() / 2, bytes.size() - 4}) {
    SCOPED_TRACE(n);
    const fs::path cut = test::write_text(dir_ / "cut.glb", bytes.substr(0, n));
    expect_error(cut, ErrorCode::kParse, "truncated");
  }
  std::string bad = bytes;
  bad[0] = 'x';
  expect_error(test::write_text(dir_ / "magic.glb", bad), ErrorCode::kParse, "magic");
  bad = bytes;
  std::memset(bad.data() + 20, '!', 8);  // the JSON text
  expect_error(test::write_text(dir_ / "json.glb", bad), ErrorCode::kParse, "not a valid glTF");
  bad = bytes;
  const uint32_t huge = 0x7ffffff0;  // the BIN chunk's length
  uint32_t json_len;
  std::memcpy(&json_len, bad.data() + 12, 4);
  std::memcpy(bad.data() + 20 + json_len, &huge, 4);
  expect_error(test::write_text(dir_ / "bin.glb", bad), ErrorCode::kParse, "past the end");
  expect_error(test::write_text(dir_ / "deep.gltf", std::string(100000, '[')), ErrorCode::kParse,
               "nests deeper");
}

TEST_F(ReadGltfTest, AccessorsAndViewsOutsideTheirBuffer) {
  expect_error(bad_gltf(R"("count": 3, "type": "VEC3")", R"("count": 4, "type": "VEC3")"),
               ErrorCode::kParse, "4 elements from byte 0 do not fit in bufferView 0");
  expect_error(
      bad_gltf(R"("byteOffset": 36, "byteLength": 6)", R"("byteOffset": 36, "byteLength": 60)"),
      ErrorCode::kParse, "bufferView 1 (bytes 36 + 60) lies outside buffer 0");
  expect_error(bad_gltf(R"("POSITION": 0})", R"("POSITION": 7})"), ErrorCode::kParse,
               "mesh 0 primitive 0 POSITION refers to accessor 7");
  expect_error(bad_gltf(R"("byteLength": 36},)", R"("byteLength": 36, "byteStride": 4},)"),
               ErrorCode::kParse, "byteStride 4");
}

TEST_F(ReadGltfTest, IndexOutOfRange) {
  const fs::path file =
      bad_gltf(R"("count": 3, "type": "SCALAR")", R"("count": 3, "type": "SCALAR")");
  // Rewrite index 2 as 5.
  Bin bin;
  bin.floats({0, 0, 0, 1, 0, 0, 0, 1, 0});
  bin.u16({0, 1, 5});
  test::write_text(dir_ / "tri.bin", bin.bytes);
  expect_error(file, ErrorCode::kParse, "mesh 0 primitive 0 index 2 is 5 but the primitive has 3");
}

TEST_F(ReadGltfTest, MissingExternalFiles) {
  const fs::path file = bad_gltf();
  fs::remove(dir_ / "tri.bin");
  expect_error(file, ErrorCode::kIo, "tri.bin");
  const fs::path img = bad_gltf(R"("nodes": [{"mesh": 0}])",
                                R"("images": [{"uri": "nowhere.png"}], "textures": [{"source": 0}],
 "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
 "nodes": [{"mesh": 0}])",
                                "img.gltf");
  std::string text = test::read_bytes(img);
  text.replace(text.find(R"("indices": 1})"), 13, R"("indices": 1, "material": 0})");
  test::write_text(img, text);
  expect_error(img, ErrorCode::kIo, "nowhere.png");
}

TEST_F(ReadGltfTest, CompressionExtensionsAndOtherModes) {
  for (const char* ext : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"}) {
    expect_error(bad_gltf(R"({"asset": {"version": "2.0"},)",
                          std::string(R"({"asset": {"version": "2.0"}, "extensionsUsed": [")") +
                              ext + R"("], "extensionsRequired": [")" + ext + R"("],)"),
                 ErrorCode::kParse, ext);
  }
  expect_error(bad_gltf(R"("indices": 1})", R"("indices": 1, "mode": 5})"), ErrorCode::kParse,
               "mesh 0 primitive 0 is TRIANGLE_STRIP");
  expect_error(bad_gltf(R"("indices": 1})", R"("indices": 1, "mode": 1})"), ErrorCode::kParse,
               "mesh 0 primitive 0 is LINES");
  expect_error(bad_gltf(R"("nodes": [{"mesh": 0}])", R"("nodes": [{"mesh": 0, "children": [0]}])"),
               ErrorCode::kParse, "node 0 appears twice");
}

// Issue #28 item 7: values tinygltf reports as malformed and then drops (a
// baseColorFactor of 3 numbers left the material white and dropped its
// texture; a texture reference without its index) are errors naming the
// file and the key.
TEST_F(ReadGltfTest, MalformedMaterialValuesAreErrors) {
  auto with_material = [&](const std::string& material, const std::string& name) {
    const fs::path file =
        bad_gltf(R"("nodes": [{"mesh": 0}])",
                 R"("materials": [)" + material + R"(], "nodes": [{"mesh": 0}])", name);
    std::string text = test::read_bytes(file);
    text.replace(text.find(R"("indices": 1})"), 13, R"("indices": 1, "material": 0})");
    return test::write_text(file, text);
  };
  expect_error(
      with_material(R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0]}})", "three.gltf"),
      ErrorCode::kParse, "`baseColorFactor` parameter in pbrMetallicRoughness must be 4");
  expect_error(with_material(R"({"pbrMetallicRoughness": {"baseColorTexture": {"texCoord": 0}}})",
                             "noindex.gltf"),
               ErrorCode::kParse, "'index' property is missing");
  // The same material with four numbers reads, its factor kept.
  Expected<LoadedMesh> m = read_mesh(with_material(
      R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 0.5]}})", "four.gltf"));
  ASSERT_TRUE(m) << m.error().message;
  ASSERT_TRUE(m->mesh.base_color_factor);
  EXPECT_EQ(*m->mesh.base_color_factor, (std::array<float, 4>{1, 0, 0, 0.5f}));
}

// Issue #28 item 9: external buffers and images are read only from the
// glTF's own folder. A URI leaving it ("..", a link pointing out), an
// absolute path or another scheme than data: is refused, naming the file
// and the URI; subfolders and links that stay inside are read.
TEST_F(ReadGltfTest, UrisLeavingTheFolderAreRefused) {
  const fs::path sub = dir_ / "sub";
  fs::create_directories(sub / "deeper");
  bad_gltf();  // writes dir_/tri.bin, outside `sub`
  auto gltf_in_sub = [&](const std::string& buffer_uri, const std::string& name,
                         const std::string& image_uri = "") {
    const fs::path file =
        bad_gltf(R"("uri": "tri.bin")", R"("uri": ")" + buffer_uri + "\"", "sub/" + name);
    if (image_uri.empty()) return file;
    std::string text = test::read_bytes(file);
    text.replace(text.find(R"("nodes": [{"mesh": 0}])"), 22,
                 R"("images": [{"uri": ")" + image_uri + R"("}], "textures": [{"source": 0}],
 "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
 "nodes": [{"mesh": 0}])");
    text.replace(text.find(R"("indices": 1})"), 13, R"("indices": 1, "material": 0})");
    return test::write_text(file, text);
  };
  expect_error(gltf_in_sub("../tri.bin", "up.gltf"), ErrorCode::kParse,
               "the URI '../tri.bin' leaves the glTF's folder");
  expect_error(gltf_in_sub("deeper/../../tri.bin", "updown.gltf"), ErrorCode::kParse,
               "'deeper/../../tri.bin' leaves");
  expect_error(gltf_in_sub("%2E%2E/tri.bin", "percent.gltf"), ErrorCode::kParse,
               "'../tri.bin' leaves");  // tinygltf decodes it first
  expect_error(gltf_in_sub((dir_ / "tri.bin").string(), "absolute.gltf"), ErrorCode::kParse,
               "is an absolute path");
  expect_error(gltf_in_sub("file:///etc/passwd", "scheme.gltf"), ErrorCode::kParse,
               "of scheme 'file'");
  fs::create_symlink(dir_ / "tri.bin", sub / "link.bin");
  expect_error(gltf_in_sub("link.bin", "link.gltf"), ErrorCode::kParse,
               "'link.bin' leaves the glTF's folder");
  fs::create_symlink(dir_, sub / "deeper" / "up");
  expect_error(gltf_in_sub("deeper/up/tri.bin", "dirlink.gltf"), ErrorCode::kParse,
               "'deeper/up/tri.bin' leaves");

  // Inside the folder: a subfolder, ".." that stays inside, a link to a
  // file inside; the buffer reads.
  fs::copy_file(dir_ / "tri.bin", sub / "deeper" / "tri.bin");
  fs::create_symlink(sub / "deeper" / "tri.bin", sub / "inner.bin");
  for (const char* uri : {"deeper/tri.bin", "deeper/../deeper/tri.bin", "inner.bin"}) {
    Expected<LoadedMesh> m = read_mesh(gltf_in_sub(uri, "inside.gltf"));
    EXPECT_TRUE(m) << uri << ": " << m.error().message;
  }

  // The base colour image: tinygltf's lookup and read_material's both refuse.
  test::write_text(dir_ / "outside.png", "not read");
  expect_error(gltf_in_sub("deeper/tri.bin", "image.gltf", "../outside.png"), ErrorCode::kParse,
               "the URI '../outside.png' leaves");
  expect_error(gltf_in_sub("deeper/tri.bin", "image_abs.gltf", (dir_ / "outside.png").string()),
               ErrorCode::kParse, "is an absolute path");
}

}  // namespace
}  // namespace texbake
