#include "mesh_io/mesh_texture.h"

namespace texbake {

Expected<Image> read_mesh_texture(const MeshData& mesh, const ImageReadOptions& options) {
  ImageReadOptions o = options;
  if (mesh.texture_is_srgb && o.color_space == TextureColorSpace::kAuto) {
    o.color_space = TextureColorSpace::kSrgb;
  }
  if (!mesh.texture_path.empty()) return read_image(mesh.texture_path, o);
  if (!mesh.texture_bytes.empty()) {
    return read_image_from_memory(mesh.texture_bytes, mesh.texture_mime_type,
                                  mesh.texture_name.empty() ? "embedded image" : mesh.texture_name,
                                  o);
  }
  return make_error(ErrorCode::kInvalidArgument, "the mesh has no texture");
}

std::string mesh_texture_label(const MeshData& mesh) {
  if (!mesh.texture_path.empty()) return mesh.texture_path;
  if (mesh.texture_bytes.empty()) return "none";
  std::string s = mesh.texture_name.empty() ? "image" : mesh.texture_name;
  s += " (embedded";
  if (!mesh.texture_mime_type.empty()) s += " " + mesh.texture_mime_type;
  s += ", " + std::to_string(mesh.texture_bytes.size()) + " bytes)";
  return s;
}

}  // namespace texbake
