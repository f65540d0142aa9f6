// Reading meshes (SPEC sections 7 and 8): OBJ, PLY (ASCII, binary little and
// big endian), OFF, STL (ASCII and binary) and glTF 2.0 (.glb, .gltf) into
// the plain arrays of MeshData, converted once.
//
// Contract:
// - Vertices keep the file's order and count, unreferenced ones included;
//   except STL, which has no shared vertices: corners at equal positions
//   become one vertex (in order of first appearance) and triangles that then
//   repeat a vertex are dropped.
// - Faces keep the file's polygons (CSR), non-manifold ones included: an edge
//   shared by three faces keeps all three (OpenMesh's halfedge meshes would
//   drop them, so the readers fill MeshData through a custom importer).
// - `triangles` is the triangulation of the faces (fan for convex polygons,
//   ear clipping otherwise) without zero-area triangles.
// - Errors (kIo: missing, unreadable, a folder, not a regular file (a FIFO,
//   a device; checked before anything opens it, see regular_file.h);
//   kParse: unknown extension,
//   truncated or lying header, NaN/inf coordinates, out-of-range or negative
//   indices, no faces) name the file and, where known, the line or element.
// - Work limits (issue #7; a small hostile file must not run for minutes
//   or allocate gigabytes): declared counts are checked against the file's
//   size before allocating; a polygon has at most 16384 corners (else
//   kParse); non-convex polygons above 512 corners are fanned, not ear
//   clipped; an OBJ `mtllib` naming something other than a regular file
//   (a folder, a device) or one above kMaxTextFileBytes (16 MiB) is kParse.
// - glTF (mesh_io/read_gltf.cpp has the details): the TRIANGLES primitives
//   (indexed or not) of the default scene's nodes (else scene 0's; with no
//   scene, every mesh once), positions and normals in the scene's frame (node
//   transforms composed down the hierarchy; a mirroring transform flips the
//   winding back). Vertices are the glTF vertices, primitive after
//   primitive (glTF splits a vertex where its UV or normal differs, so the
//   per-corner tables index them one to one; the fill and smooth normals
//   weld them by position, mesh_io/weld.h); faces are the triangles.
//   NORMAL per corner; TEXCOORD_n of the base colour texture (n its
//   texCoord, else 0) as per-corner UVs with v = 1 - t (glTF's t runs down
//   from the image's top, texbake's v up); COLOR_0 (float or normalised
//   integers, VEC3 or VEC4; linear light) as sRGB-encoded vertex_colors
//   (linear_to_srgb). An attribute some primitives lack is filled there:
//   UV (0, 0), a zero normal (users then take the smooth one), white. The
//   texture is the first primitive's material's baseColorTexture: an
//   external image as texture_path, an embedded one (bufferView, data: URI)
//   as texture_bytes; its baseColorFactor in base_color_factor. Primitives
//   with another material are not an error (their geometry and UVs are
//   read): counted in MeshIssues::other_material_primitives for callers to
//   warn. Errors: kParse for a truncated or corrupt container, invalid
//   JSON, an accessor or buffer view outside its buffer, an index out of
//   range, a mode other than TRIANGLES (naming the primitive), a required
//   extension texbake cannot read (KHR_draco_mesh_compression,
//   EXT_meshopt_compression, KHR_texture_transform, ...), a value tinygltf
//   reports as malformed (a baseColorFactor of 3 numbers), a buffer or
//   image URI outside the glTF's folder (absolute, another scheme than
//   data:, or leaving it through ".." or a link); kIo for a missing
//   or unreadable external buffer or base colour image. Instancing is
//   limited: at most 2^24 corners (and vertices) more than the buffers have
//   bytes.
// - Degenerate triangles, unreferenced vertices and non-manifold edges are
//   not errors: they are counted in MeshIssues.
// - Thread-safe (OpenMesh's reader singletons are serialised internally).
#pragma once

#include <filesystem>

#include "mapping/error.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct LoadedMesh {
  MeshData mesh;
  MeshIssues issues;
};

// Reads the mesh at `path`; the format comes from the extension (.obj, .ply,
// .off, .stl, .glb, .gltf, case-insensitive). The triangulation and the
// edge count run in parallel (oneTBB) in the caller's task arena; the
// results do not depend on the thread count (texbake/texbake.h has an
// overload taking RunOptions).
Expected<LoadedMesh> read_mesh(const std::filesystem::path& path);

// Fills mesh.triangles/triangle_corners/triangle_face from the faces
// (positions and faces must be valid: indices < vertex count) and returns the
// issues found (degenerate triangles, unreferenced vertices, non-manifold
// edges), in parallel like read_mesh. read_mesh calls it; it is public for
// meshes built in memory.
MeshIssues triangulate_faces(MeshData& mesh);

}  // namespace texbake
