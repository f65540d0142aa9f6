// Writing meshes (SPEC section 7): PLY (binary little-endian by default, ASCII
// on request) and OBJ, always through write_atomically (no partial file under
// the target's name, ever).
//
// Contract:
// - The input's vertices are written in order and its faces as its polygons
//   (face_offsets/face_vertices), not the triangulation: per-vertex outputs
//   keep the input's vertices and faces (SPEC section 8).
// - Colours are float RGBA in [0, 1] (values outside are clamped, NaN -> 0).
//   PLY stores them as uchar red/green/blue, plus alpha when any vertex is
//   not opaque, each rounded to the nearest 8-bit value (round(c * 255)).
//   OBJ stores `v x y z r g b` with the 8-bit-rounded value / 255 (so PLY and
//   OBJ outputs hold the same colours); OBJ has no alpha.
// - PLY: `element vertex` (float x y z [uchar red green blue [alpha]]),
//   `element face` (list uchar int vertex_indices; list int int when a face
//   has more than 255 corners). Normals and UVs are not written to PLY.
// - OBJ: `v` (with colours), `vt` and `vn` when the mesh has them, and `f`
//   with v/vt/vn indices; with `obj_material_texture` set, also an MTL file
//   beside it (same stem, .mtl) whose map_Kd names that texture (and map_d
//   with `obj_material_alpha`).
// - The format comes from the extension (.ply, .obj; case-insensitive).
//   Any other extension is kUnsupported; .glb included, whose writers are
//   write_vertex_color_glb and write_textured_mesh (mesh_io/write_textured.h).
#pragma once

#include <array>
#include <filesystem>
#include <span>
#include <string>

#include "mapping/error.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

class AtomicFileSet;

struct MeshWriteOptions {
  bool ascii = false;  // PLY only: ASCII instead of binary little-endian
  // Colours to write instead of mesh.vertex_colors (one per vertex); empty:
  // the mesh's own colours, if any.
  std::span<const std::array<float, 4>> vertex_colors;
  // OBJ only: texture file name written as map_Kd in an MTL beside the OBJ
  // (relative to the OBJ's folder). Empty: no MTL.
  std::string obj_material_texture;
  // OBJ only: the texture's alpha is the surface's coverage (an atlas with
  // alpha, layers over a transparent base): the MTL names it as map_d too.
  bool obj_material_alpha = false;
  // Stage the file(s) (an OBJ and its MTL) into this set (mesh_io/
  // atomic_file.h; the caller commits it) instead of writing them at once.
  AtomicFileSet* file_set = nullptr;
};

Status write_mesh(const std::filesystem::path& path, const MeshData& mesh,
                  const MeshWriteOptions& options = {});

// round(clamp(c, 0, 1) * 255), NaN -> 0: the one float -> 8-bit rule.
uint8_t colour_to_byte(float c);

}  // namespace texbake
