// glTF conventions of the GLB writers (mesh_io/write_textured.h, issue #11
// item 5): the node matrix turns the mesh's up axis to glTF's +Y while the
// vertex data stay the mesh's; NORMAL in every GLB, the input's when it has
// them. Expected matrices are worked out by hand from the rotations
// (column-major, as glTF stores them); files are read back with tinygltf.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh_io/read_mesh.h"
#include "mesh_io/write_mesh.h"
#include "mesh_io/write_textured.h"
#include "tests/bake/test_meshes.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using Matrix = std::array<double, 16>;

// Column-major: columns are the images of +X, +Y, +Z.
// +Z up, -90 degrees about X: (x, y, z) -> (x, z, -y); X -> X, Y -> -Z, Z -> Y.
constexpr Matrix kZUp = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
// -Z up, +90 degrees about X: (x, y, z) -> (x, -z, y); X -> X, Y -> Z, Z -> -Y.
constexpr Matrix kMinusZUp = {1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1};
// +X up, +90 degrees about Z: (x, y, z) -> (-y, x, z); X -> Y, Y -> -X, Z -> Z.
constexpr Matrix kXUp = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
// -X up, -90 degrees about Z: (x, y, z) -> (y, -x, z); X -> -Y, Y -> X, Z -> Z.
constexpr Matrix kMinusXUp = {0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
// -Y up, 180 degrees about X: (x, y, z) -> (x, -y, -z).
constexpr Matrix kMinusYUp = {1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1};
constexpr Matrix kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

// m * (x, y, z, 0) for a column-major m.
std::array<double, 3> apply(const std::vector<double>& m, double x, double y, double z) {
  return {m[0] * x + m[4] * y + m[8] * z, m[1] * x + m[5] * y + m[9] * z,
          m[2] * x + m[6] * y + m[10] * z};
}

template <class T>
std::vector<T> accessor_values(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors.at(index);
  const tinygltf::BufferView& v = m.bufferViews.at(a.bufferView);
  EXPECT_EQ(v.byteStride, 0u);  // tightly packed
  const unsigned char* p = m.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset;
  const std::size_t n = a.count * tinygltf::GetNumComponentsInType(a.type);
  std::vector<T> out(n);
  std::memcpy(out.data(), p, n * sizeof(T));
  return out;
}

tinygltf::Model load(const fs::path& glb) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, glb.string())) << err;
  return model;
}

// POSITION, NORMAL and the indices of the one primitive.
struct GlbArrays {
  std::vector<float> pos, nrm;
  std::vector<uint32_t> idx;
};
GlbArrays arrays_of(const tinygltf::Model& model) {
  const tinygltf::Primitive& prim = model.meshes.at(0).primitives.at(0);
  return {accessor_values<float>(model, prim.attributes.at("POSITION")),
          accessor_values<float>(model, prim.attributes.at("NORMAL")),
          accessor_values<uint32_t>(model, prim.indices)};
}

class WriteGlbTest : public ::testing::Test {
 protected:
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_ = test::fresh_temp_dir("write-glb");

  static std::vector<Rgba> grey(std::size_t n) {
    return std::vector<Rgba>(n, Rgba{0.5f, 0.5f, 0.5f, 1});
  }
  // One UV for every corner: enough for the atlas writer.
  static void add_uvs(MeshData& m) {
    m.uvs = {{0.25f, 0.75f}};
    m.corner_uv.assign(m.face_vertices.size(), 0);
  }
  static std::vector<float> atlas() { return std::vector<float>(4 * 4, 0.5f); }
};

TEST(GlbUpMatrix, SixAxesByHand) {
  EXPECT_EQ(glb_up_matrix({0, 0, 1}), kZUp);
  EXPECT_EQ(glb_up_matrix({0, 0, -1}), kMinusZUp);
  EXPECT_EQ(glb_up_matrix({1, 0, 0}), kXUp);
  EXPECT_EQ(glb_up_matrix({-1, 0, 0}), kMinusXUp);
  EXPECT_EQ(glb_up_matrix({0, 1, 0}), kIdentity);
  EXPECT_EQ(glb_up_matrix({0, -1, 0}), kMinusYUp);
  EXPECT_EQ(glb_up_matrix({0, 0, 7}), kZUp);  // need not be unit
}

// The Z-up sphere of radius 2 around (1, 2, 3): matrix maps +Z to +Y,
// positions as given, NORMAL unit and outward, for both writers.
TEST_F(WriteGlbTest, ZUpSphereHasYUpMatrixSamePositionsOutwardNormals) {
  const Float3 c{1, 2, 3};
  MeshData sphere = test::uv_sphere(c, 2, 12, 24);
  add_uvs(sphere);
  const std::vector<float> image = atlas();
  ASSERT_TRUE(write_vertex_color_glb(dir_ / "v.glb", sphere, grey(sphere.vertex_count())));
  ASSERT_TRUE(write_textured_mesh(dir_ / "a.glb", sphere, {2, 2, image.data()}));
  for (const char* name : {"v.glb", "a.glb"}) {
    SCOPED_TRACE(name);
    const tinygltf::Model model = load(dir_ / name);
    ASSERT_EQ(model.nodes.size(), 1u);
    const std::vector<double>& m = model.nodes[0].matrix;
    ASSERT_EQ(m, std::vector<double>(kZUp.begin(), kZUp.end()));
    EXPECT_EQ(apply(m, 0, 0, 1), (std::array<double, 3>{0, 1, 0}));   // up -> +Y
    EXPECT_EQ(apply(m, 1, 0, 0), (std::array<double, 3>{1, 0, 0}));   // X stays
    EXPECT_EQ(apply(m, 0, 1, 0), (std::array<double, 3>{0, 0, -1}));  // Y -> -Z
    const tinygltf::Primitive& prim = model.meshes.at(0).primitives.at(0);
    ASSERT_TRUE(prim.attributes.count("NORMAL"));
    const tinygltf::Accessor& na = model.accessors[prim.attributes.at("NORMAL")];
    EXPECT_EQ(na.type, TINYGLTF_TYPE_VEC3);
    EXPECT_EQ(na.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
    const std::vector<float> pos = accessor_values<float>(model, prim.attributes.at("POSITION"));
    const std::vector<float> nrm = accessor_values<float>(model, prim.attributes.at("NORMAL"));
    ASSERT_EQ(pos.size(), sphere.vertex_count() * 3);  // one UV, no normals: no split
    ASSERT_EQ(nrm.size(), pos.size());
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
      // The vertex data are the mesh's own, bit for bit.
      EXPECT_EQ(pos[v * 3 + 0], sphere.positions[v].x) << v;
      EXPECT_EQ(pos[v * 3 + 1], sphere.positions[v].y) << v;
      EXPECT_EQ(pos[v * 3 + 2], sphere.positions[v].z) << v;
      const double nx = nrm[v * 3], ny = nrm[v * 3 + 1], nz = nrm[v * 3 + 2];
      EXPECT_NEAR(std::sqrt(nx * nx + ny * ny + nz * nz), 1.0, 1e-6) << v;
      const double dx = pos[v * 3] - c.x, dy = pos[v * 3 + 1] - c.y, dz = pos[v * 3 + 2] - c.z;
      const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
      EXPECT_GT(nx * dx + ny * dy + nz * dz, 0.99 * d) << v;  // outward, |n| = 1
    }
  }
}

TEST_F(WriteGlbTest, EveryUpAxisGivesItsHandWorkedMatrixYGivesNone) {
  MeshData sphere = test::uv_sphere({0, 0, 0}, 1, 4, 6);
  add_uvs(sphere);
  const std::vector<float> image = atlas();
  const std::pair<Vec3, const Matrix*> cases[] = {
      {{0, 0, 1}, &kZUp},       {{0, 0, -1}, &kMinusZUp}, {{1, 0, 0}, &kXUp},
      {{-1, 0, 0}, &kMinusXUp}, {{0, -1, 0}, &kMinusYUp}, {{0, 1, 0}, nullptr}};
  for (const auto& [up, want] : cases) {
    SCOPED_TRACE(std::to_string(up.x) + "," + std::to_string(up.y) + "," + std::to_string(up.z));
    TexturedWriteOptions options;
    options.up = up;
    ASSERT_TRUE(write_vertex_color_glb(dir_ / "v.glb", sphere, grey(sphere.vertex_count()), up));
    ASSERT_TRUE(write_textured_mesh(dir_ / "a.glb", sphere, {2, 2, image.data()}, options));
    for (const char* name : {"v.glb", "a.glb"}) {
      const tinygltf::Model model = load(dir_ / name);
      const std::vector<double>& m = model.nodes.at(0).matrix;
      if (!want) {
        EXPECT_TRUE(m.empty()) << name;  // identity: no matrix
        continue;
      }
      ASSERT_EQ(m, std::vector<double>(want->begin(), want->end())) << name;
      EXPECT_EQ(apply(m, up.x, up.y, up.z), (std::array<double, 3>{0, 1, 0})) << name;
    }
  }
}

TEST_F(WriteGlbTest, ZeroUpIsRefused) {
  MeshData sphere = test::uv_sphere({0, 0, 0}, 1, 4, 6);
  Status s =
      write_vertex_color_glb(dir_ / "v.glb", sphere, grey(sphere.vertex_count()), Vec3{0, 0, 0});
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(s.error().message.find("v.glb"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "v.glb"));
}

// A unit cube with one normal per side (flat, as exporters write hard
// edges): vn 1..6 = +X -X +Y -Y +Z -Z, each face's corners use its side's.
constexpr const char* kFlatCube =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "vn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 2\nvn 0 0 -1\n"
    "f 2//1 3//1 7//1 6//1\n"   // +X
    "f 1//2 5//2 8//2 4//2\n"   // -X
    "f 4//3 8//3 7//3 3//3\n"   // +Y
    "f 1//4 2//4 6//4 5//4\n"   // -Y
    "f 5//5 6//5 7//5 8//5\n"   // +Z (vn not unit: written normalised)
    "f 1//6 4//6 3//6 2//6\n";  // -Z
const float kSideNormal[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                 {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};

TEST_F(WriteGlbTest, InputNormalsAreKeptVertexGlbSplitsHardEdges) {
  auto read = read_mesh(test::write_text(dir_ / "cube.obj", kFlatCube));
  ASSERT_TRUE(read) << read.error().message;
  const MeshData& cube = read->mesh;
  ASSERT_TRUE(write_vertex_color_glb(dir_ / "v.glb", cube, grey(cube.vertex_count())));
  const auto [pos, nrm, idx] = arrays_of(load(dir_ / "v.glb"));
  // Each of the 8 corners of the cube is on 3 sides: 8 * 3 = 24 glTF
  // vertices, the first 8 the input's in order.
  ASSERT_EQ(pos.size(), 24u * 3);
  for (std::size_t v = 0; v < 8; ++v) {
    EXPECT_EQ(pos[v * 3], cube.positions[v].x);
    EXPECT_EQ(pos[v * 3 + 1], cube.positions[v].y);
    EXPECT_EQ(pos[v * 3 + 2], cube.positions[v].z);
  }
  ASSERT_EQ(idx.size(), 6u * 2 * 3);  // each side fanned into two triangles
  for (std::size_t k = 0; k < idx.size(); ++k) {
    const std::size_t side = k / 6;
    for (int a = 0; a < 3; ++a) EXPECT_EQ(nrm[idx[k] * 3 + a], kSideNormal[side][a]) << k;
  }
}

TEST_F(WriteGlbTest, InputNormalsAreKeptInAtlasGlb) {
  auto read = read_mesh(test::write_text(dir_ / "cube.obj", kFlatCube));
  ASSERT_TRUE(read);
  MeshData cube = read->mesh;
  add_uvs(cube);
  const std::vector<float> image = atlas();
  ASSERT_TRUE(write_textured_mesh(dir_ / "a.glb", cube, {2, 2, image.data()}));
  const auto [pos, nrm, idx] = arrays_of(load(dir_ / "a.glb"));
  ASSERT_EQ(pos.size(), 24u * 3);
  ASSERT_EQ(idx.size(), 36u);
  for (std::size_t k = 0; k < idx.size(); ++k) {
    // MeshData::triangles: two per side, in the faces' order.
    const std::size_t side = cube.triangle_face[k / 3];
    for (int a = 0; a < 3; ++a) EXPECT_EQ(nrm[idx[k] * 3 + a], kSideNormal[side][a]) << k;
  }
}

// OBJ in with vn, OBJ out: every corner keeps its normal (the reader gives
// each corner its own vn entry, so the table is not the file's).
TEST_F(WriteGlbTest, ObjNormalsRoundTrip) {
  auto read = read_mesh(test::write_text(dir_ / "cube.obj", kFlatCube));
  ASSERT_TRUE(read);
  ASSERT_TRUE(write_mesh(dir_ / "out.obj", read->mesh));
  const std::string text = test::read_bytes(dir_ / "out.obj");
  EXPECT_NE(text.find("\nvn 0 0 2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nf 2//"), std::string::npos) << text;  // v//vn corners
  auto back = read_mesh(dir_ / "out.obj");
  ASSERT_TRUE(back);
  ASSERT_EQ(back->mesh.corner_normal.size(), 24u);
  for (std::size_t c = 0; c < 24; ++c) {
    const Float3 n = back->mesh.normals[back->mesh.corner_normal[c]];
    const float* want = kSideNormal[c / 4];
    EXPECT_EQ(n.x, want[0]) << c;
    EXPECT_EQ(n.y, want[1]) << c;
    EXPECT_EQ(n.z, want[2] * (c / 4 == 4 ? 2 : 1)) << c;  // as written: not normalised
  }
}

// PLY nx ny nz in: the GLB's NORMAL is the file's, normalised.
TEST_F(WriteGlbTest, PlyVertexNormalsAreKept) {
  const fs::path ply = test::write_text(dir_ / "t.ply",
                                        "ply\nformat ascii 1.0\nelement vertex 3\n"
                                        "property float x\nproperty float y\nproperty float z\n"
                                        "property float nx\nproperty float ny\nproperty float nz\n"
                                        "element face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n"
                                        "0 0 0 0 0 3\n1 0 0 0 4 3\n0 1 0 0 0 -1\n3 0 1 2\n");
  auto read = read_mesh(ply);
  ASSERT_TRUE(read) << read.error().message;
  ASSERT_TRUE(write_vertex_color_glb(dir_ / "v.glb", read->mesh, grey(3)));
  const tinygltf::Model model = load(dir_ / "v.glb");
  const auto nrm =
      accessor_values<float>(model, model.meshes[0].primitives[0].attributes.at("NORMAL"));
  // (0, 0, 3) -> (0, 0, 1); (0, 4, 3) / 5 = (0, 0.8, 0.6); (0, 0, -1).
  const std::vector<float> want = {0, 0, 1, 0, 0.8f, 0.6f, 0, 0, -1};
  ASSERT_EQ(nrm.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(nrm[i], want[i], 1e-7) << i;
}

// A corner without a normal (the OBJ reader pads a zero one) takes the
// smooth normal; a vertex in no face the up axis. Every NORMAL is unit.
TEST_F(WriteGlbTest, MissingNormalsFallBackToSmoothThenUp) {
  // Triangle 1-2-3 in the plane z = 0 (counter-clockwise from +Z) without
  // vn; triangle 1-3-4 with vn (1, 0, 0); vertex 5 unreferenced.
  auto read = read_mesh(test::write_text(
      dir_ / "m.obj",
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 9 9 9\nvn 1 0 0\nf 1 2 3\nf 1//1 3//1 4//1\n"));
  ASSERT_TRUE(read) << read.error().message;
  const MeshData& m = read->mesh;
  ASSERT_TRUE(write_vertex_color_glb(dir_ / "v.glb", m, grey(m.vertex_count()), Vec3{0, -1, 0}));
  const GlbArrays glb = arrays_of(load(dir_ / "v.glb"));
  const std::vector<float>& nrm = glb.nrm;
  const std::vector<uint32_t>& idx = glb.idx;
  ASSERT_EQ(idx.size(), 6u);
  auto normal_of = [&](std::size_t k) {
    return std::array<float, 3>{nrm[idx[k] * 3], nrm[idx[k] * 3 + 1], nrm[idx[k] * 3 + 2]};
  };
  // Vertex 2 (index 1) is only in the first triangle: smooth = (0, 0, 1).
  EXPECT_EQ(normal_of(1), (std::array<float, 3>{0, 0, 1}));
  // The second triangle's corners: the file's (1, 0, 0).
  for (std::size_t k = 3; k < 6; ++k) EXPECT_EQ(normal_of(k), (std::array<float, 3>{1, 0, 0}));
  // Vertex 5 (index 4, in no face): the up axis, (0, -1, 0).
  EXPECT_EQ(nrm[4 * 3 + 0], 0);
  EXPECT_EQ(nrm[4 * 3 + 1], -1);
  EXPECT_EQ(nrm[4 * 3 + 2], 0);
  for (std::size_t i = 0; i < nrm.size(); i += 3) {
    EXPECT_NEAR(std::hypot(nrm[i], nrm[i + 1], nrm[i + 2]), 1.0, 1e-6) << i / 3;
  }
}

}  // namespace
}  // namespace texbake
