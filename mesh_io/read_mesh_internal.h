// Internals of read_mesh shared by its pieces (not a public API; read_mesh.h
// is):
//   read_mesh.cpp      the dispatcher (by extension), the checks every format
//                      shares, triangulation and issue counting;
//   read_obj.cpp       OBJ (checked here, parsed by OpenMesh);
//   read_off.cpp       OFF (ASCII parsed here, binary checked here and parsed
//                      by OpenMesh);
//   read_ply.cpp       PLY (parsed here);
//   read_stl.cpp       STL (ASCII parsed here, binary checked here and parsed
//                      by OpenMesh);
//   read_gltf.cpp      glTF 2.0, .glb and .gltf (checked here, parsed by
//                      tinygltf, its accessors read here);
//   read_openmesh.cpp  the OpenMesh adapter: an importer into MeshData's
//                      plain arrays;
//   text_scan.h        the shared tokenizer, number parsing, line counting.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mapping/error.h"
#include "mesh_io/byte_order.h"
#include "mesh_io/mesh_data.h"

namespace texbake::read_detail {

// Work limit for small hostile files (issue #7: no small input may run for
// minutes). A polygon may have at most kMaxFaceCorners corners: OpenMesh's
// OBJ reader removes repeated corners in O(n^2) per face (a 2 MB line of
// "1 1 1 ..." would take minutes). Real meshes' largest polygons (caps of
// scanned or CAD cylinders) have hundreds to a few thousand corners.
inline constexpr std::size_t kMaxFaceCorners = 16384;

// "has N corners; texbake reads polygons of at most 16384".
std::string too_many_corners(std::size_t n);

// The little-endian uint32 at `p` (binary OFF and STL).
inline uint32_t load_le32(const char* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  if constexpr (std::endian::native == std::endian::big) v = byte_swap(v);
  return v;
}

// kParse with the message "PATH: what".
Error parse_error(const std::filesystem::path& path, const std::string& what);

// The per-format readers. `bytes` is the whole file at `path` (not empty);
// the reader parses or checks it and, where OpenMesh parses, lets OpenMesh
// read `path` again. On success the mesh's positions, faces and attributes
// are filled (not yet validated, not triangulated); errors are kParse naming
// `path` and, where known, the line or element.
Expected<MeshData> read_obj(const std::filesystem::path& path, std::string_view bytes);
Expected<MeshData> read_off(const std::filesystem::path& path, std::string_view bytes);
Expected<MeshData> read_ply(const std::filesystem::path& path, std::string_view bytes);
Expected<MeshData> read_stl(const std::filesystem::path& path, std::string_view bytes);
// .glb or .gltf by the extension of `path`; adds to *other_material_primitives
// the triangle primitives whose material is not the first one's.
Expected<MeshData> read_gltf(const std::filesystem::path& path, std::string_view bytes,
                             std::size_t* other_material_primitives);

// ---------------------------------------------------------------------------
// The OpenMesh adapter (read_openmesh.cpp).

// Where OpenMesh's normals go: per corner (OBJ's vn, reported while a face is
// parsed) or per vertex (OFF, PLY; the corner table is then the vertex index).
enum class NormalsAt { kVertex, kCorner };

// What OpenMesh's reader reported through the importer.
struct OpenMeshRead {
  MeshData mesh;  // per-corner / per-vertex arrays completed to full length
  // The first face with a negative vertex index (stored as UINT32_MAX), if any.
  std::optional<std::size_t> negative_index_face;
  // OBJ: the materials' textures (id, map_Kd name) and the texture id of
  // the first face that has one (0 if none).
  std::vector<std::pair<int, std::string>> textures;
  int first_face_texindex = 0;
};

// Reads `path` with OpenMesh's reader for its extension (one read at a time
// in the process; OpenMesh's log output off). kParse "PATH: OpenMesh cannot
// parse it as EXT (malformed file)" if OpenMesh's reader fails. The caller
// must have checked the file: OpenMesh's readers trust their input.
Expected<OpenMeshRead> read_with_openmesh(const std::filesystem::path& path, NormalsAt normals);

// The mesh of `read`, or kParse "PATH: face F has a negative vertex index".
Expected<MeshData> mesh_without_negative_index(const std::filesystem::path& path,
                                               OpenMeshRead&& read);

}  // namespace texbake::read_detail
