// The writers of texbake/texbake.h, over mesh_io/write_mesh.h and
// mesh_io/write_textured.h (both atomic).
#include <string>

#include "mesh_io/file_name.h"
#include "mesh_io/write_mesh.h"
#include "mesh_io/write_textured.h"
#include "texbake/texbake.h"

namespace texbake {

namespace {

ImageBitDepth bit_depth(AtlasFormat format) {
  switch (format) {
    case AtlasFormat::kPng8:
      return ImageBitDepth::k8;
    case AtlasFormat::kPng16:
      return ImageBitDepth::k16;
    case AtlasFormat::kExr:
      return ImageBitDepth::kFloat;
  }
  return ImageBitDepth::k8;
}

}  // namespace

Status validate_write(const std::filesystem::path& path, const WriteOptions& options, bool atlas) {
  const std::string ext = lower_extension(path);
  if (atlas) {
    if (ext != ".obj" && ext != ".glb") {
      return make_error(ErrorCode::kUnsupported, path.string() + ": unknown atlas format '" + ext +
                                                     "' (an atlas is written as .obj or .glb)");
    }
    if (options.format == AtlasFormat::kExr && ext == ".glb") {
      return make_error(ErrorCode::kUnsupported, "--format exr cannot be embedded in " +
                                                     path.string() +
                                                     " (glTF embeds PNG: use png8 or png16)");
    }
    return ok_status();
  }
  if (ext != ".ply" && ext != ".obj" && ext != ".glb") {
    return make_error(ErrorCode::kUnsupported,
                      path.string() + ": unknown output format '" + ext +
                          "' (vertex colours are written as .ply, .obj or .glb)");
  }
  if (options.ascii && ext != ".ply") {
    return make_error(ErrorCode::kInvalidArgument, "--ascii applies to .ply output only");
  }
  return ok_status();
}

Status write_vertex_colors(const std::filesystem::path& path, const MeshData& mesh,
                           std::span<const Rgba> colors, const WriteOptions& options) {
  if (Status s = validate_write(path, options, /*atlas=*/false); !s) return s;
  if (colors.size() != mesh.vertex_count()) {
    return make_error(ErrorCode::kInvalidArgument,
                      "cannot write " + path.string() + ": " + std::to_string(colors.size()) +
                          " colours for " + std::to_string(mesh.vertex_count()) + " vertices");
  }
  if (lower_extension(path) == ".glb")
    return write_vertex_color_glb(path, mesh, colors, options.up);
  MeshWriteOptions wo;
  wo.ascii = options.ascii;
  wo.vertex_colors = colors;
  return write_mesh(path, mesh, wo);
}

Status write_atlas(const std::filesystem::path& path, const Atlas& atlas,
                   const WriteOptions& options) {
  if (Status s = validate_write(path, options, /*atlas=*/true); !s) return s;
  TexturedWriteOptions wo;
  wo.bit_depth = bit_depth(options.format);
  wo.repeat_u = atlas.repeat_u;
  wo.blend = atlas.blend;
  wo.up = options.up;
  return write_textured_mesh(path, atlas.mesh, atlas.image.view(), wo);
}

std::vector<std::filesystem::path> atlas_files(const std::filesystem::path& path,
                                               const WriteOptions& options) {
  if (lower_extension(path) != ".obj") return {path};
  return {path, std::filesystem::path(path).replace_extension(".mtl"),
          atlas_path_for(path, bit_depth(options.format))};
}

}  // namespace texbake
