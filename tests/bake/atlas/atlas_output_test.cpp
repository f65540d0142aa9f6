// Textured outputs re-opened with independent readers: a small OBJ/MTL parser
// written here, OpenImageIO (read_image) for the atlas, tinygltf's loader for
// GLB (accessors, texture reference, embedded PNG, COLOR_0).
#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "mesh_io/write_textured.h"
#include "tests/bake/atlas/atlas_test_util.h"

namespace texbake {
namespace {
namespace fs = std::filesystem;

class AtlasOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_atlas_out_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A unit square of two triangles, UVs = positions, shared UV table.
    mesh_.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh_.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh_.face_offsets = {0, 3, 6};
    mesh_.face_vertices = {0, 1, 2, 0, 2, 3};
    mesh_.corner_uv = {0, 1, 2, 0, 2, 3};
    mesh_.triangles = {{0, 1, 2}, {0, 2, 3}};
    mesh_.triangle_corners = {{0, 1, 2}, {3, 4, 5}};
    mesh_.triangle_face = {0, 1};
    // 4 x 2 atlas, values on the 8-bit grid so PNG round trips exactly.
    atlas_.resize(4 * 2 * 4);
    for (int i = 0; i < 8; ++i) {
      atlas_[i * 4 + 0] = (i * 30) / 255.f;
      atlas_[i * 4 + 1] = (255 - i * 20) / 255.f;
      atlas_[i * 4 + 2] = (i % 2 ? 255 : 0) / 255.f;
      atlas_[i * 4 + 3] = 1;
    }
  }
  void TearDown() override {
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add);
    fs::remove_all(dir_);
  }
  ImageView view() const { return {4, 2, atlas_.data()}; }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  template <class T>
  static std::vector<T> accessor_values(const tinygltf::Model& m, int index) {
    const tinygltf::Accessor& a = m.accessors[index];
    const tinygltf::BufferView& v = m.bufferViews[a.bufferView];
    const unsigned char* p = m.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset;
    const std::size_t n = a.count * tinygltf::GetNumComponentsInType(a.type);
    std::vector<T> out(n);
    std::memcpy(out.data(), p, n * sizeof(T));
    return out;
  }

  fs::path dir_;
  MeshData mesh_;
  std::vector<float> atlas_;
};

TEST_F(AtlasOutputTest, ObjMtlAndPngReferenceEachOther) {
  const fs::path obj = dir_ / "out.obj";
  ASSERT_TRUE(write_textured_mesh(obj, mesh_, view()));
  ASSERT_TRUE(fs::exists(dir_ / "out.png"));
  ASSERT_TRUE(fs::exists(dir_ / "out.mtl"));

  // Parse the OBJ: v, vt, f v/vt, mtllib, usemtl.
  std::istringstream in(slurp(obj));
  std::string line, mtllib, usemtl;
  std::vector<Float3> v;
  std::vector<Float2> vt;
  std::vector<std::pair<int, int>> corners;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      Float3 p;
      ls >> p.x >> p.y >> p.z;
      v.push_back(p);
    } else if (tag == "vt") {
      Float2 q;
      ls >> q.u >> q.v;
      vt.push_back(q);
    } else if (tag == "f") {
      std::string c;
      int n = 0;
      while (ls >> c) {
        const auto slash = c.find('/');
        ASSERT_NE(slash, std::string::npos) << line;
        corners.push_back({std::stoi(c.substr(0, slash)) - 1, std::stoi(c.substr(slash + 1)) - 1});
        ++n;
      }
      EXPECT_EQ(n, 3);
    } else if (tag == "mtllib") {
      ls >> mtllib;
    } else if (tag == "usemtl") {
      ls >> usemtl;
    }
  }
  EXPECT_EQ(mtllib, "out.mtl");
  ASSERT_EQ(v.size(), 4u);
  ASSERT_EQ(corners.size(), 6u);
  for (std::size_t c = 0; c < 6; ++c) {
    EXPECT_EQ(corners[c].first, static_cast<int>(mesh_.face_vertices[c]));
    const Float2 q = vt.at(corners[c].second), want = mesh_.uvs[mesh_.corner_uv[c]];
    EXPECT_FLOAT_EQ(q.u, want.u);
    EXPECT_FLOAT_EQ(q.v, want.v);
  }

  // The MTL names the material the OBJ uses and the PNG by relative path.
  std::istringstream mtl(slurp(dir_ / "out.mtl"));
  std::string newmtl, map_kd;
  while (std::getline(mtl, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "newmtl") ls >> newmtl;
    if (tag == "map_Kd") ls >> map_kd;
  }
  EXPECT_EQ(newmtl, usemtl);
  EXPECT_EQ(map_kd, "out.png");

  auto img = read_image(dir_ / map_kd);
  ASSERT_TRUE(img) << img.error().message;
  ASSERT_EQ(img->width, 4);
  ASSERT_EQ(img->height, 2);
  for (std::size_t i = 0; i < atlas_.size(); ++i) EXPECT_NEAR(img->pixels[i], atlas_[i], 1e-6);
}

TEST_F(AtlasOutputTest, UnwritableAtlasLeavesNothing) {
  fs::create_directories(dir_ / "out.png");  // a folder where the atlas should go
  auto s = write_textured_mesh(dir_ / "out.obj", mesh_, view());
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kIo);
  EXPECT_NE(s.error().message.find("out.png"), std::string::npos) << s.error().message;
  EXPECT_FALSE(fs::exists(dir_ / "out.obj"));
  EXPECT_FALSE(fs::exists(dir_ / "out.mtl"));
  // Only the blocking folder remains: no temporary files either.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(AtlasOutputTest, UnwritableObjRemovesAtlasAndMtl) {
  fs::create_directories(dir_ / "out.obj");  // the OBJ itself cannot be written
  auto s = write_textured_mesh(dir_ / "out.obj", mesh_, view());
  ASSERT_FALSE(s);
  EXPECT_FALSE(fs::exists(dir_ / "out.png"));
  EXPECT_FALSE(fs::exists(dir_ / "out.mtl"));
}

TEST_F(AtlasOutputTest, BadRequestsAreRejected) {
  auto s = write_textured_mesh(dir_ / "out.ply", mesh_, view());
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kUnsupported);
  EXPECT_NE(s.error().message.find("PLY"), std::string::npos);
  TexturedWriteOptions exr;
  exr.bit_depth = ImageBitDepth::kFloat;
  s = write_textured_mesh(dir_ / "out.glb", mesh_, view(), exr);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kUnsupported);
  MeshData no_uv = mesh_;
  no_uv.uvs.clear();
  no_uv.corner_uv.clear();
  s = write_textured_mesh(dir_ / "out.obj", no_uv, view());
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kInvalidArgument);
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(AtlasOutputTest, GlbWithEmbeddedAtlasReopensWithTinygltf) {
  const fs::path glb = dir_ / "out.glb";
  TexturedWriteOptions opt;
  opt.repeat_u = true;
  ASSERT_TRUE(write_textured_mesh(glb, mesh_, view(), opt));
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, glb.string())) << err;
  ASSERT_EQ(model.meshes.size(), 1u);
  const tinygltf::Primitive& prim = model.meshes[0].primitives.at(0);
  EXPECT_EQ(prim.mode, TINYGLTF_MODE_TRIANGLES);
  const auto pos = accessor_values<float>(model, prim.attributes.at("POSITION"));
  const auto st = accessor_values<float>(model, prim.attributes.at("TEXCOORD_0"));
  const auto idx = accessor_values<uint32_t>(model, prim.indices);
  ASSERT_EQ(idx.size(), 6u);
  ASSERT_EQ(pos.size(), 12u);  // 4 distinct (vertex, uv) corners
  for (std::size_t c = 0; c < 6; ++c) {
    const uint32_t gv = idx[c];
    const Float3 p = mesh_.positions[mesh_.face_vertices[c]];
    const Float2 uv = mesh_.uvs[mesh_.corner_uv[c]];
    EXPECT_FLOAT_EQ(pos[gv * 3 + 0], p.x);
    EXPECT_FLOAT_EQ(pos[gv * 3 + 1], p.y);
    EXPECT_FLOAT_EQ(pos[gv * 3 + 2], p.z);
    EXPECT_FLOAT_EQ(st[gv * 2 + 0], uv.u);
    EXPECT_FLOAT_EQ(st[gv * 2 + 1], 1 - uv.v);  // glTF's t runs down the image
  }
  const tinygltf::Accessor& pa = model.accessors[prim.attributes.at("POSITION")];
  EXPECT_EQ(pa.minValues, (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(pa.maxValues, (std::vector<double>{1, 1, 0}));

  // Material -> texture -> image (embedded PNG in a bufferView) + sampler.
  const tinygltf::Material& mat = model.materials.at(prim.material);
  const int tex = mat.pbrMetallicRoughness.baseColorTexture.index;
  ASSERT_GE(tex, 0);
  const tinygltf::Texture& texture = model.textures.at(tex);
  const tinygltf::Image& image = model.images.at(texture.source);
  EXPECT_EQ(image.mimeType, "image/png");
  EXPECT_GE(image.bufferView, 0);
  EXPECT_EQ(model.samplers.at(texture.sampler).wrapS, TINYGLTF_TEXTURE_WRAP_REPEAT);
  EXPECT_EQ(model.samplers.at(texture.sampler).wrapT, TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE);
  // tinygltf decoded the PNG (stb_image): the 8-bit values of the atlas.
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 2);
  ASSERT_EQ(image.bits, 8);
  const int comp = image.component;
  ASSERT_GE(comp, 3);
  for (int i = 0; i < 8; ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(image.image[i * comp + c], std::lround(atlas_[i * 4 + c] * 255)) << i << "," << c;
    }
  }
}

// COLOR_0 = linearised sRGB, by the IEC 61966-2-1 formula worked here:
// 0 -> 0, 1 -> 1, 0.5 -> ((0.5 + 0.055) / 1.055)^2.4 = 0.2140411,
// 0.2 -> ((0.255) / 1.055)^2.4 = 0.0331048, 0.04 -> 0.04 / 12.92 = 0.0030960.
TEST_F(AtlasOutputTest, VertexColourGlbHasLinearColor0) {
  const std::vector<Rgba> colors = {
      {0, 1, 0.5f, 1}, {0.2f, 0.04f, 1, 0.5f}, {1, 1, 1, 1}, {0.5f, 0.5f, 0.5f, 0.25f}};
  const fs::path glb = dir_ / "v.glb";
  ASSERT_TRUE(write_vertex_color_glb(glb, mesh_, colors));
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, glb.string())) << err;
  const tinygltf::Primitive& prim = model.meshes.at(0).primitives.at(0);
  const tinygltf::Accessor& ca = model.accessors[prim.attributes.at("COLOR_0")];
  EXPECT_EQ(ca.type, TINYGLTF_TYPE_VEC4);
  EXPECT_EQ(ca.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const auto col = accessor_values<float>(model, prim.attributes.at("COLOR_0"));
  const std::vector<float> want = {0,          1,          0.2140411f, 1,     //
                                   0.0331048f, 0.0030960f, 1,          0.5f,  //
                                   1,          1,          1,          1,     //
                                   0.2140411f, 0.2140411f, 0.2140411f, 0.25f};
  ASSERT_EQ(col.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(col[i], want[i], 2e-6) << i;
  // Vertices in the input's order, faces as given.
  const auto pos = accessor_values<float>(model, prim.attributes.at("POSITION"));
  ASSERT_EQ(pos.size(), 12u);
  for (int v = 0; v < 4; ++v) EXPECT_FLOAT_EQ(pos[v * 3], mesh_.positions[v].x);
  EXPECT_EQ(accessor_values<uint32_t>(model, prim.indices),
            (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

}  // namespace
}  // namespace texbake
