// The mesh as plain arrays (struct of arrays), converted once from the file
// readers. Hot loops use these arrays directly, never OpenMesh handles.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
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

  // Optional per-vertex colours, RGBA in [0, 1] (empty if absent), RGB
  // sRGB-encoded as PLY and OBJ store them and as the bake produces them
  // (a glTF COLOR_0, linear light, is converted on reading: linear_to_srgb
  // of mapping/sample.h, the inverse of what write_vertex_color_glb does).
  std::vector<std::array<float, 4>> vertex_colors;

  // Triangulation of the faces, degenerate triangles removed.
  std::vector<std::array<uint32_t, 3>> triangles;         // vertex indices
  std::vector<std::array<uint32_t, 3>> triangle_corners;  // corner indices (into face_vertices)
  std::vector<uint32_t> triangle_face;                    // source face per triangle

  // Texture of the material the mesh references, if any: OBJ map_Kd; glTF
  // the first triangle primitive's pbrMetallicRoughness.baseColorTexture
  // (see read_mesh.h for primitives with other materials). At most one of
  // the two forms is set; read_mesh_texture (mesh_io/mesh_texture.h) decodes
  // either:
  //  - texture_path: an image file, resolved relative to the mesh file (OBJ
  //    map_Kd; a .gltf image's external URI, percent-decoded);
  //  - texture_bytes: an image embedded in the mesh file (a .glb or .gltf
  //    image in a bufferView or a data: URI), the encoded file as stored
  //    (PNG, JPEG, ...), with its glTF mimeType in texture_mime_type (may be
  //    empty: the bytes then tell the format) and texture_name naming it in
  //    messages ("MODEL.glb: image 0").
  std::string texture_path;
  std::vector<unsigned char> texture_bytes;
  std::string texture_mime_type;
  std::string texture_name;
  // glTF: a baseColorTexture is sRGB-encoded by definition (glTF 2.0,
  // section 3.9.2), whatever colour chunks its file has; read_mesh_texture
  // then reads it as sRGB unless told otherwise. false for OBJ.
  bool texture_is_srgb = false;
  // glTF: the material's pbrMetallicRoughness.baseColorFactor as stored
  // (linear RGBA; glTF multiplies the texture and COLOR_0 by it). Kept, not
  // applied: vertex_colors and the texture are the file's own. Absent for
  // other formats and for primitives without a material.
  std::optional<std::array<float, 4>> base_color_factor;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t face_count() const { return face_offsets.empty() ? 0 : face_offsets.size() - 1; }
  bool has_uvs() const { return !corner_uv.empty(); }
  bool has_vertex_colors() const { return !vertex_colors.empty(); }
  bool has_texture() const { return !texture_path.empty() || !texture_bytes.empty(); }
};

// Problems found while loading that are reported, not fatal (SPEC section 8).
struct MeshIssues {
  std::size_t degenerate_triangles = 0;  // zero-area triangles skipped
  std::size_t unreferenced_vertices = 0;
  std::size_t non_manifold_edges = 0;  // edges shared by more than two faces
  // glTF: triangle primitives whose material is not the first primitive's
  // (the mesh's texture and base_color_factor are the first one's; their
  // UVs are read all the same). Callers that use the texture warn.
  std::size_t other_material_primitives = 0;
};

}  // namespace texbake
