#include "mesh_io/write_textured.h"

// Debian ships tinygltf as a shared library (libtinygltf.so, README.Debian):
// its implementation (and the stb image code it uses) lives there, so this
// file includes only the declarations and defines no TINYGLTF_IMPLEMENTATION.
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "mapping/sample.h"
#include "mapping/vec.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/file_name.h"
#include "mesh_io/vertex_normals.h"
#include "mesh_io/write_mesh.h"

namespace texbake {
namespace fs = std::filesystem;

namespace {

bool has_corner_uvs(const MeshData& mesh) {
  return mesh.has_uvs() && mesh.corner_uv.size() == mesh.face_vertices.size();
}

// Appends raw bytes to the single GLB buffer as a new bufferView (4-byte
// aligned, as accessors of 4-byte components require).
int add_view(tinygltf::Model& model, const void* data, std::size_t bytes, int target) {
  std::vector<unsigned char>& buf = model.buffers[0].data;
  while (buf.size() % 4) buf.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buf.insert(buf.end(), p, p + bytes);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

template <class T>
int add_accessor(tinygltf::Model& model, const std::vector<T>& values, int component_type, int type,
                 int components, int target) {
  tinygltf::Accessor acc;
  acc.bufferView = add_view(model, values.data(), values.size() * sizeof(T), target);
  acc.componentType = component_type;
  acc.type = type;
  acc.count = values.size() / components;  // T is one component (float or uint32)
  model.accessors.push_back(acc);
  return static_cast<int>(model.accessors.size() - 1);
}

// POSITION needs min and max (glTF 2.0, section 5.1.1 accessor.min/max).
int add_positions(tinygltf::Model& model, const std::vector<float>& xyz) {
  const int index = add_accessor(model, xyz, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3,
                                 TINYGLTF_TARGET_ARRAY_BUFFER);
  tinygltf::Accessor& acc = model.accessors[index];
  acc.minValues.assign(3, std::numeric_limits<double>::infinity());
  acc.maxValues.assign(3, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    acc.minValues[i % 3] = std::min<double>(acc.minValues[i % 3], xyz[i]);
    acc.maxValues[i % 3] = std::max<double>(acc.maxValues[i % 3], xyz[i]);
  }
  return index;
}

tinygltf::Model new_model(Vec3 up) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "texbake";
  model.buffers.emplace_back();
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  tinygltf::Node node;
  node.mesh = 0;
  const std::array<double, 16> m = glb_up_matrix(up);
  constexpr std::array<double, 16> kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  if (m != kIdentity) node.matrix.assign(m.begin(), m.end());  // none: identity (glTF default)
  model.nodes.push_back(node);
  return model;
}

Status serialise_glb(const fs::path& target, const fs::path& temp, tinygltf::Model& model) {
  std::ostringstream os(std::ios::binary);
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, os, false, true)) {
    return make_error(ErrorCode::kInternal, "cannot write " + target.string() +
                                                ": tinygltf failed to serialise the model");
  }
  const std::string bytes = os.str();
  std::ofstream out(temp, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) return make_error(ErrorCode::kIo, "cannot write " + target.string());
  return ok_status();
}

// What both GLB writers build: the triangle list and, per glTF vertex, its
// position and unit normal.
struct GlbGeometry {
  std::vector<uint32_t> indices;
  std::vector<float> xyz, normals;  // 3 per glTF vertex
};

// The normal of each corner: the input's (corner_normal, when there is one
// per corner) normalised; where that is missing, zero or not finite, the
// vertex's smooth normal (mesh_io/vertex_normals.h); where that is zero too
// (a vertex in degenerate faces only, or in none), `up` normalised.
class CornerNormals {
 public:
  static constexpr uint32_t kNoCorner = std::numeric_limits<uint32_t>::max();
  CornerNormals(const MeshData& mesh, Vec3 up)
      : mesh_(mesh),
        input_(!mesh.corner_normal.empty() &&
               mesh.corner_normal.size() == mesh.face_vertices.size()),
        up_(normalize(up)) {
    bool complete = input_;
    if (input_) {
      // The readers give a corner its own entry even where the file shares
      // one (OpenMesh's OBJ reader reports vn per corner): equal values are
      // one normal, so a smooth mesh's vertices are not split.
      std::unordered_map<std::array<uint32_t, 3>, uint32_t, BitsHash> first;
      canonical_.resize(mesh.normals.size());
      for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        const Float3 f = mesh.normals[i];
        complete = complete && usable(f);
        std::array<uint32_t, 3> bits;
        const float xyz[3] = {f.x + 0.f, f.y + 0.f, f.z + 0.f};  // -0 as 0
        std::memcpy(bits.data(), xyz, sizeof bits);
        canonical_[i] = first.try_emplace(bits, static_cast<uint32_t>(i)).first->second;
      }
    }
    for (std::size_t c = 0; complete && c < mesh.corner_normal.size(); ++c) {
      complete = mesh.corner_normal[c] < mesh.normals.size();
    }
    if (!complete) smooth_ = smooth_vertex_normals(mesh);
  }
  // The normal's identity at a corner: the first index in mesh.normals of
  // its value (0 when the normals are the smooth ones, which are per
  // vertex; kNoCorner for kNoCorner, a vertex in no face). A glTF vertex
  // per distinct (vertex[, UV], key).
  uint32_t key(uint32_t corner) const {
    if (corner == kNoCorner) return kNoCorner;
    if (!input_) return 0;
    const uint32_t n = mesh_.corner_normal[corner];
    return n < canonical_.size() ? canonical_[n] : n;
  }
  // The unit normal at `corner` (of vertex `vertex`; kNoCorner for a vertex
  // in no face), appended to `out` as three floats; corner is ignored when
  // the normals are smooth.
  void append(std::vector<float>& out, uint32_t vertex, uint32_t corner) const {
    Vec3 n{};
    if (input_ && corner != kNoCorner && mesh_.corner_normal[corner] < mesh_.normals.size()) {
      const Float3 f = mesh_.normals[mesh_.corner_normal[corner]];
      if (usable(f)) n = normalize(Vec3{f.x, f.y, f.z});
    }
    if (n == Vec3{} && !smooth_.empty()) {
      const Float3 f = smooth_[vertex];
      n = {f.x, f.y, f.z};
    }
    if (n == Vec3{}) n = up_;
    out.insert(out.end(),
               {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)});
  }

 private:
  struct BitsHash {
    std::size_t operator()(const std::array<uint32_t, 3>& b) const {
      uint64_t h = (uint64_t{b[0]} << 32 | b[1]) * 0x9E3779B97F4A7C15ull;
      h ^= (uint64_t{b[2]} + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull;
      return static_cast<std::size_t>(h ^ (h >> 31));
    }
  };
  static bool usable(Float3 f) {
    const Vec3 v{f.x, f.y, f.z};
    return is_finite(v) && length(v) > 0;
  }
  const MeshData& mesh_;
  bool input_;
  Vec3 up_;
  std::vector<uint32_t> canonical_;  // per input normal: first index of its value
  std::vector<Float3> smooth_;       // empty when every input normal is usable
};

// Adds to the model what the writer adds to the shared GLB (attributes of
// the primitive, parts of the material, images and textures).
using GlbFinish =
    std::function<Status(tinygltf::Model&, tinygltf::Primitive&, tinygltf::Material&)>;

// The GLB both writers write (atomically): one scene of one node whose
// matrix turns `up` to +Y (glb_up_matrix; no matrix when that is the
// identity), holding one mesh of one triangle primitive with indices,
// POSITION (with min/max) and NORMAL, and material 0 (metallic 0, roughness
// 1); `finish` adds the rest before serialisation.
Status write_glb(const fs::path& path, const GlbGeometry& geometry, Vec3 up,
                 const GlbFinish& finish) {
  return write_atomically(path, [&](const fs::path& temp) -> Status {
    tinygltf::Model model = new_model(up);
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.indices = add_accessor(model, geometry.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                TINYGLTF_TYPE_SCALAR, 1, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    prim.attributes["POSITION"] = add_positions(model, geometry.xyz);
    prim.attributes["NORMAL"] = add_accessor(model, geometry.normals, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                             TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER);
    prim.material = 0;
    tinygltf::Material material;
    material.name = "texbake";
    material.pbrMetallicRoughness.metallicFactor = 0;
    material.pbrMetallicRoughness.roughnessFactor = 1;
    if (Status s = finish(model, prim, material); !s) return s;
    tinygltf::Mesh gmesh;
    gmesh.primitives.push_back(prim);
    model.meshes.push_back(gmesh);
    model.materials.push_back(material);
    return serialise_glb(path, temp, model);
  });
}

Status check_up(const fs::path& path, Vec3 up) {
  if (!is_finite(up) || length(up) == 0) {
    return make_error(ErrorCode::kInvalidArgument,
                      "cannot write " + path.string() + ": the up direction must be non-zero");
  }
  return ok_status();
}

struct CornerKey {
  uint32_t vertex, uv, normal;
  bool operator==(const CornerKey&) const = default;
};
struct CornerKeyHash {
  std::size_t operator()(const CornerKey& k) const {
    uint64_t h = k.vertex * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t{k.uv} + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull;
    h ^= (uint64_t{k.normal} + 0x94D049BB133111EBull) * 0x94D049BB133111EBull;
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
};

Status write_textured_glb(const fs::path& path, const MeshData& mesh, const ImageView& atlas,
                          const TexturedWriteOptions& options) {
  if (options.bit_depth == ImageBitDepth::kFloat) {
    return make_error(ErrorCode::kUnsupported,
                      "cannot write " + path.string() +
                          ": a .glb embeds its atlas as PNG (use --format png8 or png16)");
  }
  if (mesh.triangles.empty()) {
    return make_error(ErrorCode::kInvalidArgument,
                      "cannot write " + path.string() + ": the mesh has no triangles");
  }
  if (Status s = check_up(path, options.up); !s) return s;
  const CornerNormals normals(mesh, options.up);

  // One glTF vertex per distinct (vertex, uv[, input normal]) corner, in
  // order of first use: deterministic.
  std::unordered_map<CornerKey, uint32_t, CornerKeyHash> index_of;
  GlbGeometry g;
  std::vector<float> st;
  g.indices.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t corner = mesh.triangle_corners[t][k];
      const CornerKey key{mesh.triangles[t][k], mesh.corner_uv[corner], normals.key(corner)};
      auto [it, added] = index_of.try_emplace(key, static_cast<uint32_t>(g.xyz.size() / 3));
      if (added) {
        const Float3 p = mesh.positions[key.vertex];
        g.xyz.insert(g.xyz.end(), {p.x, p.y, p.z});
        const Float2 uv = mesh.uvs[key.uv];
        st.insert(st.end(), {uv.u, 1.0f - uv.v});  // glTF: origin at the top-left
        normals.append(g.normals, key.vertex, corner);
      }
      g.indices.push_back(it->second);
    }
  }

  return write_glb(path, g, options.up,
                   [&](tinygltf::Model& model, tinygltf::Primitive& prim,
                       tinygltf::Material& material) -> Status {
                     ImageWriteOptions io;
                     io.bit_depth = options.bit_depth;
                     io.png_compression = options.png_compression;
                     // baseColorTexture is sRGB; glTF ignores PNG colour
                     // chunks and its validator warns about them.
                     io.encode_for_format = true;
                     io.tag_color_space = false;
                     auto png = encode_image(atlas, ".png", io);
                     if (!png) return png.error();
                     prim.attributes["TEXCOORD_0"] =
                         add_accessor(model, st, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2,
                                      2, TINYGLTF_TARGET_ARRAY_BUFFER);
                     tinygltf::Image image;
                     image.mimeType = "image/png";
                     image.bufferView = add_view(model, png->data(), png->size(), 0);
                     model.images.push_back(image);
                     tinygltf::Sampler sampler;
                     sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
                     sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
                     sampler.wrapS = options.repeat_u ? TINYGLTF_TEXTURE_WRAP_REPEAT
                                                      : TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
                     sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
                     model.samplers.push_back(sampler);
                     tinygltf::Texture texture;
                     texture.source = 0;
                     texture.sampler = 0;
                     model.textures.push_back(texture);
                     material.pbrMetallicRoughness.baseColorTexture.index = 0;
                     // Coverage alpha (layers over base "none") is blended
                     // by glTF viewers only with alphaMode BLEND.
                     if (options.blend) material.alphaMode = "BLEND";
                     return ok_status();
                   });
}

Status write_textured_obj(const fs::path& path, const MeshData& mesh, const ImageView& atlas,
                          const TexturedWriteOptions& options) {
  const fs::path image_path = atlas_path_for(path, options.bit_depth);
  const fs::path mtl_path = fs::path(path).replace_extension(".mtl");
  for (const fs::path& p : {path, image_path, mtl_path}) {
    if (Status s = check_writable(p); !s) return s;
  }
  // The three files are staged, then renamed together (image, MTL, OBJ
  // last): a failure or an interruption while writing leaves the previous
  // set untouched (atomic_file.h).
  AtomicFileSet set;
  ImageWriteOptions io;
  io.bit_depth = options.bit_depth;
  io.png_compression = options.png_compression;
  io.encode_for_format = true;  // EXR linear, PNG sRGB, tagged
  io.file_set = &set;
  if (Status s = write_image(image_path, atlas, io); !s) return s;
  MeshWriteOptions mo;
  mo.obj_material_texture = image_path.filename().string();  // relative: beside the OBJ
  mo.obj_material_alpha = options.blend;
  mo.file_set = &set;
  if (Status s = write_mesh(path, mesh, mo); !s) return s;
  return set.commit();
}

}  // namespace

fs::path atlas_path_for(const fs::path& obj_path, ImageBitDepth depth) {
  return fs::path(obj_path).replace_extension(depth == ImageBitDepth::kFloat ? ".exr" : ".png");
}

Status write_textured_mesh(const fs::path& path, const MeshData& mesh, const ImageView& atlas,
                           const TexturedWriteOptions& options) {
  const std::string ext = lower_extension(path);
  if (ext != ".obj" && ext != ".glb") {
    return make_error(ErrorCode::kUnsupported,
                      "cannot write " + path.string() + ": an atlas needs an .obj or .glb output" +
                          (ext == ".ply" ? " (PLY has no standard texture)" : ""));
  }
  if (!has_corner_uvs(mesh)) {
    return make_error(ErrorCode::kInvalidArgument,
                      "cannot write " + path.string() + ": the mesh has no per-corner UVs");
  }
  if (atlas.width < 1 || atlas.height < 1 || atlas.data == nullptr) {
    return make_error(ErrorCode::kInvalidArgument,
                      "cannot write " + path.string() + ": the atlas is empty");
  }
  return ext == ".obj" ? write_textured_obj(path, mesh, atlas, options)
                       : write_textured_glb(path, mesh, atlas, options);
}

std::array<double, 16> glb_up_matrix(Vec3 up) {
  // Rodrigues' formula for the rotation taking unit u to y = +Y:
  // R = I + [v]x + [v]x^2 / (1 + c), v = u x y, c = u . y; exact (entries 0,
  // +-1) for the six axes. u = -Y has no smallest rotation: 180 degrees
  // about X.
  const Vec3 u = normalize(up), y{0, 1, 0};
  double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const double c = dot(u, y);
  if (c < -1 + 1e-12) {
    r[1][1] = r[2][2] = -1;
  } else {
    const Vec3 v = cross(u, y);
    const double k[3][3] = {{0, -v.z, v.y}, {v.z, 0, -v.x}, {-v.y, v.x, 0}};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        double k2 = 0;
        for (int m = 0; m < 3; ++m) k2 += k[i][m] * k[m][j];
        r[i][j] += k[i][j] + k2 / (1 + c);
      }
    }
  }
  std::array<double, 16> m{};  // column-major
  for (int col = 0; col < 3; ++col) {
    for (int row = 0; row < 3; ++row) m[col * 4 + row] = r[row][col] + 0.0;  // no -0
  }
  m[15] = 1;
  return m;
}

Status write_vertex_color_glb(const fs::path& path, const MeshData& mesh,
                              std::span<const Rgba> colors, Vec3 up) {
  if (colors.size() != mesh.vertex_count()) {
    return make_error(ErrorCode::kInternal, "cannot write " + path.string() + ": " +
                                                std::to_string(colors.size()) + " colours for " +
                                                std::to_string(mesh.vertex_count()) + " vertices");
  }
  if (Status s = check_up(path, up); !s) return s;
  // Every face, fan-triangulated (degenerate ones included: the input's
  // faces are kept, SPEC section 8). The first vertex_count() glTF vertices
  // are the input's, in order, each with the normal of its first corner; a
  // corner whose input normal is another gets a copy of its vertex, appended
  // in order of first use.
  const CornerNormals normals(mesh, up);
  constexpr uint32_t kNoCorner = CornerNormals::kNoCorner;
  std::vector<uint32_t> first_corner(mesh.vertex_count(), kNoCorner);
  for (uint32_t c = 0; c < mesh.face_vertices.size(); ++c) {
    if (first_corner[mesh.face_vertices[c]] == kNoCorner) first_corner[mesh.face_vertices[c]] = c;
  }
  std::unordered_map<CornerKey, uint32_t, CornerKeyHash> copy_of;
  std::vector<uint32_t> copy_corner;  // the first corner of each copy
  const auto gltf_vertex = [&](uint32_t c) -> uint32_t {
    const uint32_t v = mesh.face_vertices[c];
    if (normals.key(c) == normals.key(first_corner[v])) return v;
    const auto next = static_cast<uint32_t>(mesh.vertex_count() + copy_corner.size());
    auto [it, added] = copy_of.try_emplace(CornerKey{v, 0, normals.key(c)}, next);
    if (added) copy_corner.push_back(c);
    return it->second;
  };
  GlbGeometry g;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
    for (uint32_t c = b + 1; c + 1 < e; ++c) {
      for (uint32_t corner : {b, c, c + 1}) g.indices.push_back(gltf_vertex(corner));
    }
  }
  if (g.indices.empty() || mesh.vertex_count() == 0) {
    return make_error(ErrorCode::kInvalidArgument,
                      "cannot write " + path.string() + ": the mesh has no faces");
  }
  std::vector<float> xyz, rgba;
  xyz.reserve(mesh.vertex_count() * 3);
  rgba.reserve(mesh.vertex_count() * 4);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const Float3 p = mesh.positions[v];
    xyz.insert(xyz.end(), {p.x, p.y, p.z});
    for (int c = 0; c < 4; ++c) {
      float x = colors[v][c];
      x = std::isnan(x) ? 0.f : std::clamp(x, 0.f, 1.f);
      rgba.push_back(c < 3 ? srgb_to_linear(x) : x);  // glTF COLOR_0 is linear
    }
  }
  g.xyz = std::move(xyz);
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v) normals.append(g.normals, v, first_corner[v]);
  for (uint32_t c : copy_corner) {
    const uint32_t v = mesh.face_vertices[c];
    const Float3 p = mesh.positions[v];
    g.xyz.insert(g.xyz.end(), {p.x, p.y, p.z});
    for (int k = 0; k < 4; ++k) {
      const float x = rgba[std::size_t{v} * 4 + k];
      rgba.push_back(x);
    }
    normals.append(g.normals, v, c);
  }
  return write_glb(
      path, g, up,
      [&](tinygltf::Model& model, tinygltf::Primitive& prim, tinygltf::Material& material) {
        prim.attributes["COLOR_0"] =
            add_accessor(model, rgba, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 4,
                         TINYGLTF_TARGET_ARRAY_BUFFER);
        // Colours that are not opaque (layers over base "none":
        // alpha is the coverage) are blended by glTF viewers
        // only with alphaMode BLEND; opaque ones stay OPAQUE.
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
          if (colors[v][3] < 1) {
            material.alphaMode = "BLEND";
            break;
          }
        }
        return ok_status();
      });
}

}  // namespace texbake
