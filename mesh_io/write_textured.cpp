#include "mesh_io/write_textured.h"

// Debian ships tinygltf as a shared library (libtinygltf.so, README.Debian):
// its implementation (and the stb image code it uses) lives there, so this
// file includes only the declarations and defines no TINYGLTF_IMPLEMENTATION.
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "mapping/sample.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/file_name.h"
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

tinygltf::Model new_model() {
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
  const bool normals =
      !mesh.corner_normal.empty() && mesh.corner_normal.size() == mesh.face_vertices.size();

  // One glTF vertex per distinct (vertex, uv[, normal]) corner, in order of
  // first use: deterministic.
  std::unordered_map<CornerKey, uint32_t, CornerKeyHash> index_of;
  std::vector<float> xyz, st, nrm;
  std::vector<uint32_t> indices;
  indices.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t corner = mesh.triangle_corners[t][k];
      const CornerKey key{mesh.triangles[t][k], mesh.corner_uv[corner],
                          normals ? mesh.corner_normal[corner] : 0u};
      auto [it, added] = index_of.try_emplace(key, static_cast<uint32_t>(xyz.size() / 3));
      if (added) {
        const Float3 p = mesh.positions[key.vertex];
        xyz.insert(xyz.end(), {p.x, p.y, p.z});
        const Float2 uv = mesh.uvs[key.uv];
        st.insert(st.end(), {uv.u, 1.0f - uv.v});  // glTF: origin at the top-left
        if (normals) {
          const Float3 n = mesh.normals[key.normal];
          const float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
          const float inv = len > 0 ? 1 / len : 0;
          nrm.insert(nrm.end(), {n.x * inv, n.y * inv, n.z * inv});
        }
      }
      indices.push_back(it->second);
    }
  }

  return write_atomically(path, [&](const fs::path& temp) -> Status {
    ImageWriteOptions io;
    io.bit_depth = options.bit_depth;
    io.png_compression = options.png_compression;
    auto png = encode_image(atlas, ".png", io);
    if (!png) return png.error();
    tinygltf::Model model = new_model();
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.indices = add_accessor(model, indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                TINYGLTF_TYPE_SCALAR, 1, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    prim.attributes["POSITION"] = add_positions(model, xyz);
    prim.attributes["TEXCOORD_0"] =
        add_accessor(model, st, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 2,
                     TINYGLTF_TARGET_ARRAY_BUFFER);
    if (normals) {
      prim.attributes["NORMAL"] = add_accessor(model, nrm, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                               TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER);
    }
    prim.material = 0;
    tinygltf::Mesh gmesh;
    gmesh.primitives.push_back(prim);
    model.meshes.push_back(gmesh);

    tinygltf::Image image;
    image.mimeType = "image/png";
    image.bufferView = add_view(model, png->data(), png->size(), 0);
    model.images.push_back(image);
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    sampler.wrapS =
        options.repeat_u ? TINYGLTF_TEXTURE_WRAP_REPEAT : TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    model.samplers.push_back(sampler);
    tinygltf::Texture texture;
    texture.source = 0;
    texture.sampler = 0;
    model.textures.push_back(texture);
    tinygltf::Material material;
    material.name = "texbake";
    material.pbrMetallicRoughness.baseColorTexture.index = 0;
    material.pbrMetallicRoughness.metallicFactor = 0;
    material.pbrMetallicRoughness.roughnessFactor = 1;
    model.materials.push_back(material);
    return serialise_glb(path, temp, model);
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
  io.file_set = &set;
  if (Status s = write_image(image_path, atlas, io); !s) return s;
  MeshWriteOptions mo;
  mo.obj_material_texture = image_path.filename().string();  // relative: beside the OBJ
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

Status write_vertex_color_glb(const fs::path& path, const MeshData& mesh,
                              std::span<const Rgba> colors) {
  if (colors.size() != mesh.vertex_count()) {
    return make_error(ErrorCode::kInternal, "cannot write " + path.string() + ": " +
                                                std::to_string(colors.size()) + " colours for " +
                                                std::to_string(mesh.vertex_count()) + " vertices");
  }
  // Every face, fan-triangulated (degenerate ones included: the input's
  // faces are kept, SPEC section 8).
  std::vector<uint32_t> indices;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
    for (uint32_t c = b + 1; c + 1 < e; ++c) {
      indices.insert(indices.end(),
                     {mesh.face_vertices[b], mesh.face_vertices[c], mesh.face_vertices[c + 1]});
    }
  }
  if (indices.empty() || mesh.vertex_count() == 0) {
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
  return write_atomically(path, [&](const fs::path& temp) -> Status {
    tinygltf::Model model = new_model();
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.indices = add_accessor(model, indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                TINYGLTF_TYPE_SCALAR, 1, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    prim.attributes["POSITION"] = add_positions(model, xyz);
    prim.attributes["COLOR_0"] = add_accessor(model, rgba, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                              TINYGLTF_TYPE_VEC4, 4, TINYGLTF_TARGET_ARRAY_BUFFER);
    prim.material = 0;
    tinygltf::Mesh gmesh;
    gmesh.primitives.push_back(prim);
    model.meshes.push_back(gmesh);
    tinygltf::Material material;
    material.name = "texbake";
    material.pbrMetallicRoughness.metallicFactor = 0;
    material.pbrMetallicRoughness.roughnessFactor = 1;
    model.materials.push_back(material);
    return serialise_glb(path, temp, model);
  });
}

}  // namespace texbake
