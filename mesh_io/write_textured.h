// Textured and glTF mesh outputs (SPEC section 7, issue #4): OBJ + MTL + atlas
// image, GLB with an embedded atlas, and GLB with per-vertex colours.
//
// All files are written atomically (mesh_io/atomic_file.h). A textured OBJ
// is three files staged as one AtomicFileSet: image, MTL and OBJ are written
// to temporaries first and renamed together only when all three are
// complete, so a failure or an interruption leaves the previous set as it
// was (never an OBJ that names a missing or newer texture).
//
// glTF conventions (glTF 2.0 specification, section 3.7 and 5.x):
//  - TEXCOORD_0 has its origin at the image's top-left: t = 1 - v.
//  - The atlas (baseColorTexture) is stored as the image's sRGB values.
//  - COLOR_0 is linear: each RGB value goes through srgb_to_linear
//    (mapping/sample.h), alpha is kept; stored as float VEC4.
//  - GLB geometry is triangles (the faces' fan triangulation for vertex
//    colours, MeshData::triangles for atlases); vertices are split where a
//    vertex has several UVs (one glTF vertex per (vertex, UV) pair).
#pragma once

#include <filesystem>
#include <span>

#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// PNG atlases are written at zlib level 4 instead of OIIO's 6: measured with
// bench/atlas_bench.cpp (BM_AtlasPngLevel, padded bunny atlas, one thread):
// 2048: 476 -> 240 ms CPU for 2.47 -> 2.63 MB; 4096: 1674 -> 864 ms for
// 7.0 -> 7.5 MB. Levels 1-3 save little more time for 13-26 % larger files.
inline constexpr int kAtlasPngCompression = 4;

struct TexturedWriteOptions {
  // Atlas encoding: k8 / k16 -> PNG, kFloat -> EXR (OBJ only: a GLB embeds
  // PNG, so kFloat there is kUnsupported).
  ImageBitDepth bit_depth = ImageBitDepth::k8;
  // GLB sampler: REPEAT in u (wrapS) when the layout is periodic in u
  // (--uv proxy on sphere, cylinder, cone, disk), else CLAMP_TO_EDGE.
  bool repeat_u = false;
  // zlib level of the PNG atlas (lossless at any level; see
  // kAtlasPngCompression).
  int png_compression = kAtlasPngCompression;
};

// The atlas file written beside a textured OBJ: same folder and stem,
// extension .png (8/16-bit) or .exr.
std::filesystem::path atlas_path_for(const std::filesystem::path& obj_path, ImageBitDepth depth);

// Writes a mesh with per-corner UVs (mesh.uvs / corner_uv, parallel to
// face_vertices) and its atlas. By extension: .obj (+ .mtl + atlas beside
// it, map_Kd relative) or .glb (atlas embedded as PNG). Errors: kUnsupported
// for other extensions (.ply has no standard texture), kInvalidArgument if
// the mesh has no UVs, kIo naming the file that could not be written.
Status write_textured_mesh(const std::filesystem::path& path, const MeshData& mesh,
                           const ImageView& atlas, const TexturedWriteOptions& options = {});

// A .glb with COLOR_0 from `colors` (one RGBA per vertex, sRGB-encoded values
// in [0, 1], as the bake produces them). Vertices keep the input's order.
Status write_vertex_color_glb(const std::filesystem::path& path, const MeshData& mesh,
                              std::span<const Rgba> colors);

}  // namespace texbake
