// Vertices at the same position (SPEC section 7): formats that store one
// attribute set per vertex (glTF, and PLY or OBJ files written from them)
// split a vertex where its UV or normal differs, so a seam leaves two or
// more vertices at one point and the triangles on either side share no
// vertex. Wherever connectivity matters (the occlusion fill, smooth
// normals), the users weld them by position through this table; outputs
// keep the split vertices.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh_io/mesh_data.h"

namespace texbake {

// Per vertex, the smallest index of a vertex at exactly the same position
// (bit for bit, -0 and +0 equal), itself if none is smaller; an empty table
// when no two vertices share a position (the usual mesh: callers then use
// the vertices as they are, with the same results as before welding
// existed). One pass in vertex order through an open-addressing hash table
// of 6 to 12 bytes per vertex, freed on return.
std::vector<uint32_t> weld_by_position(const MeshData& mesh);

}  // namespace texbake
