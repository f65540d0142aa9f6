// Reading meshes (SPEC sections 7 and 8): OBJ, PLY (ASCII, binary little and
// big endian), OFF and STL (ASCII and binary) into the plain arrays of
// MeshData, converted once.
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
// .off, .stl, case-insensitive).
Expected<LoadedMesh> read_mesh(const std::filesystem::path& path);

// Fills mesh.triangles/triangle_corners/triangle_face from the faces
// (positions and faces must be valid: indices < vertex count) and returns the
// issues found (degenerate triangles, unreferenced vertices, non-manifold
// edges). read_mesh calls it; it is public for meshes built in memory.
MeshIssues triangulate_faces(MeshData& mesh);

}  // namespace texbake
