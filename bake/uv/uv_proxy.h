// UV layouts that come without UV generation: `--uv proxy` (the proxy's own
// (u, v), cut at its seam) and the checks of `--uv mesh` (SPEC section 4).
#pragma once

#include <cstddef>

#include "mapping/error.h"
#include "mapping/proxy.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct ProxyUvStats {
  std::size_t cut_triangles = 0;     // triangles split along the u = 0/1 seam
  std::size_t added_vertices = 0;    // vertices created on cut edges
  std::size_t singular_corners = 0;  // corners at a pole, apex or disk centre (or where the
                                     // mapping is undefined): u (and v if undefined) taken from
                                     // the triangle's other corners
  std::size_t wide_triangles = 0;    // triangles still spanning more than half the u range
                                     // (they contain a pole in their interior)
  bool rescaled = false;  // some (u, v) left [0, 1] (mesh beyond the proxy's domain): the
                          // layout was scaled affinely into [0, 1]
};

struct ProxyUvLayout {
  MeshData mesh;  // the cut mesh: see proxy_uv_layout
  ProxyUvStats stats;
};

// --uv proxy: per-corner UVs from proxy inverse_map of each vertex.
//
// Periodic proxies (sphere, cylinder, cone, disk, where u wraps):
//  - each triangle's corners are unwrapped to the shortest u interval (the
//    largest circular gap between them is left outside);
//  - a singular corner (within 1e-3 of the triangle's longest edge from the
//    proxy's axis: a pole, the apex, the disk centre; or MapStatus::kUndefined)
//    takes the mean unwrapped u of the triangle's regular corners, so no
//    triangle fans across the whole u range;
//  - a triangle whose unwrapped u passes 1 is cut along u = 1 into pieces
//    that lie in [0, 1] (the part beyond 1 is shifted by -1). Cut points are
//    new vertices (shared by the two triangles of a cut edge), positions
//    interpolated linearly along the edge.
// Quad and plane have no seam. If any (u, v) falls outside [0, 1] (the mesh
// extends beyond the proxy's domain) the layout's bounding box is mapped
// affinely onto [0, 1] per axis (never u of periodic proxies), so every
// triangle keeps texels of its own.
//
// The output mesh: the input's positions followed by the added vertices;
// faces = its triangles (polygons are replaced by their triangulation, so
// the OBJ writer can write it as it is); per-corner uvs/corner_uv and, if
// the input had them, normals/corner_normal (interpolated at cut points);
// no vertex colours, no texture path. Deterministic (serial in triangle
// order after a parallel inverse mapping).
Expected<ProxyUvLayout> proxy_uv_layout(const MeshData& mesh, const Proxy& proxy);

// --uv mesh checks (warnings, not errors).
struct MeshUvCheck {
  std::size_t corners_outside = 0;  // per-corner UVs with u or v outside [0, 1]
  std::size_t overlap_texels = 0;   // texels of a size x size raster whose centre lies strictly
                                    // inside two or more UV triangles
  std::size_t covered_texels = 0;   // texels whose centre lies strictly inside at least one
};
// Precondition: mesh.has_uvs(); size >= 1.
MeshUvCheck check_mesh_uvs(const MeshData& mesh, int size);

}  // namespace texbake
