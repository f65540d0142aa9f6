// The texture a mesh file names or embeds (MeshData::texture_path or
// texture_bytes, mesh_io/mesh_data.h), decoded as read_image decodes files.
#pragma once

#include "mapping/error.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// read_image(mesh.texture_path) or read_image_from_memory(mesh.texture_bytes)
// (image_io.h). When mesh.texture_is_srgb (glTF) and options ask for
// kAuto, the image is read as sRGB (glTF fixes a base colour texture's
// space). Errors: kInvalidArgument if the mesh has no texture; those of the
// image readers (naming the file, or "MODEL.glb: image N").
Expected<Image> read_mesh_texture(const MeshData& mesh, const ImageReadOptions& options = {});

// The texture as a short label for messages: the path, or
// "MODEL.glb: image 0 (embedded image/png, 1234 bytes)"; "none".
std::string mesh_texture_label(const MeshData& mesh);

}  // namespace texbake
