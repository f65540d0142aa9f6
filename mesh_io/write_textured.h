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
//  - The atlas (baseColorTexture) is stored as sRGB values (converted from
//    the atlas view's color_space if it is linear), PNG without colour
//    chunks (glTF fixes the space by the texture's use).
//  - A textured OBJ's atlas is encoded for its format (issue #11): PNG
//    sRGB-encoded and tagged "sRGB", EXR linear light and tagged "Linear".
//  - COLOR_0 is linear: each RGB value goes through srgb_to_linear
//    (mapping/sample.h), alpha is kept; stored as float VEC4.
//  - GLB geometry is triangles (the faces' fan triangulation for vertex
//    colours, MeshData::triangles for atlases); vertices are split where a
//    vertex has several UVs (one glTF vertex per (vertex, UV) pair).
//  - glTF is +Y up (section 3.4): the vertex data are the mesh's own
//    (positions unchanged, so PLY/OBJ and GLB outputs agree) and the one
//    node's `matrix` is glb_up_matrix(up), the rotation from the mesh's up
//    direction to +Y (no matrix when up is +Y).
//  - Every GLB has NORMAL (unit VEC3 float): the input's normals when the
//    mesh has one per corner (vertices are then split per (vertex[, UV],
//    normal value)), else smooth_vertex_normals (mesh_io/vertex_normals.h);
//    a zero or non-finite input normal takes the smooth one instead, and a
//    vertex with neither (in degenerate faces only, or in none) takes `up`.
#pragma once

#include <array>
#include <filesystem>
#include <span>

#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/vec.h"
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
  // The atlas's alpha is the surface's coverage: GLB material alphaMode
  // BLEND (else OPAQUE), OBJ map_d naming the atlas beside map_Kd (else
  // none). Set it when covered texels are not opaque (layers over a
  // transparent base); the atlas's background alpha alone does not call
  // for it.
  bool blend = false;
  // zlib level of the PNG atlas (lossless at any level; see
  // kAtlasPngCompression).
  int png_compression = kAtlasPngCompression;
  // GLB only: the mesh's up direction (non-zero, need not be unit), turned
  // to glTF's +Y by the node matrix (glb_up_matrix).
  Vec3 up{0, 0, 1};
};

// The glTF node matrix, column-major as glTF stores it, for a mesh whose up
// direction is `up` (non-zero, need not be unit): the smallest rotation
// taking up to +Y (for -Y: 180 degrees about X). For the axes, (x, y, z) ->
// +Z up: (x, z, -y) (-90 degrees about X, as Blender's glTF exporter);
// -Z: (x, -z, y); +X: (-y, x, z); -X: (y, -x, z); -Y: (x, -y, -z); +Y: the
// identity. Exact (entries 0 and +-1) for these six.
std::array<double, 16> glb_up_matrix(Vec3 up);

// The atlas file written beside a textured OBJ: same folder and stem,
// extension .png (8/16-bit) or .exr.
std::filesystem::path atlas_path_for(const std::filesystem::path& obj_path, ImageBitDepth depth);

// Writes a mesh with per-corner UVs (mesh.uvs / corner_uv, parallel to
// face_vertices) and its atlas. By extension: .obj (+ .mtl + atlas beside
// it, map_Kd relative) or .glb (atlas embedded as PNG). Errors: kUnsupported
// for other extensions (.ply has no standard texture), kInvalidArgument if
// the mesh has no UVs (or, GLB, options.up is zero or not finite), kIo
// naming the file that could not be written.
Status write_textured_mesh(const std::filesystem::path& path, const MeshData& mesh,
                           const ImageView& atlas, const TexturedWriteOptions& options = {});

// A .glb with COLOR_0 from `colors` (one RGBA per vertex, sRGB-encoded values
// in [0, 1], as the bake produces them) and the node matrix of `up` (see
// TexturedWriteOptions::up). The first vertex_count() glTF vertices are the
// input's, in order (unreferenced ones included), each with the normal of
// its first corner; where the input has another normal at a corner, a copy
// of the vertex (same position and colour) follows them. Errors:
// kInvalidArgument (no faces, `up` zero or not finite), kInternal (not one
// colour per vertex), kIo.
Status write_vertex_color_glb(const std::filesystem::path& path, const MeshData& mesh,
                              std::span<const Rgba> colors, Vec3 up = {0, 0, 1});

}  // namespace texbake
