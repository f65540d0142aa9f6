// The mesh as plain arrays (struct of arrays), converted once from the file
// readers. Hot loops use these arrays directly, never OpenMesh handles.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace texbake {

struct Float3 {
  float x = 0, y = 0, z = 0;
};
struct Float2 {
  float u = 0, v = 0;
};

// Faces are kept as the input's polygons (CSR: face f has corners
// face_offsets[f] .. face_offsets[f+1]-1), so per-vertex outputs keep the
// input's vertices and faces (SPEC section 8). `triangles` is their
// triangulation without degenerate triangles: the input of ray tracing and
// atlas charts.
struct MeshData {
  std::vector<Float3> positions;  // one per vertex, in the input's order

  std::vector<uint32_t> face_offsets;   // size = face count + 1 (empty mesh: {0})
  std::vector<uint32_t> face_vertices;  // vertex index per corner

  // Optional per-corner attributes, parallel to face_vertices (empty if absent).
  std::vector<Float2> uvs;              // UV table (OBJ vt)
  std::vector<uint32_t> corner_uv;      // index into uvs per corner
  std::vector<Float3> normals;          // normal table (OBJ vn)
  std::vector<uint32_t> corner_normal;  // index into normals per corner

  // Optional per-vertex colours, RGBA in [0, 1] (empty if absent).
  std::vector<std::array<float, 4>> vertex_colors;

  // Triangulation of the faces, degenerate triangles removed.
  std::vector<std::array<uint32_t, 3>> triangles;         // vertex indices
  std::vector<std::array<uint32_t, 3>> triangle_corners;  // corner indices (into face_vertices)
  std::vector<uint32_t> triangle_face;                    // source face per triangle

  // Texture of the material the mesh references (OBJ map_Kd), if any: a path
  // resolved relative to the mesh file.
  std::string texture_path;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t face_count() const { return face_offsets.empty() ? 0 : face_offsets.size() - 1; }
  bool has_uvs() const { return !corner_uv.empty(); }
  bool has_vertex_colors() const { return !vertex_colors.empty(); }
};

// Problems found while loading that are reported, not fatal (SPEC section 8).
struct MeshIssues {
  std::size_t degenerate_triangles = 0;  // zero-area triangles skipped
  std::size_t unreferenced_vertices = 0;
  std::size_t non_manifold_edges = 0;  // edges shared by more than two faces
};

}  // namespace texbake
