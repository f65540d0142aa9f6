// Smooth per-vertex normals of a MeshData, for outputs and previews that
// shade a mesh without normals of its own (texbake render, the GLB writers).
//
// Written here rather than taken from OpenMesh (update_vertex_normals): that
// needs a halfedge mesh, which cannot hold the non-manifold faces MeshData
// keeps (mesh_io/read_mesh.h).
#pragma once

#include <vector>

#include "mesh_io/mesh_data.h"

namespace texbake {

// One normal per vertex: the sum of the unnormalised cross products
// (b - a) x (c - a) of mesh.triangles around it (area-weighted, the usual
// smooth-shading normal), normalised; accumulated in double, so the result
// does not depend on anything but the triangles' order. Vertices at one
// position (split at a UV or normal seam) are welded (mesh_io/weld.h): each
// gets the normal of all the triangles around the point. A vertex in no
// triangle (unreferenced, or only in degenerate ones), or whose sum is zero,
// gets (0, 0, 0). Outward for a closed mesh whose triangles are counter-
// clockwise seen from outside.
std::vector<Float3> smooth_vertex_normals(const MeshData& mesh);

}  // namespace texbake
